#pragma once
// What the renderer needs from a frame, as engine/render's plain inputs:
// deformed positions, operational tets, interface nodes, manipulated nodes
// with their force lines, tool shapes, and the render settings at time t.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render/scene.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

// Operational tets, tissue groups and label ids, interface nodes (if shown),
// manipulated nodes with a line from each node to its tool's tip (if shown),
// and one shape per enabled tool (probe: ball-tipped rod; grasper: jaws,
// closed while engaged; scalpel: blade and handle).
render::SceneContent scene_content(const Model& m, const State& s);

// The unit direction a tool's shaft is drawn along, from its tip toward the
// handle: spec.shaft if given; a probe's or scalpel's against its force
// direction if given; else back along its approach (the way it came to its
// first contact, or, before one, from its first active frame's tip) once that
// is longer than its radius; else `up`.
Eigen::Vector3d shaft_axis(const tools::ToolSpec& spec, const tools::ToolState& ts, const Eigen::Vector3d& up);

// m.spec.outputs.render at the state's time: the palette of tissue_palette()
// and the camera of camera_settings().
render::RenderSettings render_settings(const Model& m, const State& s);
// The same from the stored settings, a palette and a camera (a re-render).
render::RenderSettings render_settings(const RenderSettings& r, const std::vector<Eigen::Vector3d>& palette,
                                       const render::CameraSettings& camera);
// The colour (RGB in [0, 1]) of each tissue group: s:material's `color`, else
// render.tissue_colors cycled, else the default palette's, in s:material call
// order; one more at the end for tets no call covers.
std::vector<Eigen::Vector3d> tissue_palette(const ScenarioSpec& spec);
// The camera at the state's time: RenderSettings' (fixed, or orbiting by
// `orbit`), or s:camera's (on a path, or following a tool along its shaft).
render::CameraSettings camera_settings(const Model& m, const State& s);

// Ids of the label image (frames/labels_NNNNNN.png; 0 is the background):
// each s:material call in order, the default material when some tet has it,
// the cut surface, each tool in declaration order.
struct LabelLegend {
  struct Entry {
    std::uint32_t id;
    std::string name, kind;  // kind: "tissue", "cut", "probe", "grasper", "scalpel"
  };
  std::vector<Entry> entries;
  std::vector<std::uint32_t> group;  // (materials + 1) id per tissue group (0: unused)
  std::uint32_t cut = 0;
  std::vector<std::uint32_t> tool;   // (tools) id per tool
};
LabelLegend label_legend(const Model& m);

// <dir>/frames/frame_000123.png
std::filesystem::path frame_png_path(const std::filesystem::path& dir, int frame);

}  // namespace softcut::sim
