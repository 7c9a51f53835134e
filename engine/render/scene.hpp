#pragma once
// The abstract scene: what a frame shows, as plain triangles, lines and points
// with colours, plus the camera. Built from plain data (a tet mesh, positions,
// flags, tools) by extract_scene() without any GL, so it is testable anywhere
// and independent of the simulation types; renderer.hpp draws it.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "mesh/tet_mesh.hpp"
#include "render/camera.hpp"
#include "render/primitives.hpp"
#include "render/tool_geometry.hpp"

namespace softcut::render {

// Default colours follow the paper's figures (Figs. 4-11): operational part
// light grey, nonoperational part dark blue, manipulated node and its force
// line green; cut faces show the tissue interior.
// style clinical: tissue coloured by group (material) from `tissue`, cycled.
struct Palette {
  Rgba operational{0.80f, 0.80f, 0.78f, 1.0f};
  Rgba nonoperational{0.12f, 0.20f, 0.55f, 1.0f};
  Rgba cut{0.72f, 0.16f, 0.24f, 1.0f};
  float cut_tint = 0.55f;   // clinical: how far a cut face's tissue colour goes toward `cut`, 0..1 ...
  float wound_shade = 0.6f; // ... and then darkened by this factor (drawn wet: a wound, not a slice)
  float margin_tint = 0.45f;  // clinical: the outer surface at the incision's edge goes this far toward the wound
  Rgba outline{0.30f, 0.03f, 0.06f, 1.0f};  // the incision's rim on the surface
  Rgba arrow{1.00f, 0.55f, 0.10f, 1.0f};    // load arrows
  Rgba manipulated{0.10f, 0.85f, 0.20f, 1.0f};
  Rgba interface_nodes{1.00f, 0.78f, 0.10f, 1.0f};
  Rgba tool{0.70f, 0.72f, 0.76f, 1.0f};       // steel: jaws, blades, probe tips
  Rgba tool_dark{0.15f, 0.16f, 0.18f, 1.0f};  // shafts and handles
  float inclusion_alpha = 0.4f;   // clinical: opacity of inclusions seen through the tissue, (0, 1] ...
  // ... fading with their depth d below the outer surface, by
  // 0.3 + 0.7 exp(-1.2 d / (inclusion_depth x the model's size)), and 40 %
  // of the way toward the colour of the tissue around them.
  float inclusion_depth = 0.08f;
  Rgba background{0.20f, 0.22f, 0.26f, 1.0f};
  // Clinical style, per tissue group: parenchyma red-brown, then a pale
  // lesion/fat tone, then further tissues.
  std::vector<Rgba> tissue{{0.62f, 0.30f, 0.26f, 1.0f}, {0.90f, 0.82f, 0.60f, 1.0f}, {0.78f, 0.55f, 0.52f, 1.0f},
                           {0.52f, 0.40f, 0.58f, 1.0f}, {0.85f, 0.70f, 0.45f, 1.0f}};
};

// paper: the paper's region colours (operational / nonoperational);
// clinical: tissue colours by group (SceneContent::tet_group).
enum class Style { paper, clinical };

struct RenderSettings {
  int width = 640, height = 480;  // pixels
  int msaa_samples = 4;            // 0 or 1: no multisampling; clamped to the driver's maximum
  Style style = Style::paper;
  bool wireframe = false;          // draw the surface edges over the shading
  bool incision_outline = true;    // outline where cut faces meet the outer surface (visible when closed)
  bool show_inclusions = true;     // clinical: tissue-group boundaries inside the organ (a lesion) seen
                                   // faintly through the surface, as an ultrasound overlay would show them
  bool show_interface = true;      // interface ("common") nodes as points
  bool show_forces = true;         // manipulated nodes and their force lines (SceneContent::manipulated)
  bool show_loads = true;          // load arrows (SceneContent::arrows)
  bool interface_on_top = true;    // ... visible through the surface (they are mostly inside)
  double crease_angle_deg = 40.0;  // normals are smoothed across edges flatter than this; 0: flat
  int tool_segments = 24;          // facets around a tool's sphere or cylinder, >= 6, even
  float point_size_px = 6.0f, line_width_px = 2.0f, wire_width_px = 1.0f;
  Palette palette;
  CameraSettings camera;
};

// A node under user manipulation, drawn as a green point with a line from its
// current position to `line_end` (the tool or "mouse" point; the paper's Figs. 9-11).
struct ManipulatedNode {
  int node = 0;
  Eigen::Vector3d line_end{0, 0, 0};  // m
};

// A load drawn as an arrow: a shaft from `from` to `to` and a head at `to`.
struct Arrow {
  Eigen::Vector3d from{0, 0, 0}, to{0, 0, 0};  // m
};

// Everything but the mesh itself. Sizes refer to the mesh passed alongside.
struct SceneContent {
  std::vector<char> operational;  // (ntet) nonzero: operational tet; empty: all operational
  std::vector<char> cut_faces;    // (4 ntet) nonzero at 4 t + f: face f (opposite local
                                  // vertex f) of tet t lies on a cut; empty: none
  std::vector<int> tet_group;     // (ntet) tissue group, >= 0 (clinical style); empty: all 0
  std::vector<int> interface_nodes;  // node ids shown as points
  std::vector<ManipulatedNode> manipulated;
  std::vector<Arrow> arrows;  // loads
  std::vector<ToolShape> tools;
  // Ids in the label image (Renderer::draw's LabelImages; 0 is the
  // background): per tissue group (empty: 1 + group), for cut faces (0: their
  // group's), per tool (empty: 0).
  std::vector<std::uint32_t> group_labels;
  std::uint32_t cut_label = 0;
  std::vector<std::uint32_t> tool_labels;
};

// --- the extracted scene ------------------------------------------------------

struct Scene {
  int width = 0, height = 0, msaa_samples = 0;
  Rgba background;
  Triangles tissue;  // boundary faces of the tet mesh, one triangle each (clinical: but the cut faces)
  Triangles wound;   // clinical: the cut faces, drawn wet
  Triangles tools;
  // Inner boundaries between tissue groups, each face once, wound outward
  // from the inclusion (the tet not of the commonest group), in its colour
  // with alpha palette.inclusion_alpha; drawn blended over the tissue.
  Triangles inclusions;
  Primitives wire;         // surface edges (lines), when wireframe is on
  Primitives outline;      // the incision's rim (lines): edges between cut and uncut surface faces
  Primitives force_lines;  // manipulated node -> line_end (lines)
  Primitives arrows;       // load arrows: shaft and two head strokes each (lines, on top)
  Primitives interface_points;
  Primitives manipulated_points;
  Camera camera;
  int tissue_faces_operational = 0, tissue_faces_nonoperational = 0, tissue_faces_cut = 0;
};

// Builds the scene of one frame. `mesh` is the current topology (its nodes are
// the rest positions, used for framing), `positions` (nnode x 3) the deformed
// node positions, m. Throws softcut::Error naming the offending item for sizes
// that do not match the mesh, ids out of range, non-finite positions or bad
// settings.
Scene extract_scene(const mesh::TetMesh& mesh, const Eigen::MatrixX3d& positions, const SceneContent& content,
                    const RenderSettings& settings);

// extract_scene for a sequence of frames: keeps what depends only on the
// topology (boundary faces, their region, node -> face adjacency, surface
// edges) and rebuilds it only when the tets or the operational / cut flags
// change (a cut), so a frame costs its normals and vertex arrays. The result
// is identical to extract_scene's.
class SceneExtractor {
 public:
  SceneExtractor();
  ~SceneExtractor();
  SceneExtractor(SceneExtractor&&) noexcept;
  SceneExtractor& operator=(SceneExtractor&&) noexcept;

  Scene extract(const mesh::TetMesh& mesh, const Eigen::MatrixX3d& positions, const SceneContent& content,
                const RenderSettings& settings);
  int topology_builds() const;  // how often the cached topology was (re)built

 private:
  struct Topology;
  std::unique_ptr<Topology> topo_;
};

}  // namespace softcut::render
