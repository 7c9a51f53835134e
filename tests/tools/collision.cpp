#include "tools/collision.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "mesh/generate/box.hpp"

using V = Eigen::Vector3d;
namespace mesh = softcut::mesh;
namespace tools = softcut::tools;

TEST_SUITE("tools/collision") {
  TEST_CASE("closest point on a triangle matches dense sampling") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 50; ++trial) {
      const V a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng)), p(2 * u(rng), 2 * u(rng), 2 * u(rng));
      const double d = (tools::closest_point_on_triangle(p, a, b, c) - p).norm();
      double best = 1e300;
      const int n = 200;
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          const V q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
          best = std::min(best, (q - p).norm());
        }
      CHECK(d <= best + 1e-12);
      CHECK(d >= best - 0.02);  // sampling resolution
    }
  }

  TEST_CASE("contact uses the deformed surface, not the rest one") {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 4;
    const mesh::TetMesh m = mesh::generate_box(o);
    const mesh::Surface s = mesh::extract_surface(m);
    // Deformation: the top face (z = 1) is lifted by 0.3 m.
    Eigen::MatrixX3d x = m.nodes;
    for (int n = 0; n < m.num_nodes(); ++n)
      if (m.nodes(n, 2) > 1 - 1e-12) x(n, 2) += 0.3;
    const Eigen::MatrixX3d normals = mesh::vertex_normals(m, s, x);
    const tools::ContactSurface deformed{x, s, normals};
    const tools::ContactSurface rest{m.nodes, s, normals};
    // Tip at the lifted centre of the top face, radius just over one cell.
    const V tip(0.5, 0.5, 1.3);
    const std::vector<int> hit = tools::nodes_in_sphere(deformed, tip, 0.26);
    // Within 0.26 of the centre on the 5 x 5 top grid (spacing 0.25): the centre and its 4 neighbours.
    REQUIRE(hit.size() == 5);
    for (int n : hit) CHECK(m.nodes(n, 2) == doctest::Approx(1.0));
    CHECK(std::is_sorted(hit.begin(), hit.end()));
    CHECK(tools::nodes_in_sphere(rest, tip, 0.26).empty());
  }

  TEST_CASE("a tip smaller than the faces touching a face picks that face's nodes") {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 1;
    const mesh::TetMesh m = mesh::generate_box(o);
    const mesh::Surface s = mesh::extract_surface(m);
    const Eigen::MatrixX3d normals = mesh::vertex_normals(m, s);
    const tools::ContactSurface rest{m.nodes, s, normals};
    const std::vector<int> hit = tools::nodes_in_sphere(rest, V(0.3, 0.6, 1.01), 0.02);
    REQUIRE(hit.size() == 3);
    for (int n : hit) CHECK(m.nodes(n, 2) == 1.0);
    CHECK(tools::nodes_in_sphere(rest, V(0.3, 0.6, 1.05), 0.02).empty());
  }

  TEST_CASE("a jaw's patch covers its disc on the surface, the same points whatever the mesh") {
    // The top face z = 1 of unit boxes meshed 2, 4 and 16 cells a side: the
    // patch's points lie on it, bound by convex weights, at the same places.
    const V center(0.43, 0.57, 1.02);
    const double r = 0.1;
    std::vector<V> first;
    for (int cells : {2, 4, 16}) {
      CAPTURE(cells);
      mesh::BoxOptions o;
      o.nx = o.ny = o.nz = cells;
      const mesh::TetMesh m = mesh::generate_box(o);
      const mesh::Surface s = mesh::extract_surface(m);
      const Eigen::MatrixX3d normals = mesh::vertex_normals(m, s);
      const tools::ContactSurface rest{m.nodes, s, normals};
      const std::vector<tools::SurfacePoint> patch = tools::surface_patch(rest, center, r);
      // The nearest point and rings of 6 and 12, all on the face, then the top
      // nodes within r of the nearest point.
      int inside = 0;
      for (int n = 0; n < m.num_nodes(); ++n)
        inside += m.nodes(n, 2) == 1.0 && (V(m.nodes.row(n).transpose()) - V(0.43, 0.57, 1.0)).norm() <= r;
      REQUIRE(patch.size() == size_t(19 + inside));
      CHECK(inside >= (cells == 16 ? 9 : 1));  // (0.5, 0.5) lies 0.099 from the centre
      std::vector<V> at;
      for (const auto& p : patch) {
        CHECK(p.weights.minCoeff() >= 0);
        CHECK(p.weights.sum() == doctest::Approx(1.0).epsilon(1e-14));
        for (int n : p.nodes) CHECK(m.nodes(n, 2) == 1.0);
        at.push_back(p.at(m.nodes));
        CHECK(at.back().z() == doctest::Approx(1.0).epsilon(1e-14));
        CHECK((at.back() - V(0.43, 0.57, 1.0)).norm() <= r * (1 + 1e-12));
      }
      CHECK((at[0] - V(0.43, 0.57, 1.0)).norm() <= 1e-14);  // the nearest point first
      if (first.empty()) first = at;
      for (size_t i = 0; i < 19; ++i) CHECK((at[i] - first[i]).norm() <= 1e-12);
    }
  }

  TEST_CASE("a jaw smaller than the faces holds the triangle under it, and a jaw off the surface nothing") {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 1;
    const mesh::TetMesh m = mesh::generate_box(o);
    const mesh::Surface s = mesh::extract_surface(m);
    const Eigen::MatrixX3d normals = mesh::vertex_normals(m, s);
    const tools::ContactSurface rest{m.nodes, s, normals};
    const std::vector<tools::SurfacePoint> patch = tools::surface_patch(rest, V(0.3, 0.6, 1.01), 0.02);
    REQUIRE(!patch.empty());
    std::vector<int> nodes;
    for (const auto& p : patch) {
      nodes.insert(nodes.end(), p.nodes.begin(), p.nodes.end());
      CHECK((p.at(m.nodes) - V(0.3, 0.6, 1.0)).norm() <= 0.02 * (1 + 1e-12));
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    CHECK(nodes.size() == 3);  // one triangle of the top face
    for (int n : nodes) CHECK(m.nodes(n, 2) == 1.0);
    CHECK(tools::surface_patch(rest, V(0.3, 0.6, 1.05), 0.02).empty());
    // At an edge of the body the samples past it are dropped, the rest kept.
    const std::vector<tools::SurfacePoint> edge = tools::surface_patch(rest, V(1.0, 0.5, 1.0), 0.2);
    CHECK(edge.size() >= 7);
    for (const auto& p : edge) CHECK((p.at(m.nodes) - V(1.0, 0.5, 1.0)).norm() <= 0.2 * (1 + 1e-12) + 1e-12);
  }

  TEST_CASE("a probe's load moves continuously: a node at the contact's rim, a nearest point on an edge") {
    // The top face of a unit box of 8 cells a side (nodes every 0.125), with
    // a ridge: the top nodes on x = 0.625 raised by 0.02, so the faces on
    // either side of it slope away from it. The load a patch puts on each node:
    // sum of share x barycentric weight, over the sum of shares (what
    // update_tool applies). An equal split over the points fails the first
    // check (a node entering moves 1/n of the load), the faces' own normals
    // the second (the face named on the ridge turns the tangent plane).
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 8;
    const mesh::TetMesh m = mesh::generate_box(o);
    const mesh::Surface s = mesh::extract_surface(m);
    Eigen::MatrixX3d x = m.nodes;
    for (int n = 0; n < m.num_nodes(); ++n)
      if (x(n, 2) == 1.0 && std::abs(x(n, 0) - 0.625) < 1e-12) x(n, 2) += 0.02;
    const Eigen::MatrixX3d normals = mesh::vertex_normals(m, s, x);
    const tools::ContactSurface surf{x, s, normals};
    // The same surface with its faces listed the other way round: where two
    // faces are as near (a point on their edge), the search names the other.
    mesh::Surface s_rev = s;
    s_rev.faces = s.faces.colwise().reverse().eval();
    const tools::ContactSurface surf_rev{x, s_rev, normals};
    auto load = [&](const V& center, double radius, bool reversed = false) {
      std::map<int, double> on;
      double shares = 0;
      for (const auto& p : tools::surface_patch(reversed ? surf_rev : surf, center, radius, true)) {
        CHECK(p.share > 0);
        CHECK(p.share <= 1);
        shares += p.share;
        for (int k = 0; k < 3; ++k) on[p.nodes[size_t(k)]] += p.share * p.weights(k);
      }
      for (auto& [n, f] : on) f /= shares;
      return on;
    };
    auto distance = [](const std::map<int, double>& a, const std::map<int, double>& b) {
      double d = 0;
      for (const auto& [n, f] : a) d += std::abs(f - (b.count(n) ? b.at(n) : 0.0));
      for (const auto& [n, f] : b) d += a.count(n) ? 0.0 : f;
      return d;
    };
    // A sphere of radius R at height h over (0.25, 0.5, 1): contact disc
    // sqrt(R^2 - h^2) = 0.25, the distance of the top nodes (0, 0.5) and
    // (0.5, 0.5): a hair higher they are outside, a hair deeper inside.
    const double R = 0.3, h = std::sqrt(R * R - 0.25 * 0.25);
    const auto outside = load(V(0.25, 0.5, 1 + h + 1e-12), R), inside = load(V(0.25, 0.5, 1 + h - 1e-12), R);
    CHECK(distance(outside, inside) <= 1e-5);
    // Over the ridge the nearest point lies on it, on an edge of two faces:
    // which one the search names must not matter.
    const auto one = load(V(0.625, 0.43, 1.2), R), other = load(V(0.625, 0.43, 1.2), R, true);
    CHECK(distance(one, other) <= 1e-9);
    // And the load sums to 1, centred under the probe on the flat part.
    double sum = 0;
    V mean = V::Zero();
    for (const auto& [n, f] : inside) sum += f, mean += f * V(m.nodes.row(n).transpose());
    CHECK(sum == doctest::Approx(1.0).epsilon(1e-12));
    // (to the rim nodes' shares, sqrt of their 1e-12 margin)
    CHECK((mean.head<2>() - Eigen::Vector2d(0.25, 0.5)).norm() <= 1e-6);
  }

  TEST_CASE("nodes near a segment: the capsule around it, else the faces it reaches") {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 2;
    const mesh::TetMesh m = mesh::generate_box(o);
    const mesh::Surface s = mesh::extract_surface(m);
    const Eigen::MatrixX3d normals = mesh::vertex_normals(m, s);
    const tools::ContactSurface rest{m.nodes, s, normals};
    // Along the top edge row y = 0.5: exactly the three nodes (0|0.5|1, 0.5, 1).
    std::vector<int> hit = tools::nodes_near_segment(rest, V(-0.1, 0.5, 1.02), V(1.1, 0.5, 1.02), 0.05);
    REQUIRE(hit.size() == 3);
    for (int n : hit) CHECK((m.nodes(n, 1) == 0.5 && m.nodes(n, 2) == 1.0));
    CHECK(std::is_sorted(hit.begin(), hit.end()));
    // Brute force against dense sampling of the segment.
    for (int n : s.nodes) {
      const V x = m.node(n), p = tools::closest_point_on_segment(x, V(0, 0, 0), V(1, 0, 0));
      double best = 1e9;
      for (int k = 0; k <= 1000; ++k) best = std::min(best, (V(k / 1000.0, 0, 0) - x).norm());
      CHECK((p - x).norm() == doctest::Approx(best).epsilon(1e-6));
    }
    // Between node rows (y = 0.25): no node within 0.05, the faces under it instead.
    hit = tools::nodes_near_segment(rest, V(0.1, 0.25, 1.02), V(0.4, 0.25, 1.02), 0.05);
    CHECK(!hit.empty());
    for (int n : hit) CHECK(m.nodes(n, 2) == 1.0);
    CHECK(tools::nodes_near_segment(rest, V(0.1, 0.25, 1.2), V(0.4, 0.25, 1.2), 0.05).empty());
  }
  TEST_CASE("distance to the surface: a point, a segment beside, above or through the unit box") {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 3;
    const mesh::TetMesh m = mesh::generate_box(o);
    const mesh::Surface s = mesh::extract_surface(m);
    const Eigen::MatrixX3d normals = mesh::vertex_normals(m, s, m.nodes);
    const tools::ContactSurface c{m.nodes, s, normals};
    CHECK(tools::distance_to_surface(c, V(0.5, 0.5, 1.7), V(0.5, 0.5, 1.7)) == doctest::Approx(0.7).epsilon(1e-12));
    CHECK(tools::distance_to_surface(c, V(2, 2, 2), V(2, 2, 2)) == doctest::Approx(std::sqrt(3.0)).epsilon(1e-12));
    CHECK(tools::distance_to_surface(c, V(0.5, 0.5, 0.6), V(0.5, 0.5, 0.6)) == doctest::Approx(0.4).epsilon(1e-12));
    // A segment crossing above a corner edge: nearest at its middle, not its ends.
    CHECK(tools::distance_to_surface(c, V(-1, 1.5, 1.5), V(3, 1.5, 1.5)) ==
          doctest::Approx(std::sqrt(0.5)).epsilon(1e-12));
    // A segment passing through a face.
    CHECK(tools::distance_to_surface(c, V(0.3, 0.4, 0.5), V(0.3, 0.4, 1.5)) == 0.0);
    // A segment lying flat 0.25 above the top face, longer than the box.
    CHECK(tools::distance_to_surface(c, V(-5, 0.5, 1.25), V(5, 0.5, 1.25)) == doctest::Approx(0.25).epsilon(1e-12));
  }
}
