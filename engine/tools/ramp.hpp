#pragma once
// Scalar functions of time that drive forces (N) and other scenario inputs.
// Pure and deterministic: the same ramp and time always give the same bits.
#include <string>
#include <vector>

namespace softcut::tools {

struct Ramp {
  enum class Kind { constant, linear, smoothstep, keyframes, sine };
  Kind kind = Kind::constant;

  // constant: `to` at every time.
  // linear / smoothstep: `from` until t0, `to` from t1 on, between them the
  // straight line / 3s^2 - 2s^3 with s = (t - t0) / (t1 - t0).
  double from = 0.0;
  double to = 0.0;
  double t0 = 0.0;  // s
  double t1 = 1.0;  // s, > t0

  // keyframes: piecewise linear through (times[k], values[k]), held constant
  // before the first and after the last key. times strictly increasing.
  std::vector<double> times;   // (nkey) s
  std::vector<double> values;  // (nkey)

  // sine: offset + amplitude * sin(2 pi frequency (t - t0) + phase) for
  // t >= t0, offset before t0.
  double offset = 0.0;
  double amplitude = 0.0;
  double frequency = 1.0;  // Hz
  double phase = 0.0;      // rad

  static Ramp constant_value(double v);
  static Ramp linear_ramp(double from, double to, double t0, double t1);
  static Ramp smoothstep_ramp(double from, double to, double t0, double t1);
  static Ramp keyframed(std::vector<double> times, std::vector<double> values);
  static Ramp sine_wave(double offset, double amplitude, double frequency, double phase = 0.0, double t0 = 0.0);
};

// Throws softcut::Error naming `where` (e.g. "load 'push' force") for
// non-finite numbers, t1 <= t0, unsorted or mismatched keyframes.
void check_ramp(const Ramp& r, const std::string& where);

double evaluate(const Ramp& r, double t);

const char* to_string(Ramp::Kind k);
// "constant", "linear", ... -> kind; throws naming `where` and the valid names.
Ramp::Kind ramp_kind_from_string(const std::string& name, const std::string& where);

}  // namespace softcut::tools
