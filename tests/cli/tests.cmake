# Scenario tests through the CLI: the doctest cases in tests/cli/*.cpp call
# SOFTCUT_BIN, so test_cli needs the executable built; and ctest runs every
# scenario's expectations and reference log via `softcut check`.
if(TARGET test_cli)
  add_dependencies(test_cli softcut)
endif()
add_test(NAME "cli: softcut check scenarios" COMMAND softcut check ${PROJECT_SOURCE_DIR}/scenarios)
