#include "sim/expectations.hpp"

#include <cmath>
#include <cstdio>

#include "core/printable.hpp"
#include "core/suggest.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

namespace {

// printf's %.<digits>g, as the Lua layer wrote these messages before.
std::string g(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// The measured value of a bounds expectation, m.
double measure(const State& s, const ExpectationSpec& e, const std::vector<int>& nodes) {
  using C = ExpectationSpec::Component;
  if (e.measure == ExpectationSpec::Measure::max) {
    double best = 0;
    for (int n : nodes) {
      const Eigen::RowVector3d u = s.displacement.row(n);
      const double v = e.component == C::magnitude ? u.norm() : u(int(e.component) - 1);
      if (std::abs(v) > std::abs(best)) best = v;
    }
    return best;
  }
  const Eigen::Vector3d mean = mean_displacement(s, nodes);
  return e.component == C::magnitude ? mean.norm() : mean(int(e.component) - 1);
}

}  // namespace

const char* to_string(ExpectationSpec::Measure v) { return v == ExpectationSpec::Measure::max ? "max" : "mean"; }

const char* to_string(ExpectationSpec::Component v) {
  switch (v) {
    case ExpectationSpec::Component::magnitude: return "magnitude";
    case ExpectationSpec::Component::x: return "x";
    case ExpectationSpec::Component::y: return "y";
    case ExpectationSpec::Component::z: return "z";
  }
  return "?";
}

void check_due_expectations(const Model& m, State& s, const ExpectationCheck& check) {
  const std::vector<ExpectationSpec>& specs = m.spec.expectations;
  s.expectations.resize(specs.size());
  for (size_t i = 0; i < specs.size(); ++i) {
    const ExpectationSpec& e = specs[i];
    ExpectationOutcome& o = s.expectations[i];
    if (o.reached || s.time < e.at - 0.5 * m.dt) continue;
    o.reached = true;
    o.time = s.time;
    if (e.bounds) {
      const std::vector<int>& nodes = m.expectation_nodes[i];
      const double u = measure(s, e, nodes);
      o.value = u;
      o.ok = (!e.min || u >= *e.min) && (!e.max || u <= *e.max);
      const bool mag = e.component == ExpectationSpec::Component::magnitude;
      o.message = cat(to_string(e.measure), " ", mag ? std::string("|u|") : std::string("u") + to_string(e.component),
                      " of ", nodes.size(), " nodes at t = ", g(s.time, 4), " s is ", g(u, 6), " m, ",
                      o.ok ? "within" : "outside", " [", e.min ? g(*e.min, 6) : "-inf", ", ",
                      e.max ? g(*e.max, 6) : "inf", "] m");
    } else if (check) {
      auto [ok, message] = check(int(i), m, s);
      o.ok = ok;
      if (message.size() > kMaxExpectationMessage)
        message = cat(message.substr(0, kMaxExpectationMessage), "... (", message.size(), " bytes, cut)");
      o.message = std::move(message);
    } else {
      o.message = "no check function to run (the scenario layer gave none)";
    }
  }
}

void mark_unreached_expectations(const Model& m, State& s) {
  s.expectations.resize(m.spec.expectations.size());
  for (size_t i = 0; i < s.expectations.size(); ++i)
    if (!s.expectations[i].reached)
      s.expectations[i].message =
          cat("not reached: the run ended at t = ", s.time, " s before at = ", m.spec.expectations[i].at, " s");
}

ExpectationSpec::Measure parse_measure(std::string_view text) {
  if (text == "mean") return ExpectationSpec::Measure::mean;
  if (text == "max") return ExpectationSpec::Measure::max;
  fail("expect: unknown measure '", printable(text), "'", suggest(text, {"mean", "max"}));
}

ExpectationSpec::Component parse_component(std::string_view text) {
  using C = ExpectationSpec::Component;
  if (text == "magnitude") return C::magnitude;
  if (text == "x") return C::x;
  if (text == "y") return C::y;
  if (text == "z") return C::z;
  fail("expect: unknown component '", printable(text), "'", suggest(text, {"magnitude", "x", "y", "z"}));
}

}  // namespace softcut::sim
