#include "tools/ramp.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace softcut::tools {

Ramp Ramp::constant_value(double v) {
  Ramp r;
  r.kind = Kind::constant;
  r.from = r.to = v;
  return r;
}

Ramp Ramp::linear_ramp(double from, double to, double t0, double t1) {
  Ramp r;
  r.kind = Kind::linear;
  r.from = from, r.to = to, r.t0 = t0, r.t1 = t1;
  return r;
}

Ramp Ramp::smoothstep_ramp(double from, double to, double t0, double t1) {
  Ramp r = linear_ramp(from, to, t0, t1);
  r.kind = Kind::smoothstep;
  return r;
}

Ramp Ramp::keyframed(std::vector<double> times, std::vector<double> values) {
  Ramp r;
  r.kind = Kind::keyframes;
  r.times = std::move(times);
  r.values = std::move(values);
  return r;
}

Ramp Ramp::sine_wave(double offset, double amplitude, double frequency, double phase, double t0) {
  Ramp r;
  r.kind = Kind::sine;
  r.offset = offset, r.amplitude = amplitude, r.frequency = frequency, r.phase = phase, r.t0 = t0;
  return r;
}

void check_ramp(const Ramp& r, const std::string& where) {
  auto finite = [&](double v, const char* field) {
    if (!std::isfinite(v)) fail(where, ": ramp field '", field, "' must be a finite number, got ", v);
  };
  switch (r.kind) {
    case Ramp::Kind::constant:
      finite(r.to, "to");
      break;
    case Ramp::Kind::linear:
    case Ramp::Kind::smoothstep:
      finite(r.from, "from"), finite(r.to, "to"), finite(r.t0, "t0"), finite(r.t1, "t1");
      if (!(r.t1 > r.t0)) fail(where, ": ", to_string(r.kind), " ramp needs t1 > t0 (got t0 = ", r.t0, ", t1 = ", r.t1, ")");
      break;
    case Ramp::Kind::keyframes:
      if (r.times.empty()) fail(where, ": keyframes ramp needs at least one key");
      if (r.times.size() != r.values.size())
        fail(where, ": keyframes ramp has ", r.times.size(), " times but ", r.values.size(), " values");
      for (size_t k = 0; k < r.times.size(); ++k) {
        if (!std::isfinite(r.times[k]) || !std::isfinite(r.values[k]))
          fail(where, ": keyframe ", k + 1, " is not finite (t = ", r.times[k], ", value = ", r.values[k], ")");
        if (k > 0 && !(r.times[k] > r.times[k - 1]))
          fail(where, ": keyframe times must increase (key ", k + 1, " at t = ", r.times[k], " after ", r.times[k - 1], ")");
      }
      break;
    case Ramp::Kind::sine:
      finite(r.offset, "offset"), finite(r.amplitude, "amplitude"), finite(r.frequency, "frequency");
      finite(r.phase, "phase"), finite(r.t0, "t0");
      if (r.frequency < 0) fail(where, ": sine ramp frequency must be >= 0 Hz, got ", r.frequency);
      break;
  }
}

double evaluate(const Ramp& r, double t) {
  switch (r.kind) {
    case Ramp::Kind::constant:
      return r.to;
    case Ramp::Kind::linear:
    case Ramp::Kind::smoothstep: {
      if (t <= r.t0) return r.from;
      if (t >= r.t1) return r.to;
      double s = (t - r.t0) / (r.t1 - r.t0);
      if (r.kind == Ramp::Kind::smoothstep) s = s * s * (3.0 - 2.0 * s);
      return r.from + (r.to - r.from) * s;
    }
    case Ramp::Kind::keyframes: {
      const auto& T = r.times;
      if (T.empty()) return 0.0;
      if (t <= T.front()) return r.values.front();
      if (t >= T.back()) return r.values.back();
      const size_t k = size_t(std::upper_bound(T.begin(), T.end(), t) - T.begin());  // T[k-1] <= t < T[k]
      const double s = (t - T[k - 1]) / (T[k] - T[k - 1]);
      return r.values[k - 1] + (r.values[k] - r.values[k - 1]) * s;
    }
    case Ramp::Kind::sine:
      if (t < r.t0) return r.offset;
      return r.offset + r.amplitude * std::sin(2.0 * std::numbers::pi * r.frequency * (t - r.t0) + r.phase);
  }
  return 0.0;
}

const char* to_string(Ramp::Kind k) {
  switch (k) {
    case Ramp::Kind::constant: return "constant";
    case Ramp::Kind::linear: return "linear";
    case Ramp::Kind::smoothstep: return "smoothstep";
    case Ramp::Kind::keyframes: return "keyframes";
    case Ramp::Kind::sine: return "sine";
  }
  return "?";
}

Ramp::Kind ramp_kind_from_string(const std::string& name, const std::string& where) {
  for (auto k : {Ramp::Kind::constant, Ramp::Kind::linear, Ramp::Kind::smoothstep, Ramp::Kind::keyframes,
                 Ramp::Kind::sine})
    if (name == to_string(k)) return k;
  fail(where, ": unknown ramp kind '", name, "' (use constant, linear, smoothstep, keyframes or sine)");
}

}  // namespace softcut::tools
