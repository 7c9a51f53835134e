# Scenario tests through the CLI: the doctest cases in tests/app/*.cpp call
# SOFTCUT_BIN, so test_app needs the executable built; and ctest runs every
# scenario's expectations and reference log via `softcut check`.
if(TARGET test_app)
  add_dependencies(test_app softcut)
endif()
# One test per shipped scenario, through the helper projects using softcut call.
include(${PROJECT_SOURCE_DIR}/scripts/SoftcutScenarioTests.cmake)
softcut_add_scenario_tests(${PROJECT_SOURCE_DIR}/scenarios PREFIX "scenario: " TIMEOUT 900)
add_test(NAME "app: softcut_add_scenario_tests() in a project that uses softcut"
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/app/scenario_tests_helper.sh $<TARGET_FILE:softcut> ${PROJECT_SOURCE_DIR})
set_tests_properties("app: softcut_add_scenario_tests() in a project that uses softcut" PROPERTIES
                     ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache")
# The operational CG in compute shaders (llvmpipe here) must reproduce the
# reference log recorded with the CPU solver, through cuts (issue: GPU CG).
add_test(NAME "app: softcut check --backend gpu through_cut"
         COMMAND softcut check --backend gpu ${PROJECT_SOURCE_DIR}/scenarios/through_cut.lua)
# Initial strains through cuts: every backend reproduces the log recorded with
# the default (hybrid, direct), the whole-mesh solve included.
foreach(backend monolithic cpu gpu)
  add_test(NAME "app: softcut check --backend ${backend} tensioned_incision"
           COMMAND softcut check --backend ${backend} ${PROJECT_SOURCE_DIR}/scenarios/tensioned_incision.lua)
endforeach()
# A probe's poke must not hinge on the solver's last digits: the flagship (a
# force-driven probe pressing a cut lip) reproduces its log, recorded with the
# default backend, on the CG and whole-mesh ones. With an equal load per
# contact point it did not (a point at the contact's rim came and went with
# rounding: 1 % of the displacement scale at frame 42).
foreach(backend monolithic cpu)
  add_test(NAME "app: softcut check --backend ${backend} incision_drag_poke"
           COMMAND softcut check --backend ${backend} ${PROJECT_SOURCE_DIR}/scenarios/incision_drag_poke.lua)
endforeach()
# softcut sweep as a Slurm array job on a private one-node cluster (root and
# Debian's slurmctld/slurmd/slurm-client needed: skipped, saying why, without).
add_test(NAME "app: softcut sweep on a one-node Slurm cluster"
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/app/sweep_slurm.sh $<TARGET_FILE:softcut> ${PROJECT_SOURCE_DIR})
set_tests_properties("app: softcut sweep on a one-node Slurm cluster" PROPERTIES
                     SKIP_RETURN_CODE 77 TIMEOUT 300 ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache")
