#include "core/atomic_file.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

TEST_SUITE("core/atomic_file") {
  TEST_CASE("writes the whole file and leaves no temporary behind") {
    const fs::path dir = softcut::test::scratch_dir("atomic_ok");
    softcut::write_file_atomic(dir / "a.txt", "hello\n");
    std::ifstream in(dir / "a.txt");
    std::stringstream ss;
    ss << in.rdbuf();
    CHECK(ss.str() == "hello\n");
    int files = 0;
    for (auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
    CHECK(files == 1);
  }

  TEST_CASE("a writer that throws leaves the old file intact") {
    const fs::path dir = softcut::test::scratch_dir("atomic_throw");
    softcut::write_file_atomic(dir / "a.txt", "old");
    CHECK_THROWS(softcut::write_file_atomic(dir / "a.txt", [](std::ostream& os) {
      os << "half";
      throw std::runtime_error("interrupted");
    }));
    std::ifstream in(dir / "a.txt");
    std::string s;
    in >> s;
    CHECK(s == "old");
    int files = 0;
    for (auto& e : fs::directory_iterator(dir)) files += e.is_regular_file();
    CHECK(files == 1);
  }

  TEST_CASE("a missing folder is a clear error naming the path") {
    const fs::path dir = softcut::test::scratch_dir("atomic_missing");
    try {
      softcut::write_file_atomic(dir / "nope" / "a.txt", "x");
      FAIL("expected an error");
    } catch (const softcut::Error& e) {
      CHECK(std::string(e.what()).find("nope/a.txt") != std::string::npos);
    }
  }
}

TEST_SUITE("core/atomic_file") {
  TEST_CASE("a symlink planted at the target or at a temporary name is never written through") {
    const fs::path dir = softcut::test::scratch_dir("atomic_symlink");
    fs::create_directories(dir / "out");
    {
      std::ofstream(dir / "victim") << "keep";
    }
    fs::create_symlink(dir / "victim", dir / "out" / "summary.json");
    const std::uintmax_t n = softcut::write_file_atomic(dir / "out" / "summary.json", "new");
    CHECK(n == 3);
    std::ifstream in(dir / "victim");
    std::string victim;
    in >> victim;
    CHECK(victim == "keep");  // the link was replaced, its target untouched
    CHECK_FALSE(fs::is_symlink(dir / "out" / "summary.json"));
  }
}
