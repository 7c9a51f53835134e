# test_hardening (resource limits, fuzz regressions) links the whole engine and
# the Lua layer; tests/CMakeLists.txt links test_<stage> with softcut_<stage>,
# so softcut_hardening is that set. The fuzz regression cases read
# tests/fuzz/regressions/<target>/ at run time.
add_library(softcut_hardening INTERFACE)
target_link_libraries(softcut_hardening INTERFACE softcut_app pugixml::pugixml)
target_compile_definitions(test_hardening PRIVATE
  SOFTCUT_FUZZ_REGRESSIONS="${PROJECT_SOURCE_DIR}/tests/fuzz/regressions")
