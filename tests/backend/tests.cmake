# The solver's tests compare backends on whole frames of the same scenario
# (the cantilever fixture), so they compile models through sim::compile.
target_link_libraries(test_backend PRIVATE softcut_sim)
