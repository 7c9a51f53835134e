// softcut run --depth --labels --video and softcut render through the CLI:
// images checked against the geometry of the run (its VTU export read by
// meshio), the video by ffprobe, the redraw byte for byte.
#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <fstream>
#include <map>
#include <set>

#include "cli_test_support.hpp"
#include "render/gray_png.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::run_cli;
using softcut::test::slurp;
using V = Eigen::Vector3d;

namespace {

// A soft block of two materials pressed by a probe and pulled by a grasper,
// every frame rendered small; VTU every frame (the geometry the test checks
// the images against).
fs::path write_scenario(const fs::path& dir, const std::string& render_extra = "") {
  std::ofstream(dir / "block.lua")
      << "local s = softcut.scenario{ name = 'block', duration = 0.3, fps = 20 }\n"
         "s:mesh{ generate = 'box', options = { max = { 0.1, 0.06, 0.04 }, nx = 8, ny = 5, nz = 4, jitter = 0.15 } }\n"
         "s:material{ name = 'tissue', young = 5e3, poisson = 0.4 }\n"
         "s:material{ name = 'lesion', box = { min = { 0.05, 0, 0 }, max = { 1, 1, 1 } }, young = 2e4, poisson = 0.4 }\n"
         "s:fix{ nodes = softcut.select.box{ min = { -1, -1, -1 }, max = { 0, 1, 1 } } }\n"
         "s:probe{ name = 'probe', radius = 0.006, force = softcut.ramp.constant(0.03), path = softcut.path.polyline{ times = { 0, 0.3 },\n"
         "         points = { { 0.03, 0.03, 0.0445 }, { 0.03, 0.03, 0.043 } } } }\n"
         "s:grasper{ name = 'jaw', radius = 0.007, stiffness = 200, path = softcut.path.polyline{ times = { 0, 0.3 },\n"
         "           points = { { 0.08, 0.03, 0.041 }, { 0.085, 0.03, 0.05 } } } }\n"
         "s:output{ vtu = true, render = { width = 160, height = 120, elevation = 40, azimuth = -50"
      << render_extra << " } }\nreturn s\n";
  return dir / "block.lua";
}

struct Camera {
  double fx, fy, cx, cy, scale;
  int width, height;
  std::map<int, std::pair<Eigen::Matrix3d, V>> frames;  // frame -> (R, t)
  std::map<std::string, int> ids;                       // legend name -> id
};

Camera read_camera(const fs::path& file) {
  const auto j = softcut::test::read_json(file);
  Camera c;
  c.fx = j.at("fx"), c.fy = j.at("fy"), c.cx = j.at("cx"), c.cy = j.at("cy");
  c.width = j.at("width"), c.height = j.at("height");
  c.scale = j.at("depth").at("scale");
  for (const auto& f : j.at("frames")) {
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) R(r, k) = f.at("R").at(r).at(k);
    c.frames[f.at("frame")] = {R, V(f.at("t").at(0), f.at("t").at(1), f.at("t").at(2))};
  }
  for (const auto& e : j.at("labels").at("legend")) c.ids[e.at("name")] = e.at("id");
  return c;
}

// The deformed boundary of the frame's tet mesh, from the VTU read by meshio:
// each tet face that no other tet shares, wound outward, with its tet.
struct Surface {
  std::vector<std::array<V, 3>> tri;
  std::vector<int> tet;
};

Surface deformed_surface(const softcut::test::ForeignArrays& vtu) {
  const auto& p = vtu.arrays.at("points");
  const auto& u = vtu.arrays.at("point.displacement");
  const auto& t = vtu.arrays.at("tetra");
  auto x = [&](int n) { return V(p[3 * n] + u[3 * n], p[3 * n + 1] + u[3 * n + 1], p[3 * n + 2] + u[3 * n + 2]); };
  auto rest = [&](int n) { return V(p[3 * n], p[3 * n + 1], p[3 * n + 2]); };
  std::map<std::array<int, 3>, std::pair<int, int>> faces;  // sorted corners -> (count, tet*4+face)
  const int nt = int(t.size() / 4);
  for (int e = 0; e < nt; ++e)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> k;
      for (int i = 0, j = 0; i < 4; ++i)
        if (i != f) k[size_t(j++)] = int(t[size_t(4 * e + i)]);
      std::sort(k.begin(), k.end());
      auto& slot = faces[k];
      slot.first++, slot.second = 4 * e + f;
    }
  Surface s;
  for (const auto& [k, v] : faces) {
    if (v.first != 1) continue;
    const int e = v.second / 4, f = v.second % 4;
    std::array<int, 3> c;
    for (int i = 0, j = 0; i < 4; ++i)
      if (i != f) c[size_t(j++)] = int(t[size_t(4 * e + i)]);
    const V opp = rest(int(t[size_t(4 * e + f)]));
    // Outward in the rest shape: away from the tet's fourth corner.
    if ((rest(c[1]) - rest(c[0])).cross(rest(c[2]) - rest(c[0])).dot(opp - rest(c[0])) > 0) std::swap(c[1], c[2]);
    s.tri.push_back({x(c[0]), x(c[1]), x(c[2])});
    s.tet.push_back(e);
  }
  return s;
}

// Distance from q to triangle (a, b, c), m.
double distance_to_triangle(const V& q, const V& a, const V& b, const V& c) {
  const V n = (b - a).cross(c - a).normalized();
  const V proj = q - n.dot(q - a) * n;
  const V e[3] = {b - a, c - b, a - c}, o[3] = {a, b, c};
  bool inside = true;
  for (int i = 0; i < 3; ++i) inside &= e[i].cross(proj - o[i]).dot(n) >= 0;
  if (inside) return std::abs(n.dot(q - a));
  double best = 1e9;
  for (int i = 0; i < 3; ++i) {
    const double s = std::clamp(e[i].dot(q - o[i]) / e[i].squaredNorm(), 0.0, 1.0);
    best = std::min(best, (q - (o[i] + s * e[i])).norm());
  }
  return best;
}

}  // namespace

TEST_SUITE("app/cmd_render") {
  TEST_CASE("depth pixels unproject onto the deformed surface and each label is the first surface a pixel's ray hits") {
    const fs::path dir = softcut::test::scratch_dir("render_geometry");
    write_scenario(dir);
    const auto r = run_cli("run block.lua --depth --labels --out out -q", dir);
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const Camera cam = read_camera(dir / "out" / "camera.json");
    CHECK(cam.width == 160);
    CHECK(cam.cx == 79.5);
    for (const int frame : {0, 6}) {
      CAPTURE(frame);
      char name[32];
      std::snprintf(name, sizeof name, "%06d", frame);
      const auto depth = softcut::render::decode_gray_png(slurp(dir / "out" / "frames" / ("depth_" + std::string(name) + ".png")), "depth");
      const auto labels = softcut::render::decode_gray_png(slurp(dir / "out" / "frames" / ("labels_" + std::string(name) + ".png")), "labels");
      const auto vtu = softcut::test::read_vtu_with_meshio(dir / "out" / "vtu" / ("frame_" + std::string(name) + ".vtu"));
      const Surface surf = deformed_surface(vtu);
      const auto& material = vtu.arrays.at("cell.material");
      const auto& [R, t] = cam.frames.at(frame);
      const V centre = -R.transpose() * t;
      const std::set<int> tools = {cam.ids.at("probe"), cam.ids.at("jaw")};
      int on_surface = 0, off_surface = 0, label_ok = 0, label_bad = 0, tool_in_front = 0, tool_behind = 0, skipped = 0;
      std::map<int, int> seen;
      for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
          const size_t i = size_t(v) * size_t(cam.width) + size_t(u);
          const int label = labels.pixels[i];
          seen[label]++;
          // The ray through the pixel's centre, and the first surface triangle it meets.
          const V dir_cam((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
          const V d = (R.transpose() * dir_cam).normalized();
          double best = 1e9, edge = 1;
          int hit = -1;
          for (size_t k = 0; k < surf.tri.size(); ++k) {
            const auto& [a, b, c] = surf.tri[k];
            const V e1 = b - a, e2 = c - a, p = d.cross(e2);
            const double det = e1.dot(p);
            if (std::abs(det) < 1e-18) continue;
            const V s = centre - a;
            const double bu = s.dot(p) / det, bv = d.dot(s.cross(e1)) / det, bt = e2.dot(s.cross(e1)) / det;
            if (bu < 0 || bv < 0 || bu + bv > 1 || bt <= 0 || bt >= best) continue;
            best = bt, hit = int(k), edge = std::min({bu, bv, 1 - bu - bv});
          }
          const double z_ray = hit >= 0 ? best * d.dot(R.row(2).transpose()) : 0;
          if (tools.count(label)) {
            // An instrument: nearer than any tissue along the ray.
            const double z = depth.pixels[i] / cam.scale / 1000.0;
            (hit < 0 || z <= z_ray + 1e-4 ? tool_in_front : tool_behind)++;
            continue;
          }
          if (hit >= 0 && edge < 0.02) {  // the ray grazes an edge between two faces: either may win
            ++skipped;
            continue;
          }
          // The label: the hit face's material (legend by name), or background.
          const int want = hit < 0 ? 0 : cam.ids.at(material[size_t(surf.tet[size_t(hit)])] == 0 ? "tissue" : "lesion");
          (label == want ? label_ok : label_bad)++;
          if (depth.pixels[i] == 0) continue;
          // The depth pixel unprojected: on the deformed surface, within the pixel's footprint.
          const double z = depth.pixels[i] / cam.scale / 1000.0;
          const V world = R.transpose() * (z * dir_cam - t);
          double dist = 1e9;
          for (const auto& [a, b, c] : surf.tri) dist = std::min(dist, distance_to_triangle(world, a, b, c));
          const double footprint = z / cam.fx + 0.5 / cam.scale / 1000.0;  // a pixel's width there, plus rounding
          (dist <= footprint ? on_surface : off_surface)++;
        }
      CAPTURE(skipped);
      CHECK(label_bad == 0);
      CHECK(label_ok > 1000);
      CHECK(off_surface == 0);
      CHECK(on_surface > 1000);
      CHECK(tool_behind == 0);
      CHECK(tool_in_front > 20);
      CHECK(seen[cam.ids.at("tissue")] > 100);
      CHECK(seen[cam.ids.at("lesion")] > 100);
      CHECK(seen[0] > 100);
    }
  }

  TEST_CASE("softcut render redraws the run's frames byte for byte, and another camera gives other frames") {
    const fs::path dir = softcut::test::scratch_dir("render_redraw");
    write_scenario(dir);
    REQUIRE(run_cli("run block.lua --out out -q", dir).status == 0);
    REQUIRE(fs::exists(dir / "out" / "render_record.bin"));
    const auto again = run_cli("render out", dir);
    REQUIRE_MESSAGE(again.status == 0, again.output);
    CHECK(contains(again.output, "block: 7 frames redrawn"));
    int frames = 0;
    for (const auto& e : fs::directory_iterator(dir / "out" / "frames")) {
      const fs::path twin = dir / "out" / "rendered" / "frames" / e.path().filename();
      CAPTURE(e.path().filename().string());
      CHECK(slurp(e.path()) == slurp(twin));
      ++frames;
    }
    CHECK(frames == 7);
    CHECK(slurp(dir / "out" / "contact_sheet.png") == slurp(dir / "out" / "rendered" / "contact_sheet.png"));
    CHECK(slurp(dir / "out" / "camera.json") == slurp(dir / "out" / "rendered" / "camera.json"));

    const auto moved = run_cli("render out --eye 0.05,-0.12,0.12 --target 0.05,0.03,0.02 --fov 40 --out moved -q", dir);
    REQUIRE_MESSAGE(moved.status == 0, moved.output);
    CHECK(slurp(dir / "out" / "frames" / "frame_000003.png") != slurp(dir / "moved" / "frames" / "frame_000003.png"));
    const auto j = softcut::test::read_json(dir / "moved" / "camera.json");
    CHECK(j.at("fov_y_deg") == 40.0);
    // The camera's centre -R^T t is the eye asked for.
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) R(r, k) = j.at("frames").at(0).at("R").at(r).at(k);
    const auto& tj = j.at("frames").at(0).at("t");
    const V eye = -R.transpose() * V(tj.at(0), tj.at(1), tj.at(2));
    CHECK((eye - V(0.05, -0.12, 0.12)).norm() < 1e-9);
    // A different size, the debug style, depth and labels from the same record.
    const auto big = run_cli("render out --size 200x100 --style debug --depth --labels --out big -q", dir);
    REQUIRE_MESSAGE(big.status == 0, big.output);
    CHECK(fs::exists(dir / "big" / "frames" / "depth_000006.png"));
    CHECK(fs::exists(dir / "big" / "frames" / "labels_000006.png"));
    CHECK(softcut::test::read_json(dir / "big" / "camera.json").at("width") == 200);
  }

  TEST_CASE("softcut render refuses what it cannot do, naming why") {
    const fs::path dir = softcut::test::scratch_dir("render_refuse");
    write_scenario(dir, ", record = false");
    REQUIRE(run_cli("run block.lua --out out -q", dir).status == 0);
    CHECK_FALSE(fs::exists(dir / "out" / "render_record.bin"));
    const auto none = run_cli("render out", dir);
    CHECK(none.status == 1);
    CHECK(contains(none.output, "render_record.bin: missing"));
    CHECK(contains(none.output, "--record"));
    REQUIRE(run_cli("run block.lua --record --out rec -q", dir).status == 0);
    const auto self = run_cli("render rec --out rec", dir);
    CHECK(self.status == 2);
    CHECK(contains(self.output, "the run's own folder"));
    const auto half = run_cli("render rec --eye 0,0,1", dir);
    CHECK(half.status == 2);
    CHECK(contains(half.output, "--eye and --target together"));
    // A record cut short (a run killed while writing) or tampered with: an error naming the file.
    std::string bytes = slurp(dir / "rec" / "render_record.bin");
    std::ofstream(dir / "rec" / "render_record.bin", std::ios::binary | std::ios::trunc).write(bytes.data(),
                                                                                              std::streamsize(bytes.size() / 2));
    const auto cut = run_cli("render rec --out x", dir);
    CHECK(cut.status == 1);
    CHECK(contains(cut.output, "render_record.bin: chunk"));
    fs::remove(dir / "rec" / "render_record.bin");
    fs::create_symlink(dir / "out" / "summary.json", dir / "rec" / "render_record.bin");
    const auto link = run_cli("render rec --out x", dir);
    CHECK(link.status == 1);
    CHECK(contains(link.output, "symbolic link"));
  }

  TEST_CASE("--video writes an H.264 MP4 that ffprobe reads with the frames' count, size and rate") {
    const fs::path dir = softcut::test::scratch_dir("render_video");
    write_scenario(dir, ", every = 2");
    REQUIRE_MESSAGE(softcut::test::run_cli_raw("command -v ffprobe").status == 0,
                    "ffmpeg is not installed: scripts/install-deps.sh --test installs it");
    const auto r = run_cli("run block.lua --video --out out -q", dir);
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const auto probe = softcut::test::run_cli_raw(
        "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
        "stream=codec_name,width,height,r_frame_rate,nb_read_frames,pix_fmt -of default=noprint_wrappers=1 '" +
        (dir / "out" / "video.mp4").string() + "'");
    REQUIRE(probe.status == 0);
    CHECK(contains(probe.output, "codec_name=h264"));
    CHECK(contains(probe.output, "width=160"));
    CHECK(contains(probe.output, "height=120"));
    CHECK(contains(probe.output, "r_frame_rate=10/1"));  // 20 fps, every 2nd frame
    CHECK(contains(probe.output, "nb_read_frames=4"));   // frames 0, 2, 4, 6
    CHECK(contains(probe.output, "pix_fmt=yuv420p"));
    CHECK(softcut::test::read_json(dir / "out" / "summary.json").at("outputs").at("video") == "video.mp4");
    // The redraw at an odd size: padded to even for H.264.
    const auto odd = run_cli("render out --size 99x71 --video --out odd -q", dir);
    REQUIRE_MESSAGE(odd.status == 0, odd.output);
    const auto p2 = softcut::test::run_cli_raw("ffprobe -v error -select_streams v:0 -show_entries stream=width,height "
                                               "-of default=noprint_wrappers=1 '" + (dir / "odd" / "video.mp4").string() + "'");
    CHECK(contains(p2.output, "width=100"));
    CHECK(contains(p2.output, "height=72"));
    // Without ffmpeg, --video says how to install it.
    const auto missing = run_cli("run block.lua --video --out none -q", dir, "SOFTCUT_FFMPEG=/nonexistent/ffmpeg");
    CHECK(missing.status == 1);
    CHECK(contains(missing.output, "apt-get install ffmpeg"));
  }
}
