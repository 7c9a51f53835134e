#pragma once
// The render record's meta data (its first chunk, sim/render_record.hpp):
// the scenario's name and frame rate, the render settings by name, the
// tissue palette and the label legend; written from a Model, read back
// checked, and whether a run writes a record at all.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/json_text.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

// RenderSettings::Record::automatic writes the record when its estimate
// (the positions of the surface and interface nodes, every rendered frame)
// stays under this.
inline constexpr double kRecordAutoBytes = 256.0 * (1 << 20);

// Whether the run writes render_record.bin: rendering on and record `on`,
// or `automatic` and small enough.
bool wants_render_record(const Model& m);

// The record's meta data: the scenario's name, frame rate, the render
// settings as the run had them (RenderSettings by name), the tissue palette
// and the label legend.
Json render_record_meta(const Model& m);

// The meta data as read back, checked (a record is untrusted): every number
// within the bounds check_spec puts on a scenario's.
struct RecordMeta {
  std::string scenario;
  double fps = 30;
  RenderSettings render;
  std::vector<Eigen::Vector3d> palette;  // RGB in [0, 1] per tissue group
  Json legend = Json::array();
};
RecordMeta parse_record_meta(const Json& meta, const std::string& what);

}  // namespace softcut::sim
