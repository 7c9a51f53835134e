#include "sim/render_record_meta.hpp"

#include "core/error.hpp"
#include "core/printable.hpp"
#include "sim/frame_outputs.hpp"
#include "sim/frame_scene.hpp"
#include "sim/render_record.hpp"

namespace softcut::sim {

namespace {

const char* style_name(RenderSettings::Style st) {
  return st == RenderSettings::Style::paper ? "paper" : st == RenderSettings::Style::debug ? "debug" : "clinical";
}

Json vec_json(const Eigen::Vector3d& v) { return Json::array({json_number(v.x()), json_number(v.y()), json_number(v.z())}); }

// Reads the meta data's fields, each checked: a record is untrusted.
struct MetaReader {
  const Json& j;
  const std::string& what;
  [[noreturn]] void bad(const std::string& key, const std::string& why) const {
    fail(what, ": meta data '", key, "' ", why);
  }
  const Json& at(const Json& o, const std::string& key) const {
    if (!o.is_object() || !o.contains(key)) bad(key, "is missing");
    return o.at(key);
  }
  double num(const Json& o, const std::string& key, double lo, double hi) const {
    const Json& v = at(o, key);
    if (!v.is_number()) bad(key, "is not a number");
    const double d = v.get<double>();
    if (!(d >= lo && d <= hi)) bad(key, cat("= ", d, " is outside [", lo, ", ", hi, "]"));
    return d;
  }
  bool flag(const Json& o, const std::string& key) const {
    const Json& v = at(o, key);
    if (!v.is_boolean()) bad(key, "is not true or false");
    return v.get<bool>();
  }
  Eigen::Vector3d vec(const Json& v, const std::string& key, double lo, double hi) const {
    if (!v.is_array() || v.size() != 3) bad(key, "is not a 3-vector");
    Eigen::Vector3d out;
    for (int k = 0; k < 3; ++k) {
      if (!v[std::size_t(k)].is_number()) bad(key, "is not a 3-vector of numbers");
      out[k] = v[std::size_t(k)].get<double>();
      if (!(out[k] >= lo && out[k] <= hi)) bad(key, "has a component outside its range");
    }
    return out;
  }
};

}  // namespace

bool wants_render_record(const Model& m) {
  const RenderSettings& r = m.spec.outputs.render;
  if (!r.enabled || r.record == RenderSettings::Record::off) return false;
  if (r.record == RenderSettings::Record::on) return true;
  const double frames = double(m.num_frames) / double(r.every) + 1;
  const double nodes = double(m.surface.nodes.size() + m.partition.interface.size());
  return frames * nodes * 24.0 + double(m.mesh.num_tets()) * 30.0 <= kRecordAutoBytes;
}

Json render_record_meta(const Model& m) {
  const RenderSettings& r = m.spec.outputs.render;
  Json palette = Json::array();
  for (const Eigen::Vector3d& c : tissue_palette(m.spec)) palette.push_back(vec_json(c));
  Json tissue = Json::array();
  for (const Eigen::Vector3d& c : r.tissue_colors) tissue.push_back(vec_json(c));
  return {{"schema", "softcut-render-record/1"},
          {"scenario", m.spec.name},
          {"fps", json_number(m.spec.timeline.fps)},
          {"render",
           {{"width", r.width}, {"height", r.height}, {"msaa", r.msaa_samples}, {"every", r.every},
            {"style", style_name(r.style)}, {"background", vec_json(r.background)},
            {"cut_color", vec_json(r.cut_color)}, {"tissue_colors", tissue}, {"show_inclusions", r.show_inclusions},
            {"wireframe", r.wireframe}, {"show_interface", r.show_interface}, {"show_forces", r.show_forces},
            {"show_loads", r.show_loads}, {"contact_sheet", r.contact_sheet}, {"depth", r.depth},
            {"labels", r.labels}, {"video", r.video}}},
          {"palette", palette},
          {"legend", legend_json(label_legend(m))}};
}

RecordMeta parse_record_meta(const Json& j, const std::string& what) {
  const MetaReader in{j, what};
  RecordMeta m;
  const Json& name = in.at(j, "scenario");
  if (!name.is_string()) in.bad("scenario", "is not a string");
  m.scenario = printable(name.get<std::string>(), 200);
  m.fps = in.num(j, "fps", 1e-9, 10000);
  const Json& r = in.at(j, "render");
  RenderSettings& s = m.render;
  s.enabled = true;
  s.width = int(in.num(r, "width", 1, 16384));
  s.height = int(in.num(r, "height", 1, 16384));
  s.msaa_samples = int(in.num(r, "msaa", 0, 16));
  s.every = int(in.num(r, "every", 1, 1e9));
  const Json& style = in.at(r, "style");
  if (style == "paper") s.style = RenderSettings::Style::paper;
  else if (style == "debug") s.style = RenderSettings::Style::debug;
  else if (style == "clinical") s.style = RenderSettings::Style::clinical;
  else in.bad("render.style", "is not clinical, paper or debug");
  s.background = in.vec(in.at(r, "background"), "render.background", 0, 1);
  s.cut_color = in.vec(in.at(r, "cut_color"), "render.cut_color", 0, 1);
  const Json& tissue = in.at(r, "tissue_colors");
  if (!tissue.is_array() || tissue.size() > 256) in.bad("render.tissue_colors", "is not a list of at most 256 colours");
  for (const Json& c : tissue) s.tissue_colors.push_back(in.vec(c, "render.tissue_colors", 0, 1));
  s.show_inclusions = in.flag(r, "show_inclusions");
  s.wireframe = in.flag(r, "wireframe");
  s.show_interface = in.flag(r, "show_interface");
  s.show_forces = in.flag(r, "show_forces");
  s.show_loads = in.flag(r, "show_loads");
  s.contact_sheet = in.flag(r, "contact_sheet");
  s.depth = in.flag(r, "depth");
  s.labels = in.flag(r, "labels");
  s.video = in.flag(r, "video");
  const Json& palette = in.at(j, "palette");
  if (!palette.is_array() || palette.empty() || palette.size() > 100000) in.bad("palette", "is not a list of colours");
  for (const Json& c : palette) m.palette.push_back(in.vec(c, "palette", 0, 1));
  const Json& legend = in.at(j, "legend");
  if (!legend.is_array() || legend.size() > 256) in.bad("legend", "is not a list of at most 256 entries");
  for (const Json& e : legend) {
    const Json& id = in.at(e, "id");
    const Json& nm = in.at(e, "name");
    const Json& kind = in.at(e, "kind");
    if (!id.is_number_unsigned() || id.get<std::uint64_t>() > 255 || !nm.is_string() || !kind.is_string())
      in.bad("legend", "has an entry that is not {id 0..255, name, kind}");
    m.legend.push_back({{"id", id}, {"name", printable(nm.get<std::string>(), 200)},
                        {"kind", printable(kind.get<std::string>(), 40)}});
  }
  return m;
}

}  // namespace softcut::sim
