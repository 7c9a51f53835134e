#include "core/binary_io.hpp"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <vector>

#include "core/error.hpp"

using namespace softcut;
namespace fs = std::filesystem;

namespace {

fs::path write_file(const std::string& name, const std::string& bytes) {
  const fs::path p = fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()));
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

// Reads back what write_sample wrote; throws softcut::Error on anything wrong.
std::vector<double> read_sample(const fs::path& p, int threads = 2) {
  const int fd = ::open(p.c_str(), O_RDONLY);
  REQUIRE(fd >= 0);
  std::vector<double> big;
  try {
    BinaryReader r(fd, fs::file_size(p), "sample", threads);
    std::int32_t tag = 0;
    r.pod(tag);
    if (tag != 42) fail("sample: wrong tag ", tag);
    big.resize(r.count(sizeof(double)));
    r.bytes(big.data(), big.size() * sizeof(double));
    r.finish();
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  return big;
}

std::string write_sample(const std::vector<double>& big) {
  std::ostringstream os;
  BinaryWriter w(os);
  w.pod(std::int32_t(42));
  w.array(big.data(), big.size());
  w.finish();
  return os.str();
}

}  // namespace

TEST_SUITE("core/binary_io") {
  TEST_CASE("round trip of a small and a large array (the two-thread read), and every corruption is caught") {
    for (size_t n : {size_t(10), size_t(5) << 20}) {  // 80 bytes; 40 MB (read in two halves)
      std::vector<double> big(n);
      std::iota(big.begin(), big.end(), 0.5);
      const std::string bytes = write_sample(big);
      const fs::path p = write_file("softcut-binio", bytes);
      CHECK(read_sample(p) == big);
      CHECK(read_sample(p, 1) == big);  // one thread: the same bytes, the same checksum
      for (size_t at : {size_t(2), bytes.size() / 3, bytes.size() * 3 / 4, bytes.size() - 1}) {
        std::string bad = bytes;
        bad[at] = char(bad[at] ^ 1);
        const fs::path q = write_file("softcut-binio-bad", bad);
        CAPTURE(at);
        CHECK_THROWS_AS(read_sample(q), Error);
        fs::remove(q);
      }
      const fs::path cut = write_file("softcut-binio-cut", bytes.substr(0, bytes.size() - 5));
      CHECK_THROWS_WITH(read_sample(cut), doctest::Contains("sample: "));
      const fs::path extra = write_file("softcut-binio-extra", bytes + "x");
      CHECK_THROWS_WITH(read_sample(extra), doctest::Contains("unexpected bytes after the checksum"));
      fs::remove(p), fs::remove(cut), fs::remove(extra);
    }
  }

  TEST_CASE("a count larger than the file is refused before anything is allocated") {
    std::ostringstream os;
    BinaryWriter w(os);
    w.pod(std::int32_t(42));
    w.pod(std::uint64_t(1) << 60);  // a billion billion doubles
    w.finish();
    const fs::path p = write_file("softcut-binio-huge", os.str());
    CHECK_THROWS_WITH(read_sample(p), doctest::Contains("does not fit"));
    fs::remove(p);
  }
}
