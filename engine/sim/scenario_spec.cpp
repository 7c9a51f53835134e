#include "sim/scenario_spec.hpp"

#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/printable.hpp"
#include "core/suggest.hpp"

namespace softcut::sim {

namespace {

std::string prefixed(const std::string& where, const std::string& item) {
  return where.empty() ? item : where + ": " + item;
}

}  // namespace

void check_scenario_name(const std::string& name) {
  const auto bad = [&](const char* why) {
    fail("scenario '", printable(name, 120), "': name ", why,
         "; it names the output folder renders/<name>/: use letters, digits, '_', '-' and '.' (e.g. liver_cut)");
  };
  if (name.empty()) bad("must not be empty");
  if (name == "." || name == "..") bad("must not be '.' or '..'");
  if (name.size() > 100) bad("must not be longer than 100 bytes");
  for (unsigned char c : name) {
    if (c == '/' || c == '\\') bad("must not contain path separators");
    if (c < 0x20 || c == 0x7F) bad("must not contain control characters");
  }
}

void check_spec(const ScenarioSpec& s) {
  check_scenario_name(s.name);
  const Timeline& tl = s.timeline;
  const std::string tw = prefixed(!tl.where.empty() ? tl.where : s.source.empty() ? "" : s.source.filename().string(),
                                  "timeline");
  if (!(tl.duration >= 0) || !std::isfinite(tl.duration))
    fail(tw, ": duration must be a finite number >= 0 s, got ", tl.duration);
  // 1 / fps is the time step: 5e-324 Hz made it infinite, and every frame's time NaN.
  if (!(tl.fps > 0) || !std::isfinite(tl.fps))
    fail(tw, ": fps must be > 0 Hz, got ", tl.fps, " (it must lie in [", Timeline::kMinFps, ", ", Timeline::kMaxFps, "])");
  if (!(tl.fps >= Timeline::kMinFps && tl.fps <= Timeline::kMaxFps))
    fail(tw, ": fps = ", tl.fps, " Hz is out of range: it must lie in [", Timeline::kMinFps, ", ", Timeline::kMaxFps,
         "] (a frame at most every 1000 s, at least every 0.1 ms)");
  if (tl.duration * tl.fps > Timeline::kMaxFrames)
    fail(tw, ": ", tl.duration * tl.fps, " frames (duration x frame rate) is too many; the limit is 10000000, "
         "shorten the duration or lower the frame rate");

  for (const auto& m : s.materials) {
    const std::string w = prefixed(m.where, "material '" + m.name + "'");
    if (m.preset.empty()) {
      fem::check_material({m.young, m.poisson}, w);
    } else {
      if (m.young != 0 && !(m.young > 0 && std::isfinite(m.young))) fail(w, ": young must be > 0 Pa, got ", m.young);
    }
    if (m.density != 0 && !(m.density > 0 && m.density <= 1e5))
      fail(w, ": density must lie in (0, 100000] kg/m^3, got ", m.density);
    if (m.has_color && !(m.color.allFinite() && m.color.minCoeff() >= 0 && m.color.maxCoeff() <= 1))
      fail(w, ": color must be RGB in [0, 1]");
  }
  if (!s.gravity.allFinite() || s.gravity.norm() > 1e4)
    fail("gravity: must be a finite vector of at most 10000 m/s^2 (about 1000 g), got (", s.gravity.transpose(), ")");
  for (const auto& a : s.prestress) {
    const std::string w = prefixed(a.where, "prestress '" + a.name + "'");
    if (!a.strain.allFinite() || a.strain != a.strain.transpose())
      fail(w, ": the strain must be a finite symmetric tensor");
    fem::Material probe;
    probe.initial_strain = voigt_strain(a.strain);
    fem::check_material(probe, w);
  }
  std::set<std::string> names;
  for (const auto& l : s.loads) {
    const std::string w = prefixed(l.where, "load '" + l.name + "'");
    if (!names.insert("load " + l.name).second) fail(w, ": another load has the same name");
    tools::check_ramp(l.magnitude, w + " magnitude");
    if (l.direction_kind == LoadSpec::Direction::world && !(l.direction.norm() > 0 && l.direction.allFinite()))
      fail(w, ": direction must be a nonzero finite vector, got (", l.direction.transpose(), ")");
  }
  for (const auto& mo : s.motions) {
    const std::string w = prefixed(mo.where, "motion '" + mo.name + "'");
    if (!names.insert("motion " + mo.name).second) fail(w, ": another motion has the same name");
    tools::check_path(mo.path, w);
  }
  if (s.expectations.size() > kMaxExpectations)
    fail(prefixed(s.expectations[kMaxExpectations].where, "expectations"), ": the scenario declares ",
         s.expectations.size(), " expectations, more than ", kMaxExpectations, "; check fewer things, or several at "
         "once in one check function");
  for (const auto& e : s.expectations) {
    if (e.name.size() > kMaxExpectationName)
      fail(prefixed(e.where, "expectation"), ": the name is ", e.name.size(), " bytes long, more than ",
           kMaxExpectationName);
    const std::string w = prefixed(e.where, "expectation '" + e.name + "'");
    if (!(std::isfinite(e.at) && e.at >= 0)) fail(w, ": at must be a finite time >= 0 s, got ", e.at);
    if (e.at > tl.duration + 1e-12)
      fail(w, ": at = ", e.at, " s is after the end of the timeline (duration = ", tl.duration, " s)");
    if (e.bounds && !e.min && !e.max) fail(w, ": give min, max or both (m)");
    if ((e.min && !std::isfinite(*e.min)) || (e.max && !std::isfinite(*e.max)))
      fail(w, ": min and max must be finite numbers (m)");
    if (e.min && e.max && *e.min > *e.max) fail(w, ": min = ", *e.min, " > max = ", *e.max);
    if (!e.bounds && (e.min || e.max))
      fail(w, ": min/max bound the displacement of `nodes`; with `check` return false, \"why\" instead");
  }
  for (const auto& t : s.tools) {
    if (!names.insert("tool " + t.name).second)
      fail(prefixed(t.where, "tool '" + t.name + "'"), ": another tool has the same name");
    tools::check_tool(t, "");
  }
  const OutputSpec& o = s.outputs;
  if (o.vtu_every < 1) fail("outputs: vtu_every must be >= 1, got ", o.vtu_every);
  const RenderSettings& r = o.render;
  if (r.width < 1 || r.height < 1 || r.width > 16384 || r.height > 16384)
    fail("outputs.render: size must be 1..16384 pixels, got ", r.width, " x ", r.height);
  if (!(r.fov_deg > 0 && r.fov_deg < 180)) fail("outputs.render: fov_deg must lie in (0, 180), got ", r.fov_deg);
  if (r.every < 1) fail("outputs.render: every must be >= 1, got ", r.every);
  if (!r.eye.allFinite() || !r.target.allFinite() || !(r.up.norm() > 0))
    fail("outputs.render: eye and target must be finite and up nonzero");
  if (!(r.elevation_deg > -90 && r.elevation_deg < 90))
    fail(prefixed(o.where, "output: render"), ": elevation must lie in (-90, 90) degrees, got ", r.elevation_deg,
         " (at +-90 the camera looks along `up` and has no horizon; to look straight down use 89.9)");
  if (!std::isfinite(r.azimuth_deg) || !std::isfinite(r.orbit_deg_per_s))
    fail("outputs.render: azimuth_deg and orbit_deg_per_s must be finite");
  if (!r.background.allFinite() || r.background.minCoeff() < 0 || r.background.maxCoeff() > 1)
    fail("outputs.render: background components must lie in [0, 1]");
  if (!r.cut_color.allFinite() || r.cut_color.minCoeff() < 0 || r.cut_color.maxCoeff() > 1)
    fail("outputs.render: cut_color must be RGB in [0, 1]");
  if (r.tissue_colors.size() > 256) fail("outputs.render: at most 256 tissue colours, got ", r.tissue_colors.size());
  for (size_t i = 0; i < r.tissue_colors.size(); ++i)
    if (!r.tissue_colors[i].allFinite() || r.tissue_colors[i].minCoeff() < 0 || r.tissue_colors[i].maxCoeff() > 1)
      fail("outputs.render: tissue colour ", i + 1, " has components outside [0, 1]");
  if (r.msaa_samples < 0 || r.msaa_samples > 16) fail("outputs.render: msaa_samples must be 0..16");
  const CameraSpec& c = s.outputs.camera;
  if (c.kind != CameraSpec::Kind::none) {
    const std::string w = prefixed(c.where, "camera");
    if (!c.up.allFinite() || c.up.norm() == 0) fail(w, ": up must be a finite, nonzero vector");
    if (c.fov_deg != 0 && !(c.fov_deg > 0 && c.fov_deg < 180)) fail(w, ": fov must lie in (0, 180) degrees, got ", c.fov_deg);
    if (c.kind == CameraSpec::Kind::path && !c.target_moves && !c.target.allFinite()) fail(w, ": target must be finite");
    if (c.kind == CameraSpec::Kind::follow) {
      bool found = false;
      for (const auto& t : s.tools) found = found || t.name == c.follow;
      if (!found) fail(w, ": follows tool '", printable(c.follow, 80), "', which the scenario does not define");
      if (!(c.distance > 0 && std::isfinite(c.distance))) fail(w, ": distance must be > 0 m, got ", c.distance);
      if (!(c.offset >= 0 && std::isfinite(c.offset))) fail(w, ": offset must be >= 0 m, got ", c.offset);
      if (!std::isfinite(c.lead)) fail(w, ": lead must be finite");
    }
  }
  if (!(s.solver.cg_tolerance > 0 && s.solver.cg_tolerance < 1))
    fail("solver: cg_tolerance must lie in (0, 1), got ", s.solver.cg_tolerance);
  if (s.solver.cg_max_iterations < 0) fail("solver: cg_max_iterations must be >= 0");
  if (!(s.cutting.snap_fraction > 0 && s.cutting.snap_fraction < 0.5))
    fail("cutting: snap_fraction must lie in (0, 0.5), got ", s.cutting.snap_fraction);
  if (!(s.cutting.min_dihedral_deg >= 0 && s.cutting.min_dihedral_deg < 60))
    fail("cutting: min_dihedral_deg must lie in [0, 60), got ", s.cutting.min_dihedral_deg);
}

const char* to_string(LoadSpec::Direction d) { return d == LoadSpec::Direction::world ? "world" : "normal"; }

std::array<double, 6> voigt_strain(const Eigen::Matrix3d& e) {
  return {e(0, 0), e(1, 1), e(2, 2), 2 * e(1, 2), 2 * e(2, 0), 2 * e(0, 1)};
}

LoadSpec::Direction parse_load_direction(std::string_view text) {
  if (text == "world") return LoadSpec::Direction::world;
  if (text == "normal") return LoadSpec::Direction::normal;
  fail("load: unknown direction kind '", printable(text), "'", suggest(text, {"world", "normal"}));
}

RenderSettings::Style parse_render_style(std::string_view text) {
  if (text == "clinical") return RenderSettings::Style::clinical;
  if (text == "paper") return RenderSettings::Style::paper;
  if (text == "debug") return RenderSettings::Style::debug;
  fail("render: unknown style '", printable(text), "'", suggest(text, {"clinical", "paper", "debug"}));
}

CameraSpec::Kind parse_camera_kind(std::string_view text) {
  if (text == "path") return CameraSpec::Kind::path;
  if (text == "follow") return CameraSpec::Kind::follow;
  fail("camera: unknown kind '", printable(text), "'", suggest(text, {"path", "follow"}));
}

}  // namespace softcut::sim
