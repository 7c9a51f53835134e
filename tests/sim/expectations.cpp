// The run loop's expectations (sim/expectations.hpp): bounds measured by the
// engine against the displacement read back here, check functions asked
// through the hook in declaration order, never-reached ones named, and the
// outcomes in summary.json.
#include "sim/expectations.hpp"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <fstream>

#include "fixtures.hpp"
#include "sim/outputs.hpp"
#include "sim/run.hpp"
#include "sim/step.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
namespace sim = softcut::sim;
using V = Eigen::Vector3d;

namespace {

// The cantilever (fixtures.hpp) for 1 s at 10 Hz with: the tip's mean uz in
// [-1, 0] m at 0.5 s (holds), the tip's largest |u| at most 1e-12 m at 0.7 s
// (fails: the tip sags), a check function at 0.3 s, and bounds at 0.95 s.
sim::ScenarioSpec spec_with_expectations(const fs::path& dir) {
  sim::ScenarioSpec s = softcut::test::cantilever_spec(dir, 1.0);
  sim::ExpectationSpec tip_z;
  tip_z.name = "tip sags";
  tip_z.where = "test:1";
  tip_z.at = 0.5;
  tip_z.bounds = true;
  tip_z.nodes = sim::NodeSelector::box(V(0.1, -1, -1), V(0.1, 1, 1));
  tip_z.component = sim::ExpectationSpec::Component::z;
  tip_z.min = -1.0;
  tip_z.max = 0.0;
  sim::ExpectationSpec still = tip_z;
  still.name = "tip still";
  still.at = 0.7;
  still.measure = sim::ExpectationSpec::Measure::max;
  still.component = sim::ExpectationSpec::Component::magnitude;
  still.min.reset();
  still.max = 1e-12;
  sim::ExpectationSpec check;
  check.name = "asked";
  check.at = 0.3;
  sim::ExpectationSpec late = tip_z;
  late.name = "late";
  late.at = 0.95;
  s.expectations = {tip_z, still, check, late};
  return s;
}

double mean_z(const sim::State& s, const std::vector<int>& nodes) {
  double sum = 0;
  for (int n : nodes) sum += s.displacement(n, 2);
  return sum / double(nodes.size());
}

}  // namespace

TEST_SUITE("sim/expectations") {
  TEST_CASE("parse_measure, parse_component: the names, and a misspelt one named") {
    CHECK(sim::parse_measure("mean") == sim::ExpectationSpec::Measure::mean);
    CHECK(sim::parse_measure("max") == sim::ExpectationSpec::Measure::max);
    for (const auto& [name, c] : {std::pair{"magnitude", sim::ExpectationSpec::Component::magnitude},
                                  {"x", sim::ExpectationSpec::Component::x}, {"y", sim::ExpectationSpec::Component::y},
                                  {"z", sim::ExpectationSpec::Component::z}})
      CHECK(sim::parse_component(name) == c);
    CHECK_THROWS_WITH(sim::parse_measure("maximum"), doctest::Contains("unknown measure 'maximum'"));
    CHECK_THROWS_WITH(sim::parse_component("magnitud"), doctest::Contains("(did you mean 'magnitude'?)"));
  }

  TEST_CASE("bounds are measured on the frame at their time, checks go through the hook in order") {
    const fs::path dir = softcut::test::scratch_dir("sim_expect_bounds");
    const sim::Model m = sim::compile(spec_with_expectations(dir));
    const std::vector<int> tip = sim::select_nodes(m, sim::NodeSelector::box(V(0.1, -1, -1), V(0.1, 1, 1)), "tip");
    REQUIRE(tip.size() == 9);
    sim::State s = sim::make_state(m);
    std::vector<int> asked;
    const sim::ExpectationCheck hook = [&](int index, const sim::Model&, sim::State& st) {
      asked.push_back(index);
      CHECK(st.time == doctest::Approx(0.3));
      return std::pair<bool, std::string>{false, "said no"};
    };
    double uz_at_half = 0, umax_at_07 = 0;
    while (s.frame < 8) {
      sim::step(m, s);
      sim::check_due_expectations(m, s, hook);
      if (s.frame == 5) uz_at_half = mean_z(s, tip);
      if (s.frame == 7)
        for (int n : tip) umax_at_07 = std::max(umax_at_07, s.displacement.row(n).norm());
    }
    sim::mark_unreached_expectations(m, s);
    REQUIRE(s.expectations.size() == 4);
    const sim::ExpectationOutcome &sag = s.expectations[0], &still = s.expectations[1], &chk = s.expectations[2],
                                   &late = s.expectations[3];
    CHECK(asked == std::vector<int>{2});
    CHECK(sag.reached);
    CHECK(sag.ok);
    CHECK(sag.time == doctest::Approx(0.5));
    REQUIRE(sag.value);
    // Same quantity, another expression: equal to rounding (compilers may fuse differently).
    CHECK(*sag.value == doctest::Approx(uz_at_half).epsilon(1e-14));
    CHECK(uz_at_half < 0);
    CHECK(sag.message.find("mean uz of 9 nodes at t = 0.5 s is ") == 0);
    CHECK(sag.message.find("within [-1, 0] m") != std::string::npos);
    CHECK(still.reached);
    CHECK(!still.ok);
    REQUIRE(still.value);
    CHECK(*still.value == doctest::Approx(umax_at_07).epsilon(1e-14));
    CHECK(still.message.find("max |u| of 9 nodes at t = 0.7 s") == 0);
    CHECK(still.message.find("outside [-inf, 1e-12] m") != std::string::npos);
    CHECK(chk.reached);
    CHECK(!chk.ok);
    CHECK(chk.message == "said no");
    CHECK(!chk.value);
    CHECK(!late.reached);
    CHECK(late.message == "not reached: the run ended at t = 0.8 s before at = 0.95 s");
  }

  TEST_CASE("a check without a hook fails with a message instead of passing") {
    const fs::path dir = softcut::test::scratch_dir("sim_expect_nohook");
    const sim::Model m = sim::compile(spec_with_expectations(dir));
    sim::State s = sim::make_state(m);
    while (s.frame < 3) sim::step(m, s), sim::check_due_expectations(m, s, {});
    CHECK(s.expectations[2].reached);
    CHECK(!s.expectations[2].ok);
    CHECK(s.expectations[2].message.find("no check function") != std::string::npos);
  }

  TEST_CASE("summary.json lists every expectation with its time, value, bounds and verdict") {
    const fs::path dir = softcut::test::scratch_dir("sim_expect_summary");
    sim::ScenarioSpec spec = spec_with_expectations(dir);
    spec.params = {{"force", "0.5"}, {"label", "a \"quoted\" one"}};
    spec.command_line = {"softcut", "run", "x.lua", "--set", "force=0.5"};
    const sim::Model m = sim::compile(spec);
    sim::State s = sim::make_state(m);
    sim::Recorder rec(m, dir);
    sim::RunHooks hooks;
    hooks.max_frames = 9;  // frames 0 .. 8: the run ends at t = 0.8 s
    hooks.check = [](int, const sim::Model&, sim::State&) { return std::pair<bool, std::string>{true, ""}; };
    sim::run(m, s, rec, hooks);
    const nlohmann::ordered_json j = softcut::test::read_json(dir / "summary.json");
    const auto& e = j.at("expectations");
    REQUIRE(e.size() == 4);
    CHECK(e[0].at("name") == "tip sags");
    CHECK(e[0].at("where") == "test:1");
    CHECK(e[0].at("kind") == "bounds");
    CHECK(e[0].at("measure") == "mean");
    CHECK(e[0].at("component") == "z");
    CHECK(e[0].at("nodes") == 9);
    CHECK(e[0].at("at_s") == 0.5);
    CHECK(e[0].at("min") == -1.0);
    CHECK(e[0].at("max") == 0.0);
    CHECK(e[0].at("reached") == true);
    CHECK(e[0].at("pass") == true);
    CHECK(e[0].at("value").get<double>() == doctest::Approx(*s.expectations[0].value).epsilon(1e-14));  // %.15g
    CHECK(e[0].at("time_s").get<double>() == doctest::Approx(0.5));
    CHECK(e[1].at("pass") == false);
    CHECK(e[1].at("min").is_null());
    CHECK(e[2].at("kind") == "check");
    CHECK(e[2].at("pass") == true);
    CHECK(e[2].at("value").is_null());
    CHECK(e[3].at("reached") == false);
    CHECK(e[3].at("pass") == false);
    CHECK(e[3].at("time_s").is_null());
    CHECK(e[3].at("message") == "not reached: the run ended at t = 0.8 s before at = 0.95 s");
    CHECK(j.at("params").at("force") == "0.5");
    CHECK(j.at("params").at("label") == "a \"quoted\" one");
    CHECK(j.at("command_line") == nlohmann::ordered_json({"softcut", "run", "x.lua", "--set", "force=0.5"}));
    CHECK(!j.at("versions").at("build_type").get<std::string>().empty());
  }

  TEST_CASE("bad expectations are refused naming the item") {
    sim::ScenarioSpec spec = spec_with_expectations(softcut::test::scratch_dir("sim_expect_bad"));
    spec.expectations[0].min = 1.0;
    spec.expectations[0].max = 0.5;
    CHECK_THROWS_WITH(sim::check_spec(spec), doctest::Contains("test:1: expectation 'tip sags': min = 1 > max = 0.5"));
    spec.expectations[0].min.reset();
    spec.expectations[0].max.reset();
    CHECK_THROWS_WITH(sim::check_spec(spec), doctest::Contains("give min, max or both"));
    spec = spec_with_expectations(softcut::test::scratch_dir("sim_expect_bad"));
    spec.expectations[1].at = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH(sim::check_spec(spec), doctest::Contains("expectation 'tip still': at must be a finite time"));
  }

  TEST_CASE("what expectations hold is bounded: their count, their names, a check's message") {
    sim::ScenarioSpec spec = spec_with_expectations(softcut::test::scratch_dir("sim_expect_bounded"));
    const sim::ExpectationSpec check = spec.expectations[2];
    spec.expectations.assign(sim::kMaxExpectations, check);
    for (std::size_t i = 0; i < spec.expectations.size(); ++i) spec.expectations[i].name = "e" + std::to_string(i);
    CHECK_NOTHROW(sim::check_spec(spec));
    spec.expectations.push_back(check);
    spec.expectations.back().where = "s.lua:9";
    CHECK_THROWS_WITH(sim::check_spec(spec),
                      doctest::Contains("s.lua:9: expectations: the scenario declares 10001 expectations, more than 10000"));
    spec.expectations.resize(3);
    spec.expectations[1].name = std::string(sim::kMaxExpectationName + 1, 'n');
    CHECK_THROWS_WITH(sim::check_spec(spec), doctest::Contains("expectation: the name is 1001 bytes long, more than 1000"));
    // A check function's long message is cut where the outcome is made.
    const sim::Model m = sim::compile(spec_with_expectations(softcut::test::scratch_dir("sim_expect_long")));
    sim::State s = sim::make_state(m);
    const sim::ExpectationCheck hook = [](int, const sim::Model&, sim::State&) {
      return std::pair<bool, std::string>{false, std::string(100000, 'x')};
    };
    while (s.frame < 3) sim::step(m, s), sim::check_due_expectations(m, s, hook);
    REQUIRE(s.expectations[2].reached);
    CHECK(s.expectations[2].message.size() < sim::kMaxExpectationMessage + 40);
    CHECK(s.expectations[2].message.find("... (100000 bytes, cut)") != std::string::npos);
  }
}
