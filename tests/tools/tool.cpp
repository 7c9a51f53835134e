#include "tools/tool.hpp"

#include <doctest/doctest.h>

#include <cmath>

#include <algorithm>

#include "core/error.hpp"
#include "mesh/generate/box.hpp"

using V = Eigen::Vector3d;
namespace mesh = softcut::mesh;
namespace tools = softcut::tools;

namespace {

struct BoxContact {
  mesh::TetMesh m;
  mesh::Surface s;
  Eigen::MatrixX3d x, normals;
  BoxContact() {
    mesh::BoxOptions o;
    o.nx = o.ny = o.nz = 4;
    m = mesh::generate_box(o);
    s = mesh::extract_surface(m);
    x = m.nodes;
    normals = mesh::vertex_normals(m, s, x);
  }
  tools::ContactSurface contact() const { return {x, s, normals}; }
};

}  // namespace

TEST_SUITE("tools/tool") {
  TEST_CASE("parse_tool_kind, parse_drive: the names, and a misspelt one named") {
    CHECK(tools::parse_tool_kind("probe") == tools::ToolSpec::Kind::probe);
    CHECK(tools::parse_tool_kind("grasper") == tools::ToolSpec::Kind::grasper);
    CHECK(tools::parse_tool_kind("scalpel") == tools::ToolSpec::Kind::scalpel);
    CHECK(tools::parse_drive("force") == tools::ToolSpec::Drive::force);
    CHECK(tools::parse_drive("spring") == tools::ToolSpec::Drive::spring);
    CHECK_THROWS_WITH(tools::parse_tool_kind("grasp"), doctest::Contains("(did you mean 'grasper'?)"));
    CHECK_THROWS_WITH(tools::parse_drive("sprung"), doctest::Contains("unknown drive 'sprung'"));
  }

  TEST_CASE("force-driven probe spreads its ramp over its contact circle, pushing against the normal") {
    BoxContact b;
    tools::ToolSpec spec;
    spec.name = "probe";
    spec.path = tools::Path::fixed_at(V(0.5, 0.5, 1.0));
    spec.radius = 0.26;
    spec.force = tools::Ramp::linear_ramp(0.0, 2.0, 0.0, 1.0);
    tools::ToolState st;
    tools::update_tool(spec, st, 0.5, b.contact());
    // Tip on the top face: the contact circle has the tip's radius; it holds
    // the pattern's nearest point and inner ring (the outer ring lies on the
    // rim, where Hertz's pressure is zero) and the 5 top nodes within 0.26,
    // the four at 0.25 with the rim's small share.
    REQUIRE(st.grip.size() == 1 + 6 + 5);
    CHECK(st.grip[0].share == 1.0);
    for (size_t i = 1; i <= 6; ++i) CHECK(st.grip[i].share == doctest::Approx(std::sqrt(0.75)).epsilon(1e-9));
    for (size_t i = 7; i < st.grip.size(); ++i) CHECK(st.grip[i].share <= 1.0);
    CHECK(st.engaged);
    CHECK((st.total_force - V(0, 0, -1.0)).norm() < 1e-12);
    // The nodal forces press where the probe does: their centre of pressure
    // is the tip (the weights reproduce the points' positions).
    V moment = V::Zero();
    for (size_t i = 0; i < st.nodes.size(); ++i) {
      CHECK(b.x(st.nodes[i], 2) == 1.0);
      CHECK(st.forces[i].z() < 0);
      moment += st.forces[i].z() * V(b.x.row(st.nodes[i]).transpose());
    }
    CHECK((moment / st.total_force.z() - V(0.5, 0.5, 1.0)).norm() < 1e-12);
    // Explicit direction wins.
    spec.direction = V(1, 0, 0);
    tools::update_tool(spec, st, 1.0, b.contact());
    CHECK((st.total_force - V(2.0, 0, 0)).norm() < 1e-12);
    // Outside the active window: nothing.
    spec.stop = 0.9;
    tools::update_tool(spec, st, 1.0, b.contact());
    CHECK(st.nodes.empty());
    CHECK(st.total_force.norm() == 0);
  }

  TEST_CASE("grasper keeps the nodes grabbed at first contact and springs them toward the moving tip") {
    BoxContact b;
    tools::ToolSpec spec;
    spec.name = "grasper";
    spec.kind = tools::ToolSpec::Kind::grasper;
    spec.drive = tools::ToolSpec::Drive::spring;
    spec.stiffness = 40.0;
    spec.radius = 0.01;
    spec.path = tools::Path::polyline({0.0, 1.0}, {V(1, 1, 1), V(1, 1, 1.5)});
    tools::ToolState st;
    tools::update_tool(spec, st, 0.0, b.contact());
    REQUIRE(!st.grip.empty());
    const std::vector<int> nodes = st.nodes;
    CHECK(st.total_force.norm() < 1e-12);
    // Tip moved 0.25 up; the tissue did not move: force = k * 0.25 up over
    // the grip, the same grip kept although the tip no longer touches it.
    tools::update_tool(spec, st, 0.5, b.contact());
    CHECK(st.nodes == nodes);
    CHECK((st.total_force - V(0, 0, 10.0)).norm() < 1e-12);
    // Released after stop.
    spec.stop = 0.75;
    tools::update_tool(spec, st, 0.8, b.contact());
    CHECK(st.nodes.empty());
    CHECK(!st.engaged);
  }

  TEST_CASE("script override of the tip ignores the path") {
    BoxContact b;
    tools::ToolSpec spec;
    spec.path = tools::Path::fixed_at(V(5, 5, 5));
    spec.radius = 0.01;
    spec.force = tools::Ramp::constant_value(1.0);
    tools::ToolState st;
    st.tip = V(0, 0, 0);
    st.override_tip = true;
    tools::update_tool(spec, st, 0.0, b.contact());
    REQUIRE(st.engaged);
    CHECK(std::count(st.nodes.begin(), st.nodes.end(), 0) == 1);  // node 0 sits at the corner (0, 0, 0)
    for (const auto& p : st.grip) CHECK(p.at(b.x).norm() <= 0.01 * (1 + 1e-12));
  }

  TEST_CASE("bad tools are refused naming the tool") {
    tools::ToolSpec spec;
    spec.name = "hook";
    spec.path = tools::Path::fixed_at(V::Zero());
    spec.radius = 0;
    CHECK_THROWS_WITH_AS(tools::check_tool(spec, ""), doctest::Contains("tool 'hook'"), softcut::Error);
    spec.radius = 0.01;
    spec.drive = tools::ToolSpec::Drive::spring;
    CHECK_THROWS_WITH_AS(tools::check_tool(spec, ""), doctest::Contains("stiffness"), softcut::Error);
    spec.stiffness = 10;
    spec.path = tools::Path::polyline({1.0, 0.5}, {V::Zero(), V::Ones()});
    CHECK_THROWS_AS(tools::check_tool(spec, ""), softcut::Error);
  }

  TEST_CASE("only spring graspers with implicit set are solved by the simulation") {
    tools::ToolSpec spec;
    CHECK(spec.implicit);  // the default
    spec.kind = tools::ToolSpec::Kind::grasper;
    spec.drive = tools::ToolSpec::Drive::force;
    CHECK(!tools::is_implicit_spring(spec));
    spec.drive = tools::ToolSpec::Drive::spring;
    CHECK(tools::is_implicit_spring(spec));
    spec.implicit = false;
    CHECK(!tools::is_implicit_spring(spec));
    spec.implicit = true;
    spec.kind = tools::ToolSpec::Kind::probe;  // contact set changes every frame: stays explicit
    CHECK(!tools::is_implicit_spring(spec));
  }

  TEST_CASE("scalpel: blade edge centred on the path, probe-like pressing, pressure = |F| / (length x 2 radius)") {
    BoxContact b;  // unit box, 4 x 4 x 4 cells: top nodes at z = 1 every 0.25
    tools::ToolSpec spec;
    spec.name = "blade";
    spec.kind = tools::ToolSpec::Kind::scalpel;
    spec.path = tools::Path::fixed_at(V(0.5, 0.5, 1.05));
    spec.blade_length = 0.6;
    spec.blade_axis = V(0, 2, 0);  // normalised
    spec.radius = 0.1;
    spec.cut_pressure = 1e3;
    spec.force = tools::Ramp::linear_ramp(0.0, 3.0, 0.0, 1.0);
    tools::check_tool(spec, "");
    V a, c;
    tools::blade_edge(spec, V(0.5, 0.5, 1.05), a, c);
    CHECK((a - V(0.5, 0.2, 1.05)).norm() < 1e-15);
    CHECK((c - V(0.5, 0.8, 1.05)).norm() < 1e-15);
    tools::ToolState st;
    tools::update_tool(spec, st, 0.5, b.contact());
    CHECK_FALSE(st.has_prev);  // first frame: no swept surface yet
    // Top nodes within 0.1 of the edge: x = 0.5, y in {0.25, 0.5, 0.75}.
    REQUIRE(st.nodes.size() == 3);
    for (int n : st.nodes) CHECK(b.m.nodes(n, 0) == 0.5);
    CHECK((st.total_force - V(0, 0, -1.5)).norm() < 1e-12);
    CHECK(st.pressure == doctest::Approx(1.5 / (0.6 * 0.2)).epsilon(1e-14));
    tools::update_tool(spec, st, 0.6, b.contact());
    CHECK(st.has_prev);
    CHECK((st.prev_a - a).norm() < 1e-15);
    // A blade between node rows still touches the faces under it.
    spec.path = tools::Path::fixed_at(V(0.6, 0.5, 1.05));
    tools::update_tool(spec, st, 0.6, b.contact());
    CHECK(!st.nodes.empty());
    // Bad blades are refused naming the tool.
    spec.blade_length = 0;
    CHECK_THROWS_WITH_AS(tools::check_tool(spec, ""), doctest::Contains("tool 'blade': blade_length"), softcut::Error);
    spec.blade_length = 0.6;
    spec.blade_axis = V::Zero();
    CHECK_THROWS_AS(tools::check_tool(spec, ""), softcut::Error);
  }

  TEST_CASE("spring scalpel pushes the nodes out of the capsule around its edge") {
    BoxContact b;
    tools::ToolSpec spec;
    spec.name = "blade";
    spec.kind = tools::ToolSpec::Kind::scalpel;
    spec.drive = tools::ToolSpec::Drive::spring;
    spec.stiffness = 30.0;
    spec.cut_pressure = 1e9;
    spec.blade_length = 0.6;
    spec.blade_axis = V(0, 1, 0);
    spec.radius = 0.1;
    spec.path = tools::Path::fixed_at(V(0.5, 0.5, 0.95));  // 0.05 below the top face
    tools::ToolState st;
    tools::update_tool(spec, st, 0.0, b.contact());
    REQUIRE(st.nodes.size() == 3);
    V sum = V::Zero();
    for (size_t k = 0; k < st.nodes.size(); ++k) {
      // Node straight above the edge at distance 0.05: pushed up by k/3 (0.1 - 0.05).
      CHECK((st.forces[k] - V(0, 0, 10.0 * 0.05)).norm() < 1e-12);
      sum += st.forces[k];
    }
    CHECK(st.pressure == doctest::Approx(sum.norm() / (0.6 * 0.2)).epsilon(1e-14));
  }
}
