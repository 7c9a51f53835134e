# Sanitizer instrumentation for every target, driven by one cache variable so a
# preset (CMakePresets.json: asan, fuzz) or a plain -D turns it on:
#   -DSOFTCUT_SANITIZE=address,undefined
# UBSan findings abort (no recovery) so ctest sees them as failures; frame
# pointers stay for readable ASan stacks. The optimisation level comes from the
# build type (the asan preset uses -O1).
set(SOFTCUT_SANITIZE "" CACHE STRING "Sanitizers for every target, e.g. address,undefined (empty: none)")
if(SOFTCUT_SANITIZE)
  add_compile_options(-fsanitize=${SOFTCUT_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${SOFTCUT_SANITIZE})
endif()
