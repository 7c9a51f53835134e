#pragma once
// Surgical tools: a probe pokes, a grasper grabs and drags. Each has a sphere
// tip moving on a Path; collision with the current deformed surface picks the
// manipulated nodes (either region); the tool then applies nodal forces, N.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "tools/collision.hpp"
#include "tools/path.hpp"
#include "tools/ramp.hpp"

namespace softcut::tools {

struct ToolSpec {
  enum class Kind { probe, grasper };
  // force: total force magnitude `force(t)` (N), split evenly over the
  //        manipulated nodes, along `direction`.
  // spring: total stiffness `stiffness` (N/m) split evenly over the
  //        manipulated nodes; each node is pulled toward its target
  //        (grasper: grasp-time offset from the tip; probe: pushed out to the
  //        tip sphere's surface). update_tool() evaluates it on last frame's
  //        positions (explicit). A grasper with `implicit` (the default) is
  //        instead solved exactly within each frame by sim::step (see
  //        sim/springs.hpp), so any stiffness works; explicit springs only
  //        settle over frames when stiffness x compliance at the contact is
  //        below about 1 (see docs/outputs.md).
  enum class Drive { force, spring };

  std::string name;   // used in messages and outputs
  std::string where;  // "scenario.lua:12" of the defining call (prefixes messages), may be empty
  bool enabled = true;  // false: no contact, no force (a grasper also lets go)
  Kind kind = Kind::probe;
  Drive drive = Drive::force;
  Path path;              // tip center, m
  double radius = 0.005;  // tip sphere radius, m, > 0
  Ramp force;             // N (drive force)
  // Unit force direction (drive force). Zero: probe pushes along minus the
  // mean deformed outward normal of its contact nodes; grasper pulls toward
  // the tip from the centroid of the grasped nodes.
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  double stiffness = 0.0;  // N/m, total (drive spring), > 0
  bool implicit = true;    // grasper spring: exact within the frame (false: explicit, lags a frame)
  // probe: in contact only in [active_from, active_until];
  // grasper: closes at the first frame with t >= active_from that touches the
  // surface, keeps the grasped nodes, opens at active_until.
  double active_from = 0.0;                                        // s
  double active_until = std::numeric_limits<double>::infinity();   // s
};

// Throws softcut::Error naming the tool (and `where`) for bad values.
void check_tool(const ToolSpec& t, const std::string& where);

struct ToolState {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();  // tip center this frame, m
  bool override_tip = false;                      // true: `tip` was set by the script, path ignored
  bool engaged = false;                           // grasper closed / probe touching
  std::vector<int> nodes;                         // (k) manipulated node ids, sorted
  std::vector<Eigen::Vector3d> offsets;           // (k) grasper: node minus tip at grasp, m
  std::vector<Eigen::Vector3d> forces;            // (k) force on each node this frame, N
  Eigen::Vector3d total_force = Eigen::Vector3d::Zero();  // N
};

// One frame of a tool at time t: moves the tip (unless overridden), finds
// contact on `s`, sets nodes and forces. Deterministic.
void update_tool(const ToolSpec& spec, ToolState& st, double t, const ContactSurface& s);

// A grasper spring solved within the frame by the simulation (its forces from
// update_tool() are only last frame's explicit estimate).
bool is_implicit_spring(const ToolSpec& spec);

const char* to_string(ToolSpec::Kind k);
const char* to_string(ToolSpec::Drive d);

}  // namespace softcut::tools
