#pragma once
// Surgical tools: a probe pokes, a grasper grabs and drags, a scalpel presses
// and, above its cutting pressure, cuts. Each moves on a Path; collision with
// the current deformed surface picks what it acts on (either region; probe
// and grasper: points of the surface patch under the sphere tip, bound to
// their triangles' nodes; a spring probe: nodes within the sphere; scalpel:
// nodes within `radius` of the blade edge); the tool then applies nodal
// forces, N. Cutting itself is done by
// the cutting stage (cut/stage.hpp) from the blade poses kept in ToolState.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "tools/collision.hpp"
#include "tools/path.hpp"
#include "tools/ramp.hpp"

namespace softcut::tools {

struct ToolSpec {
  enum class Kind { probe, grasper, scalpel };
  // force: total force magnitude `force(t)` (N) along `direction`, split
  //        evenly over the grip points (grasper: its jaw's patch; probe: the
  //        circle it presses into the surface, tools::surface_patch) and on
  //        to their nodes by barycentric weights; a scalpel splits it evenly
  //        over its contact nodes.
  // spring: total stiffness `stiffness` (N/m) split evenly over the
  //        manipulated nodes (grasper: over its grip points); each is pulled
  //        toward its target (grasper: grasp-time offset from the tip; probe:
  //        pushed out to the tip sphere's surface). update_tool() evaluates it on last frame's
  //        positions (explicit). A grasper with `implicit` (the default) is
  //        instead solved exactly within each frame by sim::step (see
  //        tools/springs.hpp), so any stiffness works; explicit springs only
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
  // the tip from the centroid of its grip points.
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  double stiffness = 0.0;  // N/m, total (drive spring), > 0
  bool implicit = true;    // grasper spring: exact within the frame (false: explicit, lags a frame)
  // probe: in contact only in [start, stop];
  // grasper: closes at the first frame with t >= start that touches the
  // surface, on the patch of surface under its jaw (tools::surface_patch,
  // radius = `radius`), keeps it, opens at stop.
  double start = 0.0;                                      // s (Lua: start)
  double stop = std::numeric_limits<double>::infinity();   // s (Lua: stop)

  // Scalpel only. The blade edge is the segment of length blade_length
  // centred on the path point along blade_axis; it touches the nodes within
  // `radius` of the edge and presses them like a probe (force or spring).
  // Contact pressure = |total contact force| / (blade_length x 2 radius), Pa
  // (the contact strip is the blade edge widened by the contact radius on
  // both sides). From the frame it reaches cut_pressure the tissue yields:
  // the blade applies no force and the surface it sweeps between frames is cut.
  double blade_length = 0.02;                                   // m, > 0
  Eigen::Vector3d blade_axis = Eigen::Vector3d::UnitY();        // any length > 0
  double cut_pressure = std::numeric_limits<double>::infinity();  // Pa, > 0 (infinity: never cuts)
  // Zero: the blade is its edge (a segment). Else a triangular blade: the
  // edge plus a third corner at centre + blade_back, m; the whole triangle
  // sweeps (a stab or a slice along its plane cuts its full area). Contact
  // and pressure stay those of the edge.
  Eigen::Vector3d blade_back = Eigen::Vector3d::Zero();

  // Drawing only: the direction from the tip to the handle, any length > 0.
  // Zero: probe and scalpel against `direction` when one is given, else (and
  // for a grasper) back along the tool's approach (ToolState::approach), else
  // the camera's up.
  Eigen::Vector3d shaft = Eigen::Vector3d::Zero();
};

// Throws softcut::Error naming the tool (and `where`) for bad values.
void check_tool(const ToolSpec& t, const std::string& where);

struct ToolState {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();  // tip center this frame, m
  bool override_tip = false;                      // true: `tip` was set by the script, path ignored
  bool engaged = false;                           // grasper closed / probe touching
  std::vector<int> nodes;                         // (k) manipulated node ids, sorted
  std::vector<Eigen::Vector3d> forces;            // (k) force on each node this frame, N
  // Grasper: the surface points it holds (surface_patch at closing; `nodes`
  // are their triangles' nodes) and each point minus the tip at grasp, m.
  // Force-driven probe: its contact area this frame (surface_patch's contact
  // circle), no offsets. A point's spring or force acts on its nodes by its weights.
  std::vector<SurfacePoint> grip;                 // (p)
  std::vector<Eigen::Vector3d> offsets;           // (p)
  Eigen::Vector3d total_force = Eigen::Vector3d::Zero();  // N
  // Scalpel only.
  Eigen::Vector3d blade_a = Eigen::Vector3d::Zero(), blade_b = Eigen::Vector3d::Zero();  // edge this frame, m
  Eigen::Vector3d prev_a = Eigen::Vector3d::Zero(), prev_b = Eigen::Vector3d::Zero();    // edge last frame, m
  Eigen::Vector3d blade_c = Eigen::Vector3d::Zero(), prev_c = Eigen::Vector3d::Zero();   // triangle's third corner, m
  bool has_prev = false;   // prev_a/prev_b are set (false before the first frame)
  double pressure = 0.0;   // contact pressure this frame (before cutting), Pa
  bool cutting = false;    // the blade cut this frame (set by sim::step)
  bool in_cut = false;     // cutting and still changing the mesh: keeps cutting next frame whatever the pressure
  // Rest-space images of blade_a / blade_b / blade_c as the last cut step
  // mapped them (cut::cut_stage). The next step of the same stroke starts its
  // swept quads from exactly these points, so consecutive steps share their
  // edge in rest space even when the displacement field changed in between.
  Eigen::Vector3d rest_a = Eigen::Vector3d::Zero(), rest_b = Eigen::Vector3d::Zero(), rest_c = Eigen::Vector3d::Zero();
  bool has_rest = false;   // rest_a/b/c belong to the stroke in progress
  bool warned_uncuttable = false;  // this stroke already warned that it reached tissue it may not cut
  bool warned_locked_snap = false; // this stroke already warned that it snapped onto the locked interface
  double touch_pressure = 0.0;     // pressure at the last frame it touched the surface, Pa
  double touch_time = -1.0;        // that frame's time, s (-1: never touched)
  bool outside_seen = false;       // the edge lay outside the tissue at some frame since it became active
  int cut_events = 0;      // frames in which this blade changed the mesh
  // Where the tool came from (drawing its shaft): the tip at its first active
  // frame, and, from its first contact on, the unit vector from the tip at
  // that contact back to start_tip (zero: it was within a radius of it).
  Eigen::Vector3d start_tip = Eigen::Vector3d::Zero(), approach = Eigen::Vector3d::Zero();
  bool has_start = false, touched = false;
  // What the run says at its end about a tool that did nothing
  // (sim/tool_report.hpp): until its first contact, its closest approach to
  // the surface (the gap between the tip's sphere, or the blade's capsule,
  // and the deformed surface, m) and when; a scalpel's highest contact
  // pressure and when.
  bool was_active = false;          // active (enabled, inside its window) at some frame
  double closest_gap = std::numeric_limits<double>::infinity();  // m
  double closest_time = -1.0;       // s (-1: never measured)
  double max_pressure = 0.0;        // Pa
  double max_pressure_time = -1.0;  // s (-1: never touched)
};

// Scalpel: end points of the blade edge with its centre at `center`.
void blade_edge(const ToolSpec& spec, const Eigen::Vector3d& center, Eigen::Vector3d& a, Eigen::Vector3d& b);

// One frame of a tool at time t: moves the tip (unless overridden), finds
// contact on `s`, sets nodes and forces. Deterministic.
void update_tool(const ToolSpec& spec, ToolState& st, double t, const ContactSurface& s);

// After a cut changed the mesh (nodes appended, tets split, the nodes of one
// side duplicated): binds each grip point anew to the face of `surf` nearest
// to where it is now (x: current node positions, nnode x 3, m), among equally
// near faces the one sharing most of its old nodes, so no point ties the two
// lips together; offsets are kept, `nodes` recomputed. No-op without a grip.
void rebind_grip(ToolState& st, const Eigen::MatrixX3d& x, const mesh::Surface& surf);

// A grasper spring solved within the frame by the simulation (its forces from
// update_tool() are only last frame's explicit estimate).
bool is_implicit_spring(const ToolSpec& spec);

const char* to_string(ToolSpec::Kind k);
const char* to_string(ToolSpec::Drive d);

// "probe"/"grasper"/"scalpel" and "force"/"spring": throw naming the
// accepted values with a did-you-mean.
ToolSpec::Kind parse_tool_kind(std::string_view text);
ToolSpec::Drive parse_drive(std::string_view text);

}  // namespace softcut::tools
