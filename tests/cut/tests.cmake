# A scenario that cuts a piece free (docs/cutting.md "Pieces cut free") through
# the CLI: the run must complete, its expectations hold and its log match the
# reference (tests/cut/cut_free.ref.csv, `softcut check --record` to renew).
add_test(NAME "cut: softcut check a scenario that cuts a piece free"
         COMMAND softcut check ${PROJECT_SOURCE_DIR}/tests/cut/cut_free.lua)
