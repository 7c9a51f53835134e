# Sanitizer instrumentation for every target, driven by one cache variable so a
# preset (CMakePresets.json: asan, fuzz) or a plain -D turns it on:
#   -DSOFTCUT_SANITIZE=address,undefined
# UBSan findings abort (no recovery) so ctest sees them as failures; frame
# pointers stay for readable ASan stacks. The optimisation level comes from the
# build type (the asan preset uses -O1).
#
# At -O1 clang leaves Eigen's small expression templates (a 3x3 block times a
# 3-vector segment: evaluators, Block constructors, coeff()) as calls, each
# with ASan checks on its by-value temporaries: the CG's operator and the
# per-tet loops ran 140x slower than the release build, and one property
# test took 190 s of CI's time. Forcing Eigen's EIGEN_STRONG_INLINE functions
# inline brings that test to 34 s (2026-11-29, clang 14) for 0-40 % more
# compile time per Eigen-heavy file; the sanitizers see the same code.
set(SOFTCUT_SANITIZE "" CACHE STRING "Sanitizers for every target, e.g. address,undefined (empty: none)")
if(SOFTCUT_SANITIZE)
  add_compile_options(-fsanitize=${SOFTCUT_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_definitions("EIGEN_STRONG_INLINE=inline __attribute__((always_inline))")
  add_link_options(-fsanitize=${SOFTCUT_SANITIZE})
endif()
