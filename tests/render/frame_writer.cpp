#include "render/frame_writer.hpp"

#include <doctest/doctest.h>

#include <string>

#include "core/error.hpp"
#include "mesh/generate/box.hpp"
#include "test_support.hpp"

using namespace softcut;
using Mode = render::FrameWriter::Mode;
namespace fs = std::filesystem;

namespace {

// Frames of a box bent a little more each time, small and without MSAA so
// the suite stays fast.
render::Scene frame_scene(int frame) {
  mesh::BoxOptions o;
  o.nx = 4, o.ny = 2, o.nz = 2;
  o.max_corner = {2, 1, 1};
  const mesh::TetMesh m = mesh::generate_box(o);
  Eigen::MatrixX3d x = m.nodes;
  x.col(2).array() += 0.05 * frame * m.nodes.col(0).array().square();
  render::RenderSettings s;
  s.width = 64, s.height = 48, s.msaa_samples = 0;
  s.camera.azimuth_deg = 10.0 * frame;
  return render::extract_scene(m, x, {}, s);
}

std::string png_name(int frame) { return "frame_" + std::to_string(frame) + ".png"; }

int files_in(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.is_regular_file();
  return n;
}

}  // namespace

TEST_SUITE("render/frame_writer") {
  TEST_CASE("inline and worker writers write the pixels Renderer::draw gives") {
    gl::EglContext ctx;
    std::vector<render::Image> expected;
    {
      render::Renderer r(ctx);
      for (int f = 0; f < 5; ++f) expected.push_back(r.draw(frame_scene(f)));
    }
    for (const Mode mode : {Mode::inline_draw, Mode::worker}) {
      CAPTURE(int(mode));
      const fs::path dir = test::scratch_dir(mode == Mode::worker ? "frame_writer_worker" : "frame_writer_inline");
      {
        render::FrameWriter w(ctx, mode, 2);
        CHECK(w.mode() == mode);
        CHECK(ctx.is_current() == (mode == Mode::inline_draw));  // the worker took the context
        for (int f = 0; f < 5; ++f) w.submit(frame_scene(f), dir / png_name(f));
        w.finish();
        const render::FrameWriterStats st = w.stats();
        CHECK(st.frames == 5);
        CHECK(st.work.draw_ms > 0);
        CHECK(st.work.encode_ms > 0);
        CHECK(st.max_work_ms * 5 >= st.work.total_ms());
      }
      for (int f = 0; f < 5; ++f) {
        const render::Image got = render::read_png(dir / png_name(f));
        CHECK(got.width == 64);
        CHECK_MESSAGE(got.rgba == expected[size_t(f)].rgba, "frame ", f);
      }
      CHECK(files_in(dir) == 5);  // no temporary files left behind
    }
    // The context works on this thread again after the worker let it go.
    render::Renderer again(ctx);
    CHECK(again.draw(frame_scene(1)).rgba == expected[1].rgba);
  }

  TEST_CASE("a failed frame surfaces at the next call naming the file, and later frames are not written") {
    gl::EglContext ctx;
    const fs::path dir = test::scratch_dir("frame_writer_fail");
    for (const Mode mode : {Mode::inline_draw, Mode::worker}) {
      CAPTURE(int(mode));
      const fs::path out = dir / (mode == Mode::worker ? "worker" : "inline");
      fs::create_directories(out);
      render::FrameWriter w(ctx, mode, 8);
      const fs::path bad = out / "missing-folder" / "frame.png";
      bool threw = false;
      try {
        w.submit(frame_scene(0), bad);  // inline: throws here; worker: here, at a later submit or at finish
        for (int f = 1; f < 4; ++f) w.submit(frame_scene(f), out / png_name(f));
        w.finish();
      } catch (const Error& e) {
        threw = true;
        CHECK(std::string(e.what()).find("frame " + bad.string() + ": ") == 0);
      }
      CHECK(threw);
      // Frames queued behind the failed one are dropped: the worker is
      // sequential, so none of them can have been written first.
      CHECK(files_in(out) == 0);
      if (mode == Mode::worker) {
        // The failure stays: later submits and finish() report it again.
        CHECK_THROWS_AS(w.submit(frame_scene(1), out / "later.png"), Error);
        CHECK_THROWS_AS(w.finish(), Error);
      }
    }
  }

  TEST_CASE("destroying a worker writer with frames still queued neither hangs nor leaves partial files") {
    gl::EglContext ctx;
    const fs::path dir = test::scratch_dir("frame_writer_drop");
    constexpr int kFrames = 64;
    std::vector<render::Scene> scenes;
    for (int f = 0; f < kFrames; ++f) scenes.push_back(frame_scene(f));
    {
      render::FrameWriter w(ctx, Mode::worker, kFrames);
      for (int f = 0; f < kFrames; ++f) w.submit(std::move(scenes[size_t(f)]), dir / png_name(f));
    }  // frames still queued here are dropped
    // Queueing 64 ready scenes takes microseconds, drawing one takes milliseconds.
    CHECK(files_in(dir) < kFrames);
    for (const auto& e : fs::directory_iterator(dir)) {
      CHECK(e.path().extension() == ".png");  // whole frames only, no temporary files
      CHECK(render::read_png(e.path()).width == 64);
    }
  }
}
