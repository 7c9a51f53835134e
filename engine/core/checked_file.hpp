#pragma once
// The one checked way to open a file below a folder: the sandbox's reads
// (scenario folder: scripts' io.open, mesh files and their sibling files) and
// writes (output folder: scripts' io.open, the engine's own outputs) all go
// through it.
//
// `root` is trusted and opened as given (it may itself be reached through a
// symlink the user chose). Everything below it is opened one component at a
// time with openat(O_NOFOLLOW): a symlink anywhere below the root is refused,
// also one planted after a path was checked, and '..' cannot climb out. Only
// regular files are opened (never a FIFO, device or socket: the open itself
// is non-blocking, so a FIFO cannot hang it), and a file opened for writing
// must not have other hard links.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>

namespace softcut {

// An owned file descriptor (closed on destruction; movable).
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& o) noexcept : fd_(o.release()) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept;
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd();
  int get() const { return fd_; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }
  explicit operator bool() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

enum class Access {
  read,       // "r"
  write,      // "w": create or truncate
  append,     // "a": create, writes go to the end
  update,     // "r+": read and write an existing file
  overwrite,  // "w+": create or truncate, read and write
  extend,     // "a+": create, read anywhere, write at the end
};

// Access for a Lua/C mode string ("r", "w", "a", "r+", "w+", "a+", each with
// optional trailing 'b'); false when the mode is not one of them.
bool parse_access(const std::string& mode, Access& out);
bool writes(Access a);

// `path` (absolute, or relative to `root`) as a relative path below `root`,
// lexically: no component may be '..' after normalisation, and none may be
// empty. Returns an empty path when it lies outside `root` (or is `root`).
std::filesystem::path relative_below(const std::filesystem::path& root, const std::filesystem::path& path);

// Opens `rel` (relative, from relative_below) below `root` as described
// above. Throws softcut::Error naming `what` ("io.open", "mesh file", ...),
// the path and the reason (a symlink, not a regular file, missing, ...).
UniqueFd open_below(const std::filesystem::path& root, const std::filesystem::path& rel, Access access,
                    const std::string& what);

// Like open_below, but a missing file (or folder on the way) is no error:
// returns an empty UniqueFd and sets *missing_errno (Lua's io.open returns
// nil, message, errno for it).
UniqueFd open_below_if_exists(const std::filesystem::path& root, const std::filesystem::path& rel, Access access,
                              const std::string& what, int* missing_errno);

// Creates the folder `rel` below `root` (and the folders on the way), each
// component checked like open_below's: an existing symlink in its place is
// refused, so a planted link cannot redirect the engine's writes. Returns
// the path root / rel.
std::filesystem::path make_folder_below(const std::filesystem::path& root, const std::filesystem::path& rel,
                                        const std::string& what);

// The whole regular file `rel` below `root`; refused (Error naming `what` and
// the size) when it holds more than `max_bytes`.
std::string read_below(const std::filesystem::path& root, const std::filesystem::path& rel,
                       const std::string& what,
                       std::size_t max_bytes = std::numeric_limits<std::size_t>::max());

// The rest of an open regular file, refused past `max_bytes` (`name` for messages).
std::string read_whole(const UniqueFd& fd, const std::string& what, const std::string& name,
                       std::size_t max_bytes = std::numeric_limits<std::size_t>::max());

// A regular file at a path the user chose (no root): opened without blocking
// on a FIFO and refused unless it is a regular file of at most `max_bytes`.
std::string read_regular_file(const std::filesystem::path& path, const std::string& what,
                              std::size_t max_bytes = std::numeric_limits<std::size_t>::max());

}  // namespace softcut
