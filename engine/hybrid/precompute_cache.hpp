#pragma once
// On-disk cache of the hybrid precompute (paper Table 1's data and the K22
// factor), so re-running a scenario (the authoring loop: edit a tool path,
// run again) starts at once. An entry is keyed by a hash of everything the
// precompute depends on (mesh, per-tet materials, partition, fixed set,
// initial loads, storage options, format version) and stores those inputs
// too: a hit compares them byte for byte, so a hash collision or a changed
// input is a miss, never a wrong model. A CRC-32 over the whole file catches
// corrupt and truncated entries; either is rebuilt and rewritten. Entries
// are written atomically; past `max_bytes` the least recently used go. The
// temporary files of writes in progress count toward `max_bytes`; those of
// killed writes (no process holds their flock, a minute old) are removed.
//
//   CacheReport rep;
//   Model M = precompute_cached(mesh, mat, part, opt, {default_cache_dir()}, &rep);
#include <filesystem>
#include <string>

#include "hybrid/precompute.hpp"

namespace softcut::hybrid {

struct CacheOptions {
  std::filesystem::path dir;                            // empty: no cache (plain precompute)
  double max_bytes = 4.0 * 1024 * 1024 * 1024;          // all entries together
};

struct CacheReport {
  bool enabled = false;
  bool hit = false;
  std::string key;          // 16 hex digits
  std::string file;         // the entry's path
  std::string miss_reason;  // "no entry", "corrupt: ...", "inputs differ", "format version ..." (misses)
  double load_ms = 0;       // reading and checking the entry (hits)
  double saved_ms = 0;      // the cold precompute's time minus load_ms (hits)
  double write_ms = 0;      // writing the entry (misses)
  double bytes = 0;         // the entry's size
  int evicted = 0;          // entries removed to stay within max_bytes
  int stale_removed = 0;    // temporary files of killed writes removed (no live writer holds their lock)
  std::string write_error;  // a failed write is reported, not fatal
};

// $SOFTCUT_CACHE_DIR, else $XDG_CACHE_HOME/softcut, else $HOME/.cache/softcut;
// empty when none is set.
std::filesystem::path default_cache_dir();

// precompute() through the cache. Errors of the precompute itself propagate;
// cache trouble (unreadable, corrupt, unwritable) only changes the report.
Model precompute_cached(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material, const Partition& p,
                        const PrecomputeOptions& opt, const CacheOptions& cache, CacheReport* report = nullptr);

}  // namespace softcut::hybrid
