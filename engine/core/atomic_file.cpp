#include "core/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <fstream>

#include "core/error.hpp"

namespace softcut {

void write_file_atomic(const std::filesystem::path& path,
                       const std::function<void(std::ostream&)>& write, bool binary) {
  static std::atomic<int> counter{0};
  std::filesystem::path tmp = path;
  tmp += cat(".", ::getpid(), ".", counter++, ".tmp");
  {
    std::ofstream os(tmp, binary ? std::ios::binary | std::ios::out : std::ios::out);
    if (!os) fail(path.string(), ": cannot create the file (does the folder exist and is it writable?)");
    try {
      write(os);
    } catch (...) {
      os.close();
      std::filesystem::remove(tmp);
      throw;
    }
    os.flush();
    if (!os) {
      os.close();
      std::filesystem::remove(tmp);
      fail(path.string(), ": write failed (disk full?)");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    fail(path.string(), ": cannot rename the finished file into place: ", ec.message());
  }
}

void write_file_atomic(const std::filesystem::path& path, std::string_view bytes) {
  write_file_atomic(path, [&](std::ostream& os) { os.write(bytes.data(), std::streamsize(bytes.size())); },
                    true);
}

}  // namespace softcut
