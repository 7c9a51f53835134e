#pragma once
// Reading segmented 3D label images in NRRD (teem's "nearly raw raster data",
// http://teem.sourceforge.net/nrrd/format.html): attached (.nrrd) or detached
// (.nhdr + data file) headers; encodings raw, gzip and ascii; integer types of
// 8, 16 and 32 bits, either endian. docs/label-volume.md lists what is
// accepted. Every malformed header line is an Error naming file:line.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace softcut::mesh {

struct LabelVolume {
  std::string source;          // file name, for messages
  Eigen::Vector3i size;        // voxels along the three axes (i, j, k)
  Eigen::Matrix3d directions;  // columns: step between voxel centres along i, j, k, m
  Eigen::Vector3d origin;      // centre of voxel (0, 0, 0), m
  std::vector<std::int32_t> labels;  // (size(0) * size(1) * size(2)) i fastest, then j, then k

  std::int64_t num_voxels() const { return std::int64_t(size(0)) * size(1) * size(2); }
  std::int64_t index(int i, int j, int k) const { return i + std::int64_t(size(0)) * (j + std::int64_t(size(1)) * k); }
};

struct NrrdReadOptions {
  // Metres per length unit of the file's spacings / directions / origin.
  // 0: from the header's `space units` ("m", "cm", "mm", "um"), and
  // millimetres (the medical-imaging convention) when it has none.
  double unit_m = 0;
  // Bytes the file, its decoded voxel data and the labels may take: a header
  // announcing more is refused before anything is inflated or allocated
  // (a 1 MB gzip file can announce 1000^3 voxels).
  std::size_t max_bytes = std::numeric_limits<std::size_t>::max();
  std::string raise = "softcut mesh --max-memory BYTES raises the limit";  // for the message
};

// Reads a 3D integer NRRD. Warnings (ignored fields, missing units, trailing
// data) go to `diag`. Label values must fit in int32.
LabelVolume read_nrrd_labels(const std::filesystem::path& path, Diagnostics& diag, const NrrdReadOptions& opt = {});

}  // namespace softcut::mesh
