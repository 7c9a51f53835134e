# The incremental-upload test of tests/gpu/compute_cg.cpp cuts a hybrid
# model with the real cutter, so test_gpu also links the cut stage.
target_link_libraries(test_gpu PRIVATE softcut_cut)
