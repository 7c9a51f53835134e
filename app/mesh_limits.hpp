#pragma once
// The bounds every `softcut mesh` command keeps (docs/hardening.md, "What
// softcut mesh promises"): wall-clock time (--timeout), the bytes a file and
// what it decodes to may take (--max-memory), and for generate the
// tetrahedra it may make (--max-tets). Declared once here, as CLI11 typed
// options with their validators, for info, convert and generate alike.
#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "core/watchdog.hpp"
#include "mesh/io/mesh_io.hpp"

namespace softcut::app {

struct MeshLimits {
  double timeout_s = 3600;                 // 0: none
  std::uint64_t max_memory = 2ull << 30;   // bytes; 0: none
  int max_tets = 2'000'000;

  // --timeout, --max-memory, and with `tets` --max-tets.
  void declare(CLI::App& app, bool tets);
  // What a reader may take: a file and each decoded array at most a quarter
  // of --max-memory (the file, its arrays and the mesh live together).
  mesh::ReadOptions read() const;
  std::size_t read_bytes() const;
  // What a label image (its file, decoded voxels and labels: the working set
  // before meshing) may take: half of --max-memory (a 512 x 512 x 300 CT
  // segmentation needs ~400 MB).
  std::size_t volume_bytes() const;
  // Starts the command's clock (`command`: "softcut mesh generate liver").
  // CGAL's meshing polls expired() and ends with exit status 124; work that
  // polls nothing is ended by the watchdog itself after a short grace.
  std::unique_ptr<Watchdog> start(const std::string& command) const;
  // How the message of a refused mesh says to raise the limit.
  static const char* raise_tets() { return "--max-tets N raises the limit"; }
};

// A validator whose description stays out of --help's value names
// ("--timeout S", not "--timeout S:NONNEGATIVE").
inline CLI::Validator plain(CLI::Validator v) {
  v.description("");
  return v;
}

// "X,Y,Z" -> three numbers; the validator's message when it is not.
CLI::Validator vec3_text();
CLI::Validator number_text();
bool parse_vec3(const std::string& text, double out[3]);

}  // namespace softcut::app
