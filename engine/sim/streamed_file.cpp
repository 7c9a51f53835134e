#include "sim/streamed_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "core/error.hpp"
#include "core/output_budget.hpp"

namespace softcut::sim {

namespace fs = std::filesystem;

StreamedFile::StreamedFile(const fs::path& dir, std::string name, std::string_view header, OutputBudget* budget)
    : dir_(dir), tmp_(dir / (name + ".partial")), name_(std::move(name)), budget_(budget) {
  // A stale one (an earlier run killed) or a planted link goes first: the
  // file is then made new, never opened through a link.
  std::error_code ec;
  fs::remove(tmp_, ec);
  const int fd = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0 || !(file_ = ::fdopen(fd, "wb"))) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    fail("outputs: cannot write ", tmp_.string(), " (", std::strerror(err), ")");
  }
  write(header);
}

StreamedFile::~StreamedFile() {
  if (!file_) return;
  std::fclose(file_);
  std::error_code ec;
  fs::remove(tmp_, ec);
}

void StreamedFile::write(std::string_view text) {
  if (!file_) fail("outputs: ", name_, " written after it was finished");
  if (budget_) budget_->charge(text.size(), name_);
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size())
    fail("outputs: writing ", tmp_.string(), " failed (disk full?)");
}

void StreamedFile::finish() {
  if (!file_) return;
  const bool ok = std::fflush(file_) == 0 && !std::ferror(file_);
  std::fclose(file_);
  file_ = nullptr;
  std::error_code ec;
  if (!ok) {
    fs::remove(tmp_, ec);
    fail("outputs: writing ", tmp_.string(), " failed (disk full?)");
  }
  fs::rename(tmp_, dir_ / name_, ec);
  if (ec) fail("outputs: cannot rename ", tmp_.string(), " to ", name_, ": ", ec.message());
}

}  // namespace softcut::sim
