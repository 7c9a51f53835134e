# Scenario tests through the CLI: the doctest cases in tests/cli/*.cpp call
# SOFTCUT_BIN, so test_cli needs the executable built; and ctest runs every
# scenario's expectations and reference log via `softcut check`.
if(TARGET test_cli)
  add_dependencies(test_cli softcut)
endif()
add_test(NAME "cli: softcut check scenarios" COMMAND softcut check ${PROJECT_SOURCE_DIR}/scenarios)
# The operational CG in compute shaders (llvmpipe here) must reproduce the
# reference log recorded with the CPU solver, through cuts (issue: GPU CG).
add_test(NAME "cli: softcut check --backend gpu through_cut"
         COMMAND softcut check --backend gpu ${PROJECT_SOURCE_DIR}/scenarios/through_cut.lua)
