#pragma once
// ScenarioSpec: plain data describing one scenario. The Lua layer fills it
// (adding file:line to its own messages); compile() turns it into a Model.
// No Lua here. Every item carries a `name` used in error messages and outputs.
#include <Eigen/Core>
#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "backend/spec.hpp"
#include "fem/material.hpp"
#include "hybrid/precompute.hpp"
#include "sim/expectations.hpp"
#include "sim/selector.hpp"
#include "tools/ramp.hpp"
#include "tools/tool.hpp"

namespace softcut::sim {

// Where the rest mesh comes from: a file, or a generator with options.
struct MeshSource {
  std::filesystem::path file;  // read with mesh::read_mesh when not empty
  std::string generator;       // "box", "cylinder", ..., "liver", "kidney", "knee_ligament", "surface"
  // The length unit of `file` (empty: metres) or, for generator "surface",
  // of `surfaces` (empty: guessed from their size, with a warning): "m",
  // "cm", "mm" or "um". A file's lengths are then times `scale` too.
  std::string unit;
  double scale = 1;
  // generator "surface": the closed surfaces to mesh (.stl .obj .ply .off),
  // the organ first, then inner regions (labels 2, 3, ...).
  std::vector<std::filesystem::path> surfaces;
  // The caller's deadline (core/watchdog.hpp): CGAL meshing stops when it
  // turns true. How the caller raises max_tets, for messages (empty: the
  // flags of softcut run/check).
  const std::atomic<bool>* stop = nullptr;
  std::string raise_limit;
  // Generator options by name (numbers only; vectors as name.x/.y/.z or
  // name[0..2]), e.g. box: min.x .. max.z, nx, ny, nz, jitter, seed, label.
  // Unknown names are an error naming the generator and the option.
  std::map<std::string, double> options;
  // Or a mesh the caller already has (used when it has tets), with its named
  // node sets (e.g. "hole").
  mesh::TetMesh given;
  std::map<std::string, std::vector<int>> named_sets;
  std::string where;
  // The mesh already loaded from this source (the Lua layer loads it at
  // s:mesh{}, through the sandbox's checked open), with its named node sets:
  // compile takes it instead of opening the file or generating it again.
  std::shared_ptr<const mesh::TetMesh> preloaded;
  std::map<std::string, std::vector<int>> preloaded_sets;
  std::vector<std::string> preloaded_warnings;  // what loading it reported (skipped elements, flips)
};

// Material of a set of tets; later entries override earlier ones. When
// `preset` is not empty it supplies E and nu (unless set explicitly below).
struct MaterialAssignment {
  std::string name;
  std::string where;              // "scenario.lua:12" (prefixes messages), may be empty
  TetSelector tets = TetSelector::of(TetSelector::Kind::all);  // which tets (default: all)
  std::string preset;             // tissue_preset() name, or empty
  double young = 0.0;             // Pa; 0: from the preset
  double poisson = -2.0;          // outside (-1, 0.5): from the preset
  // Rendering: this material's colour (RGB in [0, 1]); without it, the
  // palette's colour of its place in s:material call order.
  bool has_color = false;
  Eigen::Vector3d color = Eigen::Vector3d::Zero();
  // The law (fem::MaterialModel); unset: linear. In the condensed region
  // only a whole-body solve applies it (SolverSpec::whole_body).
  std::optional<fem::MaterialModel> model;
  double density = 0;             // kg/m^3 (gravity); 0: the preset's, else 1000
};

// A prescribed motion (s:fix{ nodes, displacement | path }): the nodes are
// fixed, displaced by `path`'s point at each frame's time (m; a constant
// displacement is a one-point path).
struct MotionSpec {
  std::string name;
  std::string where;   // "scenario.lua:12" (prefixes messages), may be empty
  NodeSelector nodes;
  tools::Path path;    // displacement, m, over time
};

// Initial strain of a set of tets (fem::Material::initial_strain); later
// entries override earlier ones on shared tets.
struct PrestressAssignment {
  std::string name;
  std::string where;  // "scenario.lua:12" (prefixes messages), may be empty
  TetSelector tets = TetSelector::of(TetSelector::Kind::all);
  Eigen::Matrix3d strain = Eigen::Matrix3d::Zero();  // symmetric tensor eps0, mesh frame, dimensionless
};

struct LoadSpec {
  std::string name;
  std::string where;  // "scenario.lua:12" (prefixes messages), may be empty
  NodeSelector nodes;
  // world: `direction` (normalized); normal: each node's rest outward surface
  // normal (a positive magnitude pulls outward, negative pushes in; nodes off
  // the surface are an error).
  enum class Direction { world, normal };
  Direction direction_kind = Direction::world;
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
  tools::Ramp magnitude;  // N, at time t
  // total: magnitude is the total force, split evenly over the nodes;
  // per_node: every node gets the full magnitude.
  bool per_node = false;
};

struct Timeline {
  double duration = 1.0;     // s, >= 0
  double fps = 30.0;         // Hz, kMinFps .. kMaxFps
  std::string where;         // "scenario.lua:3" (softcut.scenario{}; prefixes messages), may be empty
  static constexpr double kMinFps = 1e-3, kMaxFps = 1e4;  // a frame at most every 1000 s, at least every 0.1 ms
  static constexpr double kMaxFrames = 1e7;
  // Frames are i = 0 .. num_frames - 1 at t = i / fps, with
  // num_frames = floor(duration * fps + 1e-9) + 1 (t = 0 included).
};

// Stored for the renderer (engine/render); sim/frame_scene.hpp maps it onto
// render::RenderSettings. Frames go to <dir>/frames/frame_000123.png.
struct RenderSettings {
  bool enabled = false;
  int width = 1280, height = 720;  // pixels
  // auto_frame: look at the rest shape's centre from azimuth/elevation about
  // `up`, just far enough to see all of it; else from `eye` at `target`.
  bool auto_frame = true;
  double azimuth_deg = -60.0, elevation_deg = 25.0;
  double orbit_deg_per_s = 0.0;  // azimuth grows at this rate (turntable), auto_frame only
  Eigen::Vector3d eye = Eigen::Vector3d(0.3, -0.4, 0.3);  // m
  Eigen::Vector3d target = Eigen::Vector3d::Zero();       // m
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fov_deg = 30.0;                                   // vertical
  Eigen::Vector3d background = Eigen::Vector3d(0.20, 0.22, 0.26);  // RGB in [0, 1]
  // clinical: tissue coloured by material (s:material call order; a lesion
  // shows); paper: the paper's region colours; debug: clinical with the
  // markers on (manipulated nodes and force lines, load arrows).
  enum class Style { clinical, paper, debug };
  Style style = Style::clinical;
  std::vector<Eigen::Vector3d> tissue_colors;  // RGB in [0, 1] per material (call order), cycled; empty: the default palette
  Eigen::Vector3d cut_color = Eigen::Vector3d(0.72, 0.16, 0.24);  // RGB in [0, 1]: cut faces (clinical: their tint)
  bool show_inclusions = true;  // clinical: tissue-group boundaries inside the organ (a lesion) drawn faintly
  bool wireframe = false;
  bool show_interface = false;  // interface nodes as points (a debugging view)
  bool show_forces = false;    // manipulated nodes and their force lines (on with style debug)
  bool show_loads = false;     // each acting load (s:load) as an arrow at its nodes' centroid
  int msaa_samples = 4;
  int every = 1;               // render every n-th frame
  bool contact_sheet = true;   // also <dir>/contact_sheet.png: a grid of up to ~24 frames
  // Per rendered frame also frames/depth_NNNNNN.png and frames/labels_NNNNNN.png
  // (docs/rendering.md "Depth, labels and camera data").
  bool depth = false, labels = false;
  bool video = false;          // video.mp4 of the frames (H.264 through ffmpeg)
  // render_record.bin for `softcut render`: automatic writes it when it
  // stays under kRecordAutoBytes (estimated from the run's size).
  enum class Record { automatic, on, off };
  Record record = Record::automatic;
};

// The camera over time, when not the fixed or orbiting camera of
// RenderSettings (s:camera): on a path looking at a point or along another
// path, or following a tool like an endoscope on its port.
struct CameraSpec {
  enum class Kind { none, path, follow };
  Kind kind = Kind::none;
  std::string where;             // "scenario.lua:12", may be empty
  tools::Path eye;               // path: the eye over time, m
  bool target_moves = false;     // path: the target follows target_path ...
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // ... else looks at this point, m
  tools::Path target_path;
  std::string follow;            // follow: the tool's name
  double distance = 0.06;        // follow: eye behind the tool's tip along its shaft, m
  double offset = 0.01;          // follow: eye off the shaft's axis, toward `up`, m
  double lead = 0.0;             // follow: looks this far beyond the tip along the tool, m
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fov_deg = 0.0;          // vertical; 0: RenderSettings::fov_deg
};

struct OutputSpec {
  std::filesystem::path dir;        // output folder (the CLI's --out, default renders/<scenario>)
  double timeout_s = 0;             // the run's wall-clock limit (--timeout), 0: none; for the summary
  std::uint64_t max_bytes = 0;      // the run's output limit (--max-output), 0: none; for the summary
  bool log_all_surface = true;      // log every whole-body surface node ...
  NodeSelector log_nodes;           // ... else these (kind all = every node)
  bool csv = true;                  // displacements.csv
  bool vtu = false;                 // vtu/frame_000123.vtu + series.pvd
  int vtu_every = 1;                // every n-th frame
  RenderSettings render;            // stored for the renderer
  std::string where;                // "scenario.lua:12" (s:output{}; prefixes messages), may be empty
  CameraSpec camera;                // s:camera (kind none: RenderSettings' camera)
};

// Cutter options (cut::CutOptions, docs/cutting.md).
struct CuttingSpec {
  double snap_fraction = 0.15;    // in (0, 0.5): crossings this close to an edge end snap to the node
  double min_dihedral_deg = 10.0; // in [0, 60): quality bound for tets made by cutting
};

struct ScenarioSpec {
  std::string name = "scenario";                 // used for renders/<name>/ and summary.json
  std::string description;                       // one line for `softcut check`'s report
  double reference_tolerance = 1e-6;             // softcut check: max |u - u_ref| relative to max |u_ref|
  std::filesystem::path source;                  // the .lua file, for messages and the summary
  std::map<std::string, std::string> versions;   // extra versions for the summary (e.g. "lua")
  MeshSource mesh;
  std::vector<MaterialAssignment> materials;     // empty: fem::Material{} everywhere
  std::vector<PrestressAssignment> prestress;    // initial strains (none: a stress-free rest state)
  TetSelector operational;                       // operational tets (default none)
  NodeSelector fixed;                            // required: at least one node (or a motion's)
  std::vector<MotionSpec> motions;               // fixed nodes moved along paths (prescribed displacement)
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // m/s^2: a body force density x gravity on every tet
  std::vector<LoadSpec> loads;
  std::vector<tools::ToolSpec> tools;
  Timeline timeline;
  OutputSpec outputs;
  backend::SolverSpec solver;
  CuttingSpec cutting;
  std::vector<ExpectationSpec> expectations;     // checked by the run loop (sim/expectations.hpp)
  // For the summary: the scenario's parameters after --set (name, value as
  // the script sees it), and the command line that ran it.
  std::vector<std::pair<std::string, std::string>> params;
  std::vector<std::string> command_line;
};

// A scenario's name becomes its output folder renders/<name>/: a plain
// folder name (not '.', '..' or empty; no '/', '\\', control characters or
// NUL; at most 100 bytes). Throws naming the name (escaped) otherwise.
void check_scenario_name(const std::string& name);

// Checks everything that can be checked without the mesh (numbers, ramps,
// paths, names unique); throws softcut::Error naming the item, e.g.
// "load 'push': ramp times must increase (t[2] = 0.5 after 0.7)".
void check_spec(const ScenarioSpec& spec);

// A symmetric strain tensor in fem::Material's Voigt order [xx yy zz yz zx
// xy] with engineering shears (2 eps_yz, ...).
std::array<double, 6> voigt_strain(const Eigen::Matrix3d& eps);

const char* to_string(LoadSpec::Direction d);

// The spec's enums from the names users write (Lua, JSON): each throws
// softcut::Error naming the field and the accepted values, with a
// did-you-mean (core/suggest.hpp). "world"/"normal"; "clinical"/"paper"/
// "debug"; "path"/"follow".
LoadSpec::Direction parse_load_direction(std::string_view text);
RenderSettings::Style parse_render_style(std::string_view text);
CameraSpec::Kind parse_camera_kind(std::string_view text);

}  // namespace softcut::sim
