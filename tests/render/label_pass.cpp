// The depth and label images (Renderer::draw with LabelImages), checked
// against rays cast through each pixel's centre onto the scene's triangles on
// the CPU: no GL in the reference.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "gl/egl_context.hpp"
#include "mesh/generate/box.hpp"
#include "render/gray_png.hpp"
#include "render/renderer.hpp"

using namespace softcut;

namespace {

gl::EglContext& shared_context() {
  static auto* ctx = new gl::EglContext();
  return *ctx;
}
render::Renderer& shared_renderer() {
  static auto* r = new render::Renderer(shared_context());
  return *r;
}

struct Hit {
  double t = std::numeric_limits<double>::infinity();  // along the unit ray, m
  double edge = 0;        // smallest barycentric coordinate of the hit
  std::uint32_t label = 0;
  double second = std::numeric_limits<double>::infinity();  // the next hit's distance (another label)
};

// First front-facing hit (counter-clockwise seen from the ray's origin) of
// the ray o + t d among the triangles.
void cast(const render::Triangles& tri, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Hit& best) {
  for (int k = 0; k < tri.count(); ++k) {
    const Eigen::Vector3d a = tri.positions[size_t(3 * k)].cast<double>(), b = tri.positions[size_t(3 * k + 1)].cast<double>(),
                          c = tri.positions[size_t(3 * k + 2)].cast<double>();
    const Eigen::Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
    const double det = e1.dot(p);
    if (det <= 0) continue;  // back face (culled) or edge-on
    const Eigen::Vector3d s = o - a;
    const double u = s.dot(p) / det;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det, t = e2.dot(q) / det;
    if (u < 0 || v < 0 || u + v > 1 || t <= 0) continue;
    const std::uint32_t label = tri.labels[size_t(3 * k)];
    if (t < best.t) {
      if (label != best.label) best.second = best.t;
      best.t = t, best.label = label, best.edge = std::min({u, v, 1 - u - v});
    } else if (label != best.label) {
      best.second = std::min(best.second, t);
    }
  }
}

}  // namespace

TEST_SUITE("render/label_pass") {
  TEST_CASE("each pixel's label and depth are those of the first triangle its centre's ray hits") {
    // A jittered, bent block of three tissue groups, one cut face patch and
    // two tools in front of it; 4x MSAA on the colour frame.
    mesh::BoxOptions bo;
    bo.nx = 6, bo.ny = 4, bo.nz = 3;
    bo.max_corner = {0.1, 0.06, 0.04};
    bo.jitter = 0.2;
    const mesh::TetMesh m = mesh::generate_box(bo);
    Eigen::MatrixX3d x = m.nodes;
    for (int v = 0; v < x.rows(); ++v) x(v, 2) += 0.01 * std::sin(30 * x(v, 0)) * x(v, 1) / 0.06;
    render::SceneContent c;
    c.tet_group.resize(size_t(m.num_tets()));
    c.cut_faces.assign(size_t(4 * m.num_tets()), 0);
    for (int t = 0; t < m.num_tets(); ++t) {
      Eigen::Vector3d ctr = Eigen::Vector3d::Zero();
      for (int k = 0; k < 4; ++k) ctr += m.node(m.tets(t, k)) / 4;
      c.tet_group[size_t(t)] = ctr.x() < 0.04 ? 0 : ctr.y() < 0.03 ? 1 : 2;
      if (ctr.x() > 0.07 && ctr.y() > 0.04)
        for (int f = 0; f < 4; ++f) c.cut_faces[size_t(4 * t + f)] = 1;  // boundary faces of these tets: "cut"
    }
    c.group_labels = {3, 5, 7};
    c.cut_label = 9;
    c.tools.push_back(render::ProbeShape{{0.03, 0.02, 0.06}, {0, -0.3, 1}, 0.006, 0.05});
    render::GrasperShape g;
    g.pivot = {0.07, 0.03, 0.07};
    g.axis = {0.2, 0, -1};
    g.hinge = {0, 1, 0};
    g.jaw_length = 0.015;
    g.jaw_width = 0.005;
    c.tools.push_back(g);
    c.tool_labels = {11, 12};
    render::RenderSettings s;
    s.width = 160;
    s.height = 120;
    s.msaa_samples = 4;
    s.style = render::Style::clinical;
    s.camera.azimuth_deg = -50;
    s.camera.elevation_deg = 35;
    const render::Scene scene = render::extract_scene(m, x, c, s);
    render::LabelImages aux;
    render::FrameTimings timings;
    const render::Image img = shared_renderer().draw(scene, &timings, &aux);
    REQUIRE(aux.width == 160);
    REQUIRE(aux.height == 120);
    REQUIRE(aux.labels.size() == size_t(160 * 120));
    CHECK(img.width == 160);
    CHECK(timings.labels_draw_ms > 0);

    // Rays through pixel centres from the camera's inverse matrices.
    const Eigen::Matrix4d inv = (scene.camera.projection * scene.camera.view).inverse();
    const Eigen::Vector3d eye = scene.camera.eye;
    const Eigen::Vector3d fwd = (scene.camera.target - eye).normalized();
    int checked = 0, wrong_label = 0, wrong_depth = 0, ambiguous = 0;
    std::map<std::uint32_t, int> seen;
    for (int py = 0; py < aux.height; ++py)
      for (int px = 0; px < aux.width; ++px) {
        const double nx = 2.0 * (px + 0.5) / aux.width - 1.0, ny = 1.0 - 2.0 * (py + 0.5) / aux.height;
        const Eigen::Vector4d far = inv * Eigen::Vector4d(nx, ny, 1.0, 1.0);
        const Eigen::Vector3d d = (far.head<3>() / far.w() - eye).normalized();
        Hit h;
        cast(scene.tissue, eye, d, h);
        cast(scene.wound, eye, d, h);
        cast(scene.tools, eye, d, h);
        const size_t i = size_t(py) * size_t(aux.width) + size_t(px);
        // A ray that grazes a triangle's edge, or meets two labels at about
        // the same depth, may fall either way in the rasteriser.
        if ((std::isfinite(h.t) && h.edge < 2e-3) || std::abs(h.second - h.t) < 1e-5) {
          ++ambiguous;
          continue;
        }
        ++checked;
        const std::uint32_t want = std::isfinite(h.t) ? h.label : 0;
        seen[want]++;
        if (aux.labels[i] != want) ++wrong_label;
        const double want_depth = std::isfinite(h.t) ? h.t * d.dot(fwd) : 0.0;
        if (std::abs(double(aux.depth[i]) - want_depth) > 1e-6 + 1e-5 * want_depth) ++wrong_depth;
      }
    CAPTURE(checked);
    CAPTURE(ambiguous);
    CHECK(ambiguous < checked / 20);
    CHECK(wrong_label == 0);
    CHECK(wrong_depth == 0);
    // Every kind of surface was there to be checked.
    for (std::uint32_t id : {0u, 3u, 5u, 7u, 9u, 11u, 12u}) {
      CAPTURE(id);
      CHECK(seen[id] > 10);
    }
  }

  TEST_CASE("depth and label PNGs: millimetres x 10 in 16 bits, ids in 8, read back by another decoder") {
    render::LabelImages aux;
    aux.width = 3, aux.height = 2;
    aux.depth = {0.0f, 0.1234f, 1.0f, 6.5535f, 7.0f, 0.00004f};
    aux.labels = {0, 1, 2, 3, 254, 255};
    const render::GrayImage16 d = render::decode_gray_png(render::encode_png(render::depth_image(aux)), "depth");
    REQUIRE(d.pixels.size() == 6);
    CHECK(d.pixels[0] == 0);
    CHECK(d.pixels[1] == 1234);   // 123.4 mm
    CHECK(d.pixels[2] == 10000);  // 1 m
    CHECK(d.pixels[3] == 65535);  // 6553.5 mm
    CHECK(d.pixels[4] == 65535);  // beyond: saturated
    CHECK(d.pixels[5] == 0);      // 0.04 mm rounds to nothing
    const render::GrayImage16 l = render::decode_gray_png(render::encode_png(render::label_image(aux)), "labels");
    REQUIRE(l.pixels.size() == 6);
    for (size_t i = 0; i < 6; ++i) CHECK(l.pixels[i] == aux.labels[i]);
  }
}
