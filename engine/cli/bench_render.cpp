// softcut bench render: the cost of a rendered frame against the cost of the
// simulated frame it shows, measured in the same run on the paper's ligament
// (615 nodes, operational 71 tets): rendering must not dominate a frame.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <numeric>

#include "cli/bench.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "hybrid/partition.hpp"
#include "hybrid/precompute.hpp"
#include "hybrid/update.hpp"
#include "mesh/generate/band.hpp"
#include "mesh/generate/presets.hpp"
#include "render/renderer.hpp"

namespace softcut::cli {

int bench_render(const Args& args) {
  int frames = 30, width = 640, height = 480, samples = 4;
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
      std::puts("usage: softcut bench render [--frames N] [--size W H] [--msaa S]\n"
                "  renders N frames (default 30) of the deforming ligament at W x H (640 x 480)\n"
                "  with S MSAA samples (4; 0 = off) and compares with the simulated frame time");
      return 0;
    } else if (a == "--frames") {
      frames = std::max(1, value());
    } else if (a == "--size") {
      width = value();
      height = value();
    } else if (a == "--msaa") {
      samples = value();
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
  hybrid::State state = hybrid::make_state(model);
  const int poked = p.interface.empty() ? p.surface.front() : p.interface.front();

  gpu::EglContext ctx;
  render::Renderer renderer(ctx);
  render::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.msaa_samples = samples;
  render::SceneContent content;
  content.operational = p.operational_tet;
  content.interface_nodes = p.interface;
  const auto dir = std::filesystem::temp_directory_path() / "softcut-bench-render";
  std::filesystem::create_directories(dir);

  double sim_ms = 0;
  render::FrameTimings sum;
  for (int f = 0; f < frames; ++f) {
    const hybrid::Load load{poked, Eigen::Vector3d(0.02 * f / frames, 0, 0)};
    Timer t;
    hybrid::update(model, state, std::span<const hybrid::Load>(&load, 1));
    sim_ms += t.ms();
    const Eigen::MatrixX3d x = m.nodes + state.u;
    sum += renderer.render_png(m, x, content, settings, dir / "frame.png");
  }
  std::filesystem::remove_all(dir);
  const double n = frames;
  std::printf("device: %s\n", ctx.info().summary().c_str());
  std::printf("ligament %d nodes / %d tets, %dx%d, MSAA %d, %d frames\n\n", m.num_nodes(), m.num_tets(), width,
              height, samples, frames);
  std::printf("| stage | ms per frame |\n|---|---|\n");
  std::printf("| simulate (hybrid update) | %.3f |\n", sim_ms / n);
  std::printf("| render: extract | %.3f |\n| render: upload | %.3f |\n| render: draw | %.3f |\n", sum.extract_ms / n,
              sum.upload_ms / n, sum.draw_ms / n);
  std::printf("| render: readback | %.3f |\n| render: PNG encode | %.3f |\n| render: write | %.3f |\n",
              sum.readback_ms / n, sum.encode_ms / n, sum.write_ms / n);
  std::printf("| render total | %.3f |\n\nrender / simulate = %.1f\n", sum.total_ms() / n,
              sum.total_ms() / std::max(sim_ms, 1e-9));
  return 0;
}

}  // namespace softcut::cli
