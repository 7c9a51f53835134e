// softcut bench render: the cost of a rendered frame against the cost of the
// simulated frame it shows, measured in the same run on the paper's ligament
// (615 nodes, operational 71 tets): rendering must not dominate a frame.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <thread>

#include "cli/bench.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "hybrid/partition.hpp"
#include "hybrid/precompute.hpp"
#include "hybrid/update.hpp"
#include "mesh/generate/band.hpp"
#include "mesh/generate/presets.hpp"
#include "render/frame_writer.hpp"

namespace softcut::cli {

int bench_render(const Args& args) {
  int frames = 60, width = 640, height = 480, samples = 4, every = 1;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() {
      if (i + 1 >= args.size()) fail("bench render: ", a, " needs a value");
      const std::string& v = args[++i];
      const int x = std::atoi(v.c_str());
      if (x < 0 || x > 8192 || std::to_string(x) != v) fail("bench render: ", a, " needs an integer, got '", v, "'");
      return x;
    };
    if (a == "--help" || a == "-h") {
      std::puts("usage: softcut bench render [--frames N] [--size W H] [--msaa S] [--every K]\n"
                "  simulates N frames (default 60) of the poked ligament and renders every K-th (1)\n"
                "  at W x H (640 x 480) with S MSAA samples (4; 0 = off): without rendering, with\n"
                "  rendering inline on the frame thread, and with a worker thread drawing and\n"
                "  writing while the next frames are simulated; reports each loop's wall time");
      return 0;
    } else if (a == "--frames") {
      frames = std::max(1, value());
    } else if (a == "--size") {
      width = value();
      height = value();
    } else if (a == "--msaa") {
      samples = value();
    } else if (a == "--every") {
      every = std::max(1, value());
    } else {
      fail("bench render: unknown option '", a, "' (see softcut bench render --help)");
    }
  }

  const mesh::TetMesh m = mesh::generate_band(mesh::ligament_preset());
  // Operational region: the 71 tets nearest the top end (the paper's 40 nodes / 71 tets).
  Eigen::Vector3d top = m.nodes.colwise().mean().transpose();
  top.z() = m.nodes.col(2).maxCoeff();
  std::vector<int> order(size_t(m.num_tets()));
  std::iota(order.begin(), order.end(), 0);
  auto dist = [&](int t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) c += m.node(m.tets(t, k));
    return (c / 4 - top).norm();
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return dist(a) < dist(b); });
  std::vector<char> op(size_t(m.num_tets()), 0);
  for (int k = 0; k < std::min(71, m.num_tets()); ++k) op[size_t(order[size_t(k)])] = 1;
  std::vector<int> fixed;
  const double zmin = m.nodes.col(2).minCoeff();
  for (int v = 0; v < m.num_nodes(); ++v)
    if (m.nodes(v, 2) < zmin + 1e-9) fixed.push_back(v);
  const auto p = hybrid::make_partition(m, op, fixed);
  const std::vector<fem::Material> mats(size_t(m.num_tets()), {3e5, 0.45});
  const hybrid::Model model = hybrid::precompute(m, mats, p);
  const int poked = p.interface.empty() ? p.surface.front() : p.interface.front();

  gpu::EglContext ctx;
  render::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.msaa_samples = samples;
  render::SceneContent content;
  content.operational = p.operational_tet;
  content.interface_nodes = p.interface;
  const auto dir = std::filesystem::temp_directory_path() / "softcut-bench-render";
  std::filesystem::create_directories(dir);

  // One pass of the frame loop: simulate every frame, render every `every`-th
  // (extraction on this thread, the rest by `writer` when given).
  struct Pass {
    double wall_ms = 0, sim_ms = 0, frame_thread_ms = 0, extract_ms = 0;
    render::FrameWriterStats writer;
  };
  auto pass = [&](render::FrameWriter* writer) {
    Pass r;
    render::SceneExtractor extractor;
    hybrid::State st = hybrid::make_state(model);
    Timer wall;
    for (int f = 0; f < frames; ++f) {
      const hybrid::Load load{poked, Eigen::Vector3d(0.02 * f / frames, 0, 0)};
      Timer t;
      hybrid::update(model, st, std::span<const hybrid::Load>(&load, 1));
      r.sim_ms += t.ms();
      if (!writer || f % every) continue;
      t.reset();
      const Eigen::MatrixX3d x = m.nodes + st.u;
      render::Scene scene = extractor.extract(m, x, content, settings);
      r.extract_ms += t.ms();
      writer->submit(std::move(scene), dir / ("frame_" + std::to_string(f % 4) + ".png"));
      r.frame_thread_ms += t.ms();
    }
    if (writer) {
      Timer t;
      writer->finish();
      r.frame_thread_ms += t.ms();
      r.writer = writer->stats();
    }
    r.wall_ms = wall.ms();
    return r;
  };
  using Mode = render::FrameWriter::Mode;
  pass(nullptr);  // warm-up: caches, page faults, first-use costs
  const Pass bare = pass(nullptr);
  // A fresh writer each (both pay the first frame's shader variants and framebuffers).
  Pass inline_pass, worker_pass;
  {
    render::FrameWriter w(ctx, Mode::inline_draw);
    inline_pass = pass(&w);
  }
  {
    render::FrameWriter w(ctx, Mode::worker);
    worker_pass = pass(&w);
  }
  std::filesystem::remove_all(dir);

  const double n = frames, nr = (frames + every - 1) / every;
  std::printf("device: %s\n", ctx.info().summary().c_str());
  std::printf("ligament %d nodes / %d tets, %dx%d, MSAA %d, %d frames, rendering every %d-th (%d)\n\n",
              m.num_nodes(), m.num_tets(), width, height, samples, frames, every, int(nr));
  std::printf("| frame loop | wall ms per frame | simulate | render on the frame thread, per rendered frame |\n"
              "|---|---|---|---|\n");
  auto row = [&](const char* name, const Pass& r) {
    std::printf("| %s | %.3f | %.3f | %.3f |\n", name, r.wall_ms / n, r.sim_ms / n, r.frame_thread_ms / nr);
  };
  row("simulate only", bare);
  row("render inline", inline_pass);
  row("render on the worker", worker_pass);
  const render::FrameTimings& w = worker_pass.writer.work;
  const double nw = std::max(1, worker_pass.writer.frames);
  std::printf("\nworker, ms per rendered frame: extract (frame thread) %.3f | upload %.3f | draw %.3f | readback %.3f |"
              " PNG encode %.3f | write %.3f | total %.3f\n",
              worker_pass.extract_ms / nr, w.upload_ms / nw, w.draw_ms / nw, w.readback_ms / nw, w.encode_ms / nw,
              w.write_ms / nw, w.total_ms() / nw);
  const double sim = std::max(bare.sim_ms / n, 1e-9);
  std::printf("\nframe-thread render / simulate: inline %.2f, worker %.2f\n", inline_pass.frame_thread_ms / nr / sim,
              worker_pass.frame_thread_ms / nr / sim);
  std::printf("wall per frame / simulate only: inline %.2f, worker %.2f (%d cores)\n", inline_pass.wall_ms / bare.wall_ms,
              worker_pass.wall_ms / bare.wall_ms, int(std::thread::hardware_concurrency()));
  return 0;
}

}  // namespace softcut::cli
