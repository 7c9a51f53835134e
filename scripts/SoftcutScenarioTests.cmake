# softcut_add_scenario_tests(): one ctest test per softcut scenario, for
# projects that keep scenarios beside their code (and for softcut's own).
#
#   include(/path/to/softcut/scripts/SoftcutScenarioTests.cmake)
#   softcut_add_scenario_tests(scenarios               # folder, searched for *.lua (recursively)
#     SOFTCUT  /usr/local/bin/softcut                  # the program or a target (default: target softcut, else softcut on PATH)
#     PREFIX   "scenario: "                            # test name prefix (default "scenario: ")
#     ARGS     --backend cpu                           # more `softcut check` options for every test
#     TIMEOUT  600                                     # per test, s (default 1500)
#     LABELS   scenarios)                              # ctest labels (default "softcut")
#
# Each test runs `softcut check FILE ARGS`: the file's expectations and its
# reference log (FILE's stem + .ref.csv beside it; `softcut check --record`
# writes them). A helper module (a file that makes no scenario) is reported
# by ctest as skipped. New files are picked up at the next build
# (CONFIGURE_DEPENDS). Test names are PREFIX + the file's path below the
# folder without ".lua" ("scenario: liver/retraction").
function(softcut_add_scenario_tests dir)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "SOFTCUT;PREFIX;TIMEOUT" "ARGS;LABELS")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "softcut_add_scenario_tests: unknown arguments ${arg_UNPARSED_ARGUMENTS} "
                        "(SOFTCUT, PREFIX, TIMEOUT, ARGS, LABELS)")
  endif()
  get_filename_component(dir "${dir}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  if(NOT IS_DIRECTORY "${dir}")
    message(FATAL_ERROR "softcut_add_scenario_tests: ${dir} is not a folder")
  endif()
  if(NOT DEFINED arg_SOFTCUT)
    if(TARGET softcut)
      set(arg_SOFTCUT softcut)
    else()
      find_program(arg_SOFTCUT softcut REQUIRED)
    endif()
  endif()
  if(TARGET ${arg_SOFTCUT})
    set(program "$<TARGET_FILE:${arg_SOFTCUT}>")
  else()
    set(program "${arg_SOFTCUT}")
  endif()
  if(NOT DEFINED arg_PREFIX)
    set(arg_PREFIX "scenario: ")
  endif()
  if(NOT DEFINED arg_TIMEOUT)
    set(arg_TIMEOUT 1500)
  endif()
  if(NOT DEFINED arg_LABELS)
    set(arg_LABELS softcut)
  endif()
  file(GLOB_RECURSE files CONFIGURE_DEPENDS "${dir}/*.lua")
  if(NOT files)
    message(FATAL_ERROR "softcut_add_scenario_tests: no *.lua file under ${dir}")
  endif()
  list(SORT files)
  foreach(file IN LISTS files)
    file(RELATIVE_PATH rel "${dir}" "${file}")
    string(REGEX REPLACE "\\.lua$" "" rel "${rel}")
    set(name "${arg_PREFIX}${rel}")
    add_test(NAME "${name}" COMMAND "${program}" check "${file}" -j 1 ${arg_ARGS})
    # Outputs go to a temporary folder softcut removes; modules print "SKIP  FILE: ...".
    set_tests_properties("${name}" PROPERTIES SKIP_REGULAR_EXPRESSION "(^|\n)SKIP  " TIMEOUT ${arg_TIMEOUT}
                                              LABELS "${arg_LABELS}")
  endforeach()
endfunction()
