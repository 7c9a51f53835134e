#include "render/camera.hpp"

#include <doctest/doctest.h>

#include <Eigen/Geometry>
#include <random>

#include "core/error.hpp"

using namespace softcut;
using render::CameraSettings;

namespace {
std::vector<Eigen::Vector3d> corners(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::vector<Eigen::Vector3d> c;
  for (int k = 0; k < 8; ++k) c.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  return c;
}
}  // namespace

TEST_SUITE("render/camera") {
  TEST_CASE("automatic framing keeps the whole bounding box snugly in view") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Vector3d lo(u(rng), u(rng), u(rng));
      const Eigen::Vector3d hi = lo + Eigen::Vector3d(1.0 + u(rng), 1.0 + u(rng), 1.0 + u(rng)) * 0.5;
      CameraSettings cs;
      cs.margin = 1.0 + 0.2 * std::abs(u(rng));
      cs.azimuth_deg = 180.0 * u(rng);
      cs.elevation_deg = 80.0 * u(rng);
      cs.fov_y_deg = 40.0 + 30.0 * u(rng);
      cs.up = Eigen::Vector3d(u(rng), u(rng), u(rng)) + Eigen::Vector3d(0, 0, 2.0);
      const int w = 100 + int(rng() % 900), h = 100 + int(rng() % 900);
      const render::Camera cam = render::resolve_camera(cs, w, h, corners(lo, hi), {});
      double reach = 0;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d p(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z());
        const Eigen::Vector3d ndc = cam.to_ndc(p);
        CHECK(std::abs(ndc.x()) <= 1.0);
        CHECK(std::abs(ndc.y()) <= 1.0);
        CHECK(ndc.z() >= -1.0);
        CHECK(ndc.z() <= 1.0);
        reach = std::max(reach, ndc.head<2>().cwiseAbs().maxCoeff());
      }
      CHECK(reach == doctest::Approx(1.0 / cs.margin));  // snug: touches the margin
      CHECK(cam.to_ndc(0.5 * (lo + hi)).head<2>().norm() < 1e-9);  // centred
      CHECK(cam.up.dot(cam.target - cam.eye) == doctest::Approx(0.0).epsilon(1e-9));
      CHECK(cam.up.dot(cs.up) > 0);  // the model's up points up on screen
    }
  }

  TEST_CASE("every framed point is in view whatever the shape") {
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<Eigen::Vector3d> pts;
      const Eigen::Vector3d scale(g(rng), g(rng), g(rng));
      for (int i = 0; i < 100; ++i) pts.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).cwiseProduct(scale));
      CameraSettings cs;
      cs.azimuth_deg = 100 * g(rng);
      const render::Camera cam = render::resolve_camera(cs, 320, 240, pts, {});
      double reach = 0;
      for (const auto& p : pts) {
        const Eigen::Vector3d ndc = cam.to_ndc(p);
        CHECK(std::abs(ndc.z()) <= 1.0);
        reach = std::max(reach, ndc.head<2>().cwiseAbs().maxCoeff());
      }
      CHECK(reach == doctest::Approx(1.0 / cs.margin));
    }
    // Nothing to frame: still a usable camera.
    const render::Camera empty = render::resolve_camera({}, 32, 32, {}, {});
    CHECK(empty.projection.allFinite());
    CHECK(empty.view.allFinite());
  }

  TEST_CASE("the orbit angles place the eye") {
    CameraSettings cs;
    cs.azimuth_deg = 0;
    cs.elevation_deg = 0;
    const render::Camera a = render::resolve_camera(cs, 100, 100, corners({-1, -1, -1}, {1, 1, 1}), {});
    const Eigen::Vector3d d = (a.eye - a.target).normalized();
    CHECK((d - Eigen::Vector3d::UnitX()).norm() < 1e-12);  // up = z: azimuth 0 looks from +x
    cs.azimuth_deg = 90;
    cs.elevation_deg = 30;
    const render::Camera b = render::resolve_camera(cs, 100, 100, corners({-1, -1, -1}, {1, 1, 1}), {});
    const Eigen::Vector3d e = (b.eye - b.target).normalized();
    CHECK((e - Eigen::Vector3d(0, std::cos(M_PI / 6), 0.5)).norm() < 1e-12);
  }

  TEST_CASE("an explicit camera is used as given and near and far hug the content") {
    CameraSettings cs;
    cs.auto_frame = false;
    cs.eye = {0, -5, 0};
    cs.target = {0, 0, 0};
    const std::vector<Eigen::Vector3f> extra = {{0, 3, 0}};
    const render::Camera cam = render::resolve_camera(cs, 64, 48, corners({-1, -1, -1}, {1, 1, 1}), {&extra});
    CHECK(cam.eye == cs.eye);
    CHECK(cam.to_ndc({0, 0, 0}).head<2>().norm() < 1e-12);
    CHECK(cam.near == doctest::Approx(4.0 * 0.95));
    CHECK(cam.far == doctest::Approx(8.0 * 1.05));
    CHECK(cam.aspect == doctest::Approx(64.0 / 48.0));
    // OpenGL convention: the target lies down -z in eye space.
    CHECK((cam.view * Eigen::Vector4d(0, 0, 0, 1)).z() == doctest::Approx(-5.0));
  }

  TEST_CASE("impossible cameras are refused with the reason") {
    CameraSettings cs;
    cs.fov_y_deg = 180;
    CHECK_THROWS_WITH_AS(render::resolve_camera(cs, 10, 10, corners({0, 0, 0}, {1, 1, 1}), {}),
                         doctest::Contains("fov_y_deg = 180"), Error);
    cs = {};
    cs.auto_frame = false;
    cs.eye = {0, 0, 5};
    cs.target = {0, 0, 0};
    CHECK_THROWS_WITH_AS(render::resolve_camera(cs, 10, 10, corners({0, 0, 0}, {1, 1, 1}), {}),
                         doctest::Contains("parallel to the view direction"), Error);
    cs.eye = cs.target;
    CHECK_THROWS_WITH_AS(render::resolve_camera(cs, 10, 10, corners({0, 0, 0}, {1, 1, 1}), {}),
                         doctest::Contains("coincide"), Error);
  }
}
