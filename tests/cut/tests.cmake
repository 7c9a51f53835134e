# A scenario that cuts a piece free (docs/cutting.md "Pieces cut free") through
# the CLI: the run must complete, its expectations hold and its log match the
# reference (tests/cut/cut_free.ref.csv, `softcut check --record` to renew).
add_test(NAME "cut: softcut check a scenario that cuts a piece free"
         COMMAND softcut check ${PROJECT_SOURCE_DIR}/tests/cut/cut_free.lua)

# Issue #16 item 1: a cut through tissue that moves while the blade passes
# (tests/cut/moving_tissue.lua checks two anchored pieces at the end). Before
# the fix every moving or loaded case ended in one piece.
foreach(case "hz=3" "hz=0,amp=0" "hz=0,amp=0,fz=-1e-30" "hz=3,fps=80" "hz=8" "hz=3,path=1")
  string(REPLACE "," " " name "${case}")
  string(REPLACE "," ";" kvs "${case}")
  set(sets "")
  foreach(kv IN LISTS kvs)
    list(APPEND sets --set ${kv})
  endforeach()
  add_test(NAME "cut: a blade cuts through moving tissue (${name})"
           COMMAND softcut run ${PROJECT_SOURCE_DIR}/tests/cut/moving_tissue.lua --no-render --quiet
                   --out ${CMAKE_BINARY_DIR}/test-out/moving_tissue/${name} ${sets})
  set_tests_properties("cut: a blade cuts through moving tissue (${name})" PROPERTIES
                       ENVIRONMENT "SOFTCUT_CACHE_DIR=${CMAKE_BINARY_DIR}/test-cache")
endforeach()
