# test_fidelity: large deformation against CalculiX (ccx, Debian's
# calculix-ccx: scripts/install-deps.sh --test installs it) on the same mesh,
# through the whole engine (a scenario compiled and stepped).
add_library(softcut_fidelity INTERFACE)
target_link_libraries(softcut_fidelity INTERFACE softcut_sim)
