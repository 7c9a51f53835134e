#include "core/checked_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "core/error.hpp"
#include "core/printable.hpp"

namespace fs = std::filesystem;

namespace softcut {

UniqueFd& UniqueFd::operator=(UniqueFd&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.release();
  }
  return *this;
}

UniqueFd::~UniqueFd() {
  if (fd_ >= 0) ::close(fd_);
}

bool parse_access(const std::string& mode, Access& out) {
  std::string m = mode;
  while (!m.empty() && m.back() == 'b') m.pop_back();
  if (m == "r") out = Access::read;
  else if (m == "w") out = Access::write;
  else if (m == "a") out = Access::append;
  else if (m == "r+") out = Access::update;
  else if (m == "w+") out = Access::overwrite;
  else if (m == "a+") out = Access::extend;
  else return false;
  return true;
}

bool writes(Access a) { return a != Access::read; }

fs::path relative_below(const fs::path& root, const fs::path& path) {
  fs::path rel = path.is_absolute() ? path.lexically_normal().lexically_relative(root.lexically_normal())
                                    : path.lexically_normal();
  if (rel.empty() || rel.is_absolute() || rel == ".") return {};
  for (const fs::path& part : rel)
    if (part == ".." || part == "." || part.empty()) return {};
  return rel;
}

namespace {

struct Failure {
  int err = 0;          // errno of the failing call (0: a refusal of ours)
  std::string reason;   // for the message
};

std::string shown(const fs::path& p) { return "'" + printable(p.string()) + "'"; }

[[noreturn]] void refuse(const std::string& what, const fs::path& root, const fs::path& rel, const Failure& f) {
  fail(what, ": ", shown(rel), " below ", shown(root), ": ", f.reason);
}

// Why openat(2) refused a component, in words.
std::string reason_of(int err, const fs::path& part, bool last) {
  if (err == ELOOP || (err == ENOTDIR && !last))
    return cat(shown(part), " is a symbolic link or not a folder; softcut follows no links below this folder "
               "(replace the link by the file or folder itself)");
  if (err == ENXIO) return cat(shown(part), " is not a regular file (a FIFO or socket?)");
  return cat(shown(part), ": ", std::strerror(err));
}

// Opens each folder of `rel` below `root` without following links; fd of the
// innermost folder (rel's parent), or -1 with *f set. `create`: mkdirat first.
int open_parent(const fs::path& root, const fs::path& rel, bool create, Failure* f) {
  int dir = ::open(root.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir < 0) {
    *f = {errno, cat("cannot open the folder (", std::strerror(errno), ")")};
    return -1;
  }
  std::vector<fs::path> parts(rel.begin(), rel.end());
  for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
    if (create && ::mkdirat(dir, parts[k].c_str(), 0755) != 0 && errno != EEXIST) {
      *f = {errno, reason_of(errno, parts[k], false)};
      ::close(dir);
      return -1;
    }
    const int next = ::openat(dir, parts[k].c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    const int err = errno;
    ::close(dir);
    if (next < 0) {
      *f = {err, reason_of(err, parts[k], false)};
      return -1;
    }
    dir = next;
  }
  return dir;
}

int open_flags(Access a) {
  switch (a) {
    case Access::read: return O_RDONLY;
    case Access::write: return O_WRONLY | O_CREAT;
    case Access::append: return O_WRONLY | O_CREAT | O_APPEND;
    case Access::update: return O_RDWR;
    case Access::overwrite: return O_RDWR | O_CREAT;
    case Access::extend: return O_RDWR | O_CREAT | O_APPEND;
  }
  return O_RDONLY;
}

// The checked open itself: -1 with *f set on failure.
int open_checked(const fs::path& root, const fs::path& rel, Access access, Failure* f) {
  if (rel.empty() || rel.is_absolute() || relative_below(root, rel) != rel) {
    *f = {0, "the path must stay below the folder (no '..', no absolute path outside it)"};
    return -1;
  }
  const int dir = open_parent(root, rel, false, f);
  if (dir < 0) return -1;
  const fs::path leaf = rel.filename();
  // Non-blocking: opening a FIFO must not wait for a writer; truncation only
  // after the file is known to be a regular one.
  const int fd = ::openat(dir, leaf.c_str(), open_flags(access) | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC, 0644);
  const int err = errno;
  ::close(dir);
  if (fd < 0) {
    *f = {err, reason_of(err, leaf, true)};
    return -1;
  }
  struct stat st {};
  std::string why;
  if (::fstat(fd, &st) != 0) why = cat("cannot inspect the file (", std::strerror(errno), ")");
  else if (!S_ISREG(st.st_mode)) why = cat(shown(leaf), " is not a regular file");
  else if (writes(access) && st.st_nlink > 1)
    why = cat(shown(leaf), " has other hard links; softcut writes only files of its own (remove it first)");
  else if ((access == Access::write || access == Access::overwrite) && ::ftruncate(fd, 0) != 0)
    why = cat("cannot truncate the file (", std::strerror(errno), ")");
  else if (::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK) != 0)
    why = cat("cannot set blocking mode (", std::strerror(errno), ")");
  if (!why.empty()) {
    ::close(fd);
    *f = {0, why};
    return -1;
  }
  return fd;
}

std::string read_all(int fd, const std::string& what, const std::string& name, std::size_t max_bytes) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) fail(what, ": ", name, ": cannot inspect the file (", std::strerror(errno), ")");
  if (!S_ISREG(st.st_mode)) fail(what, ": ", name, ": not a regular file");
  if (std::uint64_t(st.st_size) > max_bytes)
    fail(what, ": ", name, ": the file holds ", std::uint64_t(st.st_size), " bytes, more than the ", max_bytes,
         " bytes allowed here (the memory budget: a sandboxed run's, which --trust lifts, or softcut mesh --max-memory)");
  std::string bytes(std::size_t(st.st_size), '\0');
  std::size_t at = 0;
  while (at < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + at, bytes.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(what, ": ", name, ": read error (", std::strerror(errno), ")");
    if (n == 0) fail(what, ": ", name, ": read error (the file shrank while it was read)");
    at += std::size_t(n);
  }
  return bytes;
}

}  // namespace

UniqueFd open_below(const fs::path& root, const fs::path& rel, Access access, const std::string& what) {
  Failure f;
  const int fd = open_checked(root, rel, access, &f);
  if (fd < 0) refuse(what, root, rel, f);
  return UniqueFd(fd);
}

UniqueFd open_below_if_exists(const fs::path& root, const fs::path& rel, Access access, const std::string& what,
                              int* missing_errno) {
  Failure f;
  const int fd = open_checked(root, rel, access, &f);
  if (fd < 0 && f.err == ENOENT) {
    if (missing_errno) *missing_errno = f.err;
    return UniqueFd();
  }
  if (fd < 0) refuse(what, root, rel, f);
  return UniqueFd(fd);
}

fs::path make_folder_below(const fs::path& root, const fs::path& rel, const std::string& what) {
  if (relative_below(root, rel) != rel) fail(what, ": ", shown(rel), " must be a folder name below ", shown(root));
  Failure f;
  const int dir = open_parent(root, rel / "x", true, &f);  // every component of rel is a folder to make
  if (dir < 0) refuse(what, root, rel, f);
  ::close(dir);
  return root / rel;
}

std::string read_below(const fs::path& root, const fs::path& rel, const std::string& what, std::size_t max_bytes) {
  const UniqueFd fd = open_below(root, rel, Access::read, what);
  return read_all(fd.get(), what, shown(rel), max_bytes);
}

std::string read_whole(const UniqueFd& fd, const std::string& what, const std::string& name, std::size_t max_bytes) {
  return read_all(fd.get(), what, name, max_bytes);
}

std::string read_regular_file(const fs::path& path, const std::string& what, std::size_t max_bytes) {
  const UniqueFd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC));
  if (!fd) fail(path.string(), ": cannot open ", what, " (", std::strerror(errno), ")");
  return read_all(fd.get(), what, shown(path), max_bytes);
}

}  // namespace softcut
