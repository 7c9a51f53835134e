#pragma once
// Reference displacement logs for `softcut check`: a scenario's
// displacements.csv compared with the one stored next to it
// (scenarios/<name>.ref.csv), within a tolerance relative to the motion's
// scale (the largest |u| component in the reference).
//
// A reference starts with one header line saying what made it, so a log
// copied from another scenario is named as such, not called stale:
//   # softcut-reference: {"scenario":"kidney_cut","mesh":"fnv1a64:…","params":{"f":"0.5"},"softcut":"0.9.0"}
//   frame,time,node,ux,uy,uz
//   0,0.000000000e+00,12,…
// References without it (recorded before the header existed) still read.
//
// Both logs are untrusted files: each is opened through the checked open
// (its last component never a link, only a regular file, never blocking),
// read as a stream in lockstep (memory does not grow with the file), lines
// are bounded, the reference is read no further than the log it is compared
// with allows, and a stop flag (the scenario's --timeout, Ctrl-C) is polled.
#include <atomic>
#include <filesystem>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "core/checked_file.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::app {

// Who made a reference: compared by `check`, written by `check --record`.
struct ReferenceHeader {
  bool present = false;  // false: a reference recorded before headers existed
  std::string scenario;  // softcut.scenario{ name }
  std::string mesh;      // mesh_fingerprint() of the rest mesh
  std::vector<std::pair<std::string, std::string>> params;  // after --set, as the script saw them
  std::string softcut;   // version that recorded it
};

// A file to read as root/rel: `root` is a folder the user named (trusted,
// opened as given), `rel` is opened below it without following any link.
struct LogFile {
  std::filesystem::path root, rel;
  // A path as given: its folder is the root, its name the file.
  static LogFile at(const std::filesystem::path& path);
  std::string shown() const;  // root / rel, for messages
};

struct LogComparison {
  bool ok = false;
  bool stale = false;      // rows differ (frames, nodes): not comparable
  bool foreign = false;    // the header names another scenario
  double max_diff = 0.0;   // m, largest |u - u_ref| component
  double scale = 0.0;      // m, largest |u_ref| component
  long worst_frame = -1, worst_node = -1;  // row of max_diff (-1: none)
  int worst_component = -1;                // 0..2: x, y, z
  long rows = 0;                           // rows of the produced log compared
  ReferenceHeader header;  // the reference's
  std::string message;     // why not ok
};

// What the reference is compared against (the run's own facts).
struct RunIdentity {
  std::string scenario;
  std::string mesh;
  std::vector<std::pair<std::string, std::string>> params;
};

// Flags polled while a log is read (between 64 KiB blocks): either set ends
// the reading with an Error.
struct CompareLimits {
  const std::atomic<bool>* timeout = nullptr;    // the scenario's --timeout passed
  double timeout_s = 0;                          // for the message
  const std::atomic<bool>* interrupt = nullptr;  // Ctrl-C
};

// Longest line either log may hold, bytes (a data row is < 100).
constexpr std::size_t kMaxLogLine = 64 << 10;

// Reference log path of a scenario: <dir>/<stem>.ref.csv.
std::filesystem::path reference_path(const std::filesystem::path& scenario);

// "fnv1a64:<16 hex digits>" of the rest mesh (node coordinates, tets,
// labels): the same mesh on the same build gives the same text.
std::string mesh_fingerprint(const mesh::TetMesh& m);

// The header line (with its newline) for `h` (present is ignored).
std::string reference_header_line(const ReferenceHeader& h);

// Reads only the header of a reference (present = false when it has none).
// Throws softcut::Error naming the file for a link, a non-regular file or
// a malformed header line.
ReferenceHeader read_reference_header(const LogFile& reference);

// Compares two logs `frame,time,node,ux,uy,uz`; ok when every row matches in
// (frame, node) and max_diff <= tolerance * scale (or both are all zero).
// With `who`, a reference whose header names another scenario is `foreign`
// (not ok, not compared). Throws softcut::Error naming the file and line of
// malformed input, and for a stop.
LogComparison compare_logs(const LogFile& produced, const LogFile& reference, double tolerance,
                           const RunIdentity* who = nullptr, const CompareLimits& limits = {});
// The same for two paths as given (tests, tools).
LogComparison compare_logs(const std::filesystem::path& produced, const std::filesystem::path& reference,
                           double tolerance);

// Copies the produced log behind `header`'s line into `os` as it is read
// (never whole in memory); polls limits.stop. Throws naming the file.
void copy_as_reference(const LogFile& produced, const ReferenceHeader& header, std::ostream& os,
                       const CompareLimits& limits = {});

}  // namespace softcut::app
