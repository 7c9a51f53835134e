# "k1=v1,k2=v2" -> name "k1=v1 k2=v2" (for test names) and sets "--set;k1=v1;--set;k2=v2".
function(softcut_case_sets case name_var sets_var)
  string(REPLACE "," " " name "${case}")
  string(REPLACE "," ";" kvs "${case}")
  set(sets "")
  foreach(kv IN LISTS kvs)
    list(APPEND sets --set ${kv})
  endforeach()
  set(${name_var} "${name}" PARENT_SCOPE)
  set(${sets_var} "${sets}" PARENT_SCOPE)
endfunction()

# A scenario that cuts a piece free (docs/cutting.md "Pieces cut free") through
# the CLI: the run must complete, its expectations hold and its log match the
# reference (tests/cut/cut_free.ref.csv, `softcut check --record` to renew).
add_test(NAME "cut: softcut check a scenario that cuts a piece free"
         COMMAND softcut check ${PROJECT_SOURCE_DIR}/tests/cut/cut_free.lua)

# Issue #16 item 1: a cut through tissue that moves while the blade passes
# (tests/cut/moving_tissue.lua checks two anchored pieces at the end). Before
# the fix every moving or loaded case ended in one piece.
foreach(case "hz=3" "hz=0,amp=0" "hz=0,amp=0,fz=-1e-30" "hz=3,fps=80" "hz=8" "hz=3,path=1")
  softcut_case_sets("${case}" name sets)
  add_test(NAME "cut: a blade cuts through moving tissue (${name})"
           COMMAND softcut run ${PROJECT_SOURCE_DIR}/tests/cut/moving_tissue.lua --no-render --quiet
                   --out ${CMAKE_BINARY_DIR}/test-out/moving_tissue/${name} ${sets})
  set_tests_properties("cut: a blade cuts through moving tissue (${name})" PROPERTIES
                       ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache")
endforeach()

# Issue #16 item 4: a blade that reaches only tissue it may not cut (outside
# the operational region, or along the interface) warns with blade and time.
foreach(case "x0=0.08,x1=0.09" "x0=0.065,x1=0.065" "x0=0.06,x1=0.06")
  softcut_case_sets("${case}" name sets)
  set(test "cut: a blade over uncuttable tissue warns (${name})")
  add_test(NAME "${test}"
           COMMAND softcut run ${PROJECT_SOURCE_DIR}/tests/cut/blocked_blade.lua --no-render
                   --out ${CMAKE_BINARY_DIR}/test-out/blocked_blade/${name} ${sets})
  set_tests_properties("${test}" PROPERTIES
    ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache"
    PASS_REGULAR_EXPRESSION "frame [0-9]+ \\(t = [0-9.]+ s\\), scalpel 'blade': the blade \\(centre [^)]*\\) reaches [0-9]+ tet\\(s\\) outside the operational region.*\\[blade_outside_operational\\]")
endforeach()

# Issue #40 item 9: a blade 1 mm inside the operational region (the snap
# distance is 1.5 mm on its 1 cm cells) snaps onto the locked interface nodes
# and opens nothing; it stopped short silently, now it says why, once.
foreach(case "x0=0.059,x1=0.059" "x0=0.021,x1=0.021")
  softcut_case_sets("${case}" name sets)
  set(test "cut: a blade within the snap distance of the interface warns (${name})")
  add_test(NAME "${test}"
           COMMAND softcut run ${PROJECT_SOURCE_DIR}/tests/cut/blocked_blade.lua --no-render
                   --out ${CMAKE_BINARY_DIR}/test-out/blocked_blade/${name} ${sets})
  set_tests_properties("${test}" PROPERTIES
    ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache"
    PASS_REGULAR_EXPRESSION "scalpel 'blade': the blade \\(centre [^)]*\\) passes within the snap distance \\(1.5 mm here\\) of [0-9]+ locked node\\(s\\) on the operational region's boundary.*the cut stops short of the interface.*\\[cut_stopped_short\\]"
    FAIL_REGULAR_EXPRESSION "passes within the snap distance[^\n]*\n[^\n]*passes within the snap distance")
endforeach()

# Issue #40 item 9: parallel strokes closer than the snap distance free a
# strip no blade closed (a known limit, docs/cutting.md); the warning names
# the strokes that bound it and says why.
add_test(NAME "cut: a piece freed between parallel strokes names them"
         COMMAND softcut run ${PROJECT_SOURCE_DIR}/tests/cut/parallel_strokes.lua --no-render
                 --out ${CMAKE_BINARY_DIR}/test-out/parallel_strokes)
set_tests_properties("cut: a piece freed between parallel strokes names them" PROPERTIES
  ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache"
  PASS_REGULAR_EXPRESSION "piece of [0-9]+ tets / [0-9]+ nodes \\(smallest node id [0-9]+\\) cut free at frame [0-9]+ by the cuts of the strokes begun at t = [0-9.]+ s \\('blade'\\), t = [0-9.]+ s \\('blade'\\)[^;]* \\(strokes closer together than the snap distance merge into one cut on this mesh.*\\[piece_cut_free\\]")

# Issue #16 item 5: a force-driven blade pressed in from the surface cuts
# through, however its force ramps and however fast it moves; a path starting
# inside the tissue, or a blade that sinks in below cut_pressure and loses
# contact, is refused with a message (exit status 1).
foreach(case "ramp=0.3" "ramp=0.6" "force=0.5" "force=2" "z0=0.041,ramp=0.3" "ramp=0.3,fps=80" "ramp=0.3,fps=8"
             "ramp=0.9,force=0.013" "force=0.5,fps=5")
  softcut_case_sets("${case}" name sets)
  add_test(NAME "cut: a blade pressed in from the surface cuts through (${name})"
           COMMAND softcut run ${PROJECT_SOURCE_DIR}/tests/cut/press_in.lua --no-render --quiet
                   --out ${CMAKE_BINARY_DIR}/test-out/press_in/${name} ${sets})
  set_tests_properties("cut: a blade pressed in from the surface cuts through (${name})" PROPERTIES
                       ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache")
endforeach()
foreach(refusal "z0=0.03|its path starts inside the tissue"
                "z0=0.03,force=0.5|its path starts inside the tissue"
                "length=0.02,force=0.003|last touched the surface at t = [0-9.]+ s pressing at 75 Pa, below its cut_pressure = 100 Pa, and lost contact")
  string(REPLACE "|" ";" parts "${refusal}")
  list(GET parts 0 case)
  list(GET parts 1 regex)
  softcut_case_sets("${case}" name sets)
  set(test "cut: a blade inside the tissue that cannot cut is refused (${name})")
  add_test(NAME "${test}"
           COMMAND softcut run ${PROJECT_SOURCE_DIR}/tests/cut/press_in.lua --no-render --quiet
                   --out ${CMAKE_BINARY_DIR}/test-out/press_in/${name} ${sets})
  set_tests_properties("${test}" PROPERTIES
    ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache"
    PASS_REGULAR_EXPRESSION "press_in.lua:[0-9]+: scalpel 'blade': at t = [0-9.]+ s its edge is [0-9.]+ mm inside the tissue.*${regex}.*start its path above the surface")
endforeach()
