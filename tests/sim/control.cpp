// sim/control: the run-control calls a script makes between frames, and the
// metrics it records (their statistics against the values put in, and the
// names and values that are refused).
#include "sim/control.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sim/model.hpp"
#include "fixtures.hpp"
#include "test_support.hpp"

namespace sim = softcut::sim;
namespace test = softcut::test;

TEST_SUITE("sim/control") {
  TEST_CASE("a metric keeps its last value with its frame and time, its min, max, mean and samples") {
    sim::State s;
    const double values[] = {2.0, -1.5, 4.0, 0.5};
    for (int f = 0; f < 4; ++f) {
      s.frame = f, s.time = 0.1 * f;
      sim::record_metric(s, "gap.mm", values[f]);
      if (f == 1) sim::record_metric(s, "_force-N", 7.0);
    }
    REQUIRE(s.metrics.size() == 2);
    const sim::Metric& g = s.metrics[0];
    CHECK(g.name == "gap.mm");
    CHECK(g.value == 0.5);
    CHECK(g.min == -1.5);
    CHECK(g.max == 4.0);
    CHECK(g.sum / g.samples == doctest::Approx(1.25));
    CHECK(g.samples == 4);
    CHECK(g.frame == 3);
    CHECK(g.time == doctest::Approx(0.3));
    CHECK(s.metrics[1].name == "_force-N");
    CHECK(s.metrics[1].frame == 1);
  }

  TEST_CASE("names that cannot be a CSV column, values that are not finite and a 257th name are errors") {
    sim::State s;
    for (const std::string& bad : std::vector<std::string>{"", "1st", "jaw force", "a,b", "quote\"", std::string(65, 'a'), "tab\t"}) {
      CAPTURE(bad);
      CHECK(test::contains(test::error_of([&] { sim::record_metric(s, bad, 1.0); }), "is not 1 to 64 letters"));
    }
    sim::record_metric(s, std::string(64, 'a'), 1.0);
    CHECK(test::contains(test::error_of([&] { sim::record_metric(s, "x", NAN); }), "metric 'x' is nan"));
    CHECK(test::contains(test::error_of([&] { sim::record_metric(s, "x", INFINITY); }), "not a finite number"));
    for (std::size_t i = s.metrics.size(); i < sim::kMaxMetrics; ++i) sim::record_metric(s, "m" + std::to_string(i), 1.0);
    CHECK(s.metrics.size() == sim::kMaxMetrics);
    sim::record_metric(s, "m5", 2.0);  // an existing name still records
    CHECK(test::contains(test::error_of([&] { sim::record_metric(s, "one_more", 1.0); }), "at most 256"));
  }

  TEST_CASE("tools and loads change from the next frame, an index out of range is an error") {
    sim::ScenarioSpec spec = test::cantilever_spec(test::scratch_dir("control"));
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    REQUIRE(!s.loads.empty());
    sim::set_load(s, 0, 2.5, std::nullopt);
    CHECK(s.loads[0].scale == 2.5);
    CHECK(s.loads[0].enabled);
    sim::set_load(s, 0, std::nullopt, false);
    CHECK(s.loads[0].scale == 2.5);
    CHECK(!s.loads[0].enabled);
    CHECK(test::contains(test::error_of([&] { sim::set_load(s, 0, NAN, std::nullopt); }), "the scale is not finite"));
    CHECK(test::contains(test::error_of([&] { sim::set_load(s, int(s.loads.size()), 1.0, std::nullopt); }),
                         "out of range"));
    CHECK(test::contains(test::error_of([&] { sim::move_tool(s, 0, Eigen::Vector3d::Zero()); }), "tool 0 out of range"));
    CHECK(test::contains(test::error_of([&] { sim::enable_tool(s, -1, true); }), "tool -1 out of range"));
    sim::request_stop(s);
    CHECK(s.stop_requested);
  }
}
