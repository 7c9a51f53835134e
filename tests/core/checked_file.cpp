// engine/core/checked_file.cpp: the one checked open refuses every way out
// of its folder (.., absolute paths, symlinks anywhere below the root, a
// link planted after a check), FIFOs without blocking, hard-linked writes.
#include "core/checked_file.hpp"

#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "core/error.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using softcut::Access;
using softcut::test::contains;
using softcut::test::error_of;

namespace {

void put(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

}  // namespace

TEST_SUITE("core/checked_file") {
  TEST_CASE("relative_below keeps paths below the root and refuses the rest") {
    const fs::path root = "/srv/scen";
    CHECK(softcut::relative_below(root, "a/b.txt") == fs::path("a/b.txt"));
    CHECK(softcut::relative_below(root, "a/../b.txt") == fs::path("b.txt"));
    CHECK(softcut::relative_below(root, "/srv/scen/m/x.vtu") == fs::path("m/x.vtu"));
    for (const char* bad : {"../x", "a/../../x", "/etc/passwd", "/srv/scenic/x", ".", "", "/srv/scen"})
      CHECK_MESSAGE(softcut::relative_below(root, bad).empty(), bad);
  }

  TEST_CASE("reads and writes regular files below the root - writes truncate, appends append") {
    const fs::path root = softcut::test::scratch_dir("checked_rw");
    fs::create_directories(root / "sub");
    put(root / "sub" / "a.txt", "hello");
    CHECK(softcut::read_below(root, "sub/a.txt", "test") == "hello");
    { auto fd = softcut::open_below(root, "sub/a.txt", Access::write, "test"); CHECK(::write(fd.get(), "x", 1) == 1); }
    CHECK(softcut::read_below(root, "sub/a.txt", "test") == "x");
    { auto fd = softcut::open_below(root, "sub/a.txt", Access::append, "test"); CHECK(::write(fd.get(), "y", 1) == 1); }
    CHECK(softcut::read_below(root, "sub/a.txt", "test") == "xy");
    CHECK(contains(error_of([&] { softcut::read_below(root, "sub/a.txt", "test", 1); }), "more than the 1 bytes"));
    int missing = 0;
    CHECK_FALSE(softcut::open_below_if_exists(root, "nope.txt", Access::read, "test", &missing));
    CHECK(missing == ENOENT);
  }

  TEST_CASE("a symlink anywhere below the root is refused, dangling or not, file or folder") {
    const fs::path root = softcut::test::scratch_dir("checked_links");
    const fs::path outside = softcut::test::scratch_dir("checked_links_outside");
    put(outside / "secret", "SECRET-TOKEN");
    fs::create_symlink(outside / "secret", root / "link.txt");
    fs::create_symlink(outside / "created-by-attack", root / "dangling.txt");
    fs::create_symlink(outside, root / "dir");
    for (Access a : {Access::read, Access::write, Access::append, Access::update})
      CHECK(contains(error_of([&] { softcut::open_below(root, "link.txt", a, "io.open"); }), "symbolic link"));
    const std::string dangling = error_of([&] { softcut::open_below(root, "dangling.txt", Access::write, "io.open"); });
    CHECK(contains(dangling, "symbolic link"));
    CHECK_FALSE(fs::exists(outside / "created-by-attack"));
    CHECK(contains(error_of([&] { softcut::read_below(root, "dir/secret", "mesh file"); }), "symbolic link"));
    CHECK_FALSE(contains(error_of([&] { softcut::read_below(root, "link.txt", "mesh file"); }), "SECRET"));
    CHECK(contains(error_of([&] { softcut::make_folder_below(root, "dir", "outputs"); }), "symbolic link"));
    CHECK(contains(error_of([&] { softcut::open_below(root, "../x", Access::read, "t"); }), "must stay below"));
  }

  TEST_CASE("a FIFO is refused at once (no blocking open), so are folders and hard-linked writes") {
    const fs::path root = softcut::test::scratch_dir("checked_special");
    REQUIRE(::mkfifo((root / "fifo").c_str(), 0600) == 0);
    CHECK(contains(error_of([&] { softcut::open_below(root, "fifo", Access::read, "t"); }), "not a regular file"));
    CHECK(contains(error_of([&] { softcut::open_below(root, "fifo", Access::write, "t"); }), "not a regular file"));
    fs::create_directories(root / "d");
    CHECK(contains(error_of([&] { softcut::open_below(root, "d", Access::read, "t"); }), "not a regular file"));
    const fs::path outside = softcut::test::scratch_dir("checked_special_outside");
    put(outside / "bashrc", "keep");
    fs::create_hard_link(outside / "bashrc", root / "hard.txt");
    CHECK(contains(error_of([&] { softcut::open_below(root, "hard.txt", Access::write, "t"); }), "hard links"));
    CHECK(softcut::read_regular_file(outside / "bashrc", "t") == "keep");
    CHECK(contains(error_of([&] { softcut::read_regular_file(root / "fifo", "the mesh file"); }), "not a regular file"));
  }

  TEST_CASE("make_folder_below makes nested folders and returns root / rel") {
    const fs::path root = softcut::test::scratch_dir("checked_mkdir");
    CHECK(softcut::make_folder_below(root, "a/b", "t") == root / "a" / "b");
    CHECK(fs::is_directory(root / "a" / "b"));
    CHECK(softcut::make_folder_below(root, "a/b", "t") == root / "a" / "b");  // twice is fine
  }

  TEST_CASE("parse_access takes Lua's modes only") {
    Access a;
    for (const char* m : {"r", "rb", "w", "a", "r+", "w+", "a+", "r+b"}) CHECK_MESSAGE(softcut::parse_access(m, a), m);
    for (const char* m : {"", "x", "rw", "+r", "wx"}) CHECK_FALSE_MESSAGE(softcut::parse_access(m, a), m);
  }
}
