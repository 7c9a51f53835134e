#pragma once
// Reference displacement logs for `softcut check`: a scenario's
// displacements.csv compared with the one stored next to it
// (scenarios/<name>.ref.csv), within a tolerance relative to the motion's
// scale (the largest |u| component in the reference).
#include <filesystem>
#include <string>

namespace softcut::app {

struct LogComparison {
  bool ok = false;
  bool stale = false;      // rows differ (frames, nodes): not comparable
  double max_diff = 0.0;   // m, largest |u - u_ref| component
  double scale = 0.0;      // m, largest |u_ref| component
  long worst_frame = -1, worst_node = -1;  // row of max_diff (-1: none)
  int worst_component = -1;                // 0..2: x, y, z
  std::string message;     // why not ok
};

// Reference log path of a scenario: <dir>/<stem>.ref.csv.
std::filesystem::path reference_path(const std::filesystem::path& scenario);

// Compares two logs `frame,time,node,ux,uy,uz`; ok when every row matches in
// (frame, node) and max_diff <= tolerance * scale (or both are all zero).
// Throws softcut::Error naming the file and line of malformed input.
LogComparison compare_logs(const std::filesystem::path& produced, const std::filesystem::path& reference,
                           double tolerance);

}  // namespace softcut::app
