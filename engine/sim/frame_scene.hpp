#pragma once
// What the renderer needs from a frame, as engine/render's plain inputs:
// deformed positions, operational tets, interface nodes, manipulated nodes
// with their force lines, tool shapes, and the render settings at time t.
#include <filesystem>

#include "render/scene.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

// Operational tets, interface nodes (if shown), manipulated nodes with a line
// from each node to its tool's tip (if shown), and one shape per enabled tool
// (probe: ball-tipped rod; grasper: jaws, closed while engaged).
render::SceneContent scene_content(const Model& m, const State& s);

// The unit direction a tool's shaft is drawn along, from its tip toward the
// handle: spec.shaft if given; a probe's or scalpel's against its force
// direction if given; else back along its approach (the way it came to its
// first contact, or, before one, from its first active frame's tip) once that
// is longer than its radius; else `up`.
Eigen::Vector3d shaft_axis(const tools::ToolSpec& spec, const tools::ToolState& ts, const Eigen::Vector3d& up);

// m.spec.outputs.render at the state's time (turntable azimuth applied).
render::RenderSettings render_settings(const Model& m, const State& s);

// <dir>/frames/frame_000123.png
std::filesystem::path frame_png_path(const std::filesystem::path& dir, int frame);

}  // namespace softcut::sim
