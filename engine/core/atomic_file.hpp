#pragma once
// Outputs are written atomically: into a temporary file beside the target,
// then renamed over it, so a reader never sees a half-written file (also when
// the run is interrupted or the disk fills up).
#include <filesystem>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string_view>

namespace softcut {

// Calls write(os) on a temporary file and renames it to `path` on success;
// returns the bytes written. The temporary file is created new (it never
// follows a symlink planted under its name) and the rename replaces `path`
// itself, a symlink there included, so a planted link never redirects the
// write. The temporary file is flock()ed while it is written (so a cleaner
// can tell it from one a killed process left). Throws softcut::Error naming
// the path when the folder is missing or not writable, or when writing fails
// (the temporary file is removed).
std::uintmax_t write_file_atomic(const std::filesystem::path& path,
                       const std::function<void(std::ostream&)>& write,
                       bool binary = false);

// Convenience for a whole buffer.
std::uintmax_t write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

}  // namespace softcut
