// libFuzzer target: the NRRD label-volume reader on an attached-header file
// (a detached header may name any data file; such seeds stay in the corpus but
// the fuzzer writes only fuzz.nrrd). Small volumes (<= 256 voxels) that read cleanly are also
// meshed (voxel Kuhn split + one smoothing pass) to reach label_volume.cpp.
#include "fuzz_support.hpp"
#include "mesh/volume/label_volume.hpp"
#include "mesh/volume/nrrd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace softcut;
  const auto path = fuzz::put_file("fuzz.nrrd", fuzz::as_text(data, size));
  fuzz::expect_clean([&] {
    Diagnostics diag;
    const mesh::LabelVolume v = mesh::read_nrrd_labels(path, diag);
    if (v.num_voxels() > 256) return;  // meshing bigger volumes would dominate exec time
    mesh::VoxelMeshOptions opt;
    opt.smooth_iterations = 1;
    mesh::mesh_label_volume(v, opt, diag);
  });
  return 0;
}
