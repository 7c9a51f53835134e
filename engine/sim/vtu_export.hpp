#pragma once
// A run's VTU export of one frame (vtu/frame_NNNNNN.vtu) through the one VTU
// writer (mesh/io/vtu_writer.hpp): the current (possibly cut) mesh at rest
// with point data "displacement" (nnode x 3, m) and "node_set", cell data
// "label", "operational" and "material" (the s:material call that set the
// tet's material, by its index; the number of calls where none did).
#include <cstdint>
#include <filesystem>

#include "sim/model.hpp"

namespace softcut::sim {

// Writes the frame atomically; returns the bytes written.
std::uintmax_t write_vtu(const std::filesystem::path& path, const Model& m, const State& s);

}  // namespace softcut::sim
