// sim/output_folder: what a new run clears from its output folder (only
// softcut's own names, links unlinked and never followed), including the
// private folder of a video whose run was killed while encoding.
#include "sim/output_folder.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "test_support.hpp"

using namespace softcut;
namespace fs = std::filesystem;

namespace {

void put(const fs::path& p, const char* text = "x") {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

}  // namespace

TEST_SUITE("sim/output_folder") {
  TEST_CASE("softcut's own files go, the user's stay") {
    const fs::path dir = test::scratch_dir("output_folder_own");
    for (const char* name : {"summary.json", "displacements.csv.partial", ".summary.json.123.4.tmp", "video.mp4",
                             "frames/frame_000001.png", "frames/labels_000012.png", "vtu/frame_000003.vtu"})
      put(dir / name);
    for (const char* name : {"notes.txt", "summary.json.bak", "frames/frame_1.png", ".summary.json.x.4.tmp"})
      put(dir / name);
    CHECK(sim::clear_earlier_outputs(dir) == 7);
    CHECK(fs::exists(dir / "notes.txt"));
    CHECK(fs::exists(dir / "summary.json.bak"));
    CHECK(fs::exists(dir / "frames/frame_1.png"));
    CHECK(fs::exists(dir / ".summary.json.x.4.tmp"));
    CHECK(!fs::exists(dir / "vtu"));  // emptied, so removed
  }

  TEST_CASE("a killed run's video folder goes when it holds only the partial video") {
    // render::VideoEncoder's private folder: ".softcut-video-" + mkdtemp's six.
    const fs::path dir = test::scratch_dir("output_folder_video");
    put(dir / ".softcut-video-a1B2c3/video.mp4");      // a SIGKILLed run's: removed
    fs::create_directories(dir / ".softcut-video-Zz0099");  // empty: removed
    put(dir / ".softcut-video-q1w2e3/video.mp4");
    put(dir / ".softcut-video-q1w2e3/keep.txt");       // something else in it: kept
    put(dir / ".softcut-video-toolong7/video.mp4");    // not mkdtemp's name: kept
    put(dir / "elsewhere/video.mp4");
    fs::create_directory_symlink(dir / "elsewhere", dir / ".softcut-video-link00");  // a link: kept, not followed
    CHECK(sim::clear_earlier_outputs(dir) == 0);  // a live encoder's folder looks the same: not here
    CHECK(sim::remove_stale_video_folders(dir) == 2);
    CHECK(!fs::exists(dir / ".softcut-video-a1B2c3"));
    CHECK(!fs::exists(dir / ".softcut-video-Zz0099"));
    CHECK(fs::exists(dir / ".softcut-video-q1w2e3/video.mp4"));
    CHECK(fs::exists(dir / ".softcut-video-toolong7/video.mp4"));
    CHECK(fs::is_symlink(dir / ".softcut-video-link00"));
    CHECK(fs::exists(dir / "elsewhere/video.mp4"));
  }
}
