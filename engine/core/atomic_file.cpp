#include "core/atomic_file.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <streambuf>

#include "core/checked_file.hpp"
#include "core/error.hpp"

namespace softcut {

namespace {

// An ostream buffer over a file descriptor (the temporary file is made with
// open(2) flags a std::ofstream cannot take).
class FdBuf : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd) { setp(buf_, buf_ + sizeof buf_); }
  ~FdBuf() override { sync(); }
  std::uintmax_t written() const { return written_ + std::uintmax_t(pptr() - pbase()); }
  bool failed() const { return failed_; }

 protected:
  int_type overflow(int_type c) override {
    if (sync() != 0) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override {
    const char* p = pbase();
    while (p < pptr()) {
      const ssize_t n = ::write(fd_, p, std::size_t(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        failed_ = true;
        setp(buf_, buf_ + sizeof buf_);
        return -1;
      }
      p += n;
      written_ += std::uintmax_t(n);
    }
    setp(buf_, buf_ + sizeof buf_);
    return 0;
  }

 private:
  int fd_;
  char buf_[1 << 16];
  std::uintmax_t written_ = 0;
  bool failed_ = false;
};

}  // namespace

std::uintmax_t write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write,
                                 bool /*binary*/) {
  static std::atomic<int> counter{0};
  const std::filesystem::path parent = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const std::filesystem::path leaf = path.filename();
  const std::string tmp = cat(".", leaf.string(), ".", ::getpid(), ".", counter++, ".tmp");
  // The folder as the caller named it; the temporary file made anew inside it
  // (O_EXCL never follows a link planted under its name); rename(2) then
  // replaces whatever `path` was, a planted link included, without following it.
  const UniqueFd dir(::open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (!dir) fail(path.string(), ": cannot create the file (does the folder exist and is it writable?)");
  const int fd = ::openat(dir.get(), tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) fail(path.string(), ": cannot create the file (", std::strerror(errno), ")");
  const UniqueFd file(fd);
  // Held while the file is written: a cleaner (the precompute cache's
  // eviction) tells a live writer's temporary file from a killed one's.
  ::flock(fd, LOCK_EX | LOCK_NB);
  std::uintmax_t bytes = 0;
  bool ok = false;
  try {
    FdBuf buf(fd);
    std::ostream os(&buf);
    write(os);
    os.flush();
    ok = bool(os) && !buf.failed();
    bytes = buf.written();
  } catch (...) {
    ::unlinkat(dir.get(), tmp.c_str(), 0);
    throw;
  }
  if (!ok) {
    ::unlinkat(dir.get(), tmp.c_str(), 0);
    fail(path.string(), ": write failed (disk full?)");
  }
  if (::renameat(dir.get(), tmp.c_str(), dir.get(), leaf.c_str()) != 0) {
    const int err = errno;
    ::unlinkat(dir.get(), tmp.c_str(), 0);
    fail(path.string(), ": cannot rename the finished file into place: ", std::strerror(err));
  }
  return bytes;
}

std::uintmax_t write_file_atomic(const std::filesystem::path& path, std::string_view bytes) {
  return write_file_atomic(path, [&](std::ostream& os) { os.write(bytes.data(), std::streamsize(bytes.size())); },
                           true);
}

}  // namespace softcut
