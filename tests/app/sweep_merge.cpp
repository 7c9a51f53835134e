// app/sweep_merge.cpp: the summaries of a sweep read field by field and
// gathered into one table, from a folder made by hand.
#include "app/sweep_merge.hpp"

#include <doctest/doctest.h>

#include <fstream>

#include "app/sweep_plan.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace softcut::app;
using softcut::test::contains;
using softcut::test::error_of;

namespace {

nlohmann::json summary(const std::string& f, const std::string& reason = "completed") {
  return {{"command_line", {"softcut", "run", "s.lua", "--set", "f=" + f}},
          {"run", {{"frames", 3}, {"last_time_s", 0.2}, {"exit_reason", reason}}},
          {"cutting", {{"events", 2}, {"detached_pieces", 1}}},
          {"expectations",
           {{{"name", "sag"}, {"value", -0.5}, {"pass", true}, {"reached", true}, {"message", "ok"}},
            {{"name", "holds"}, {"value", nullptr}, {"pass", reason == "completed"}, {"reached", true}}}}};
}

void make_sweep(const fs::path& dir, const std::vector<std::string>& values) {
  SweepPlan plan;
  plan.scenario = "/abs/s.lua";
  plan.keys = {"f"};
  for (const auto& v : values) plan.runs.push_back({"", {{"f", v}}});
  number_runs(plan.runs);
  fs::create_directories(dir);
  std::ofstream(dir / "sweep_plan.json") << plan_json(plan);
}

void put_summary(const fs::path& dir, const std::string& id, const nlohmann::json& s) {
  fs::create_directories(dir / id);
  std::ofstream(dir / id / "summary.json") << s.dump();
}

}  // namespace

TEST_SUITE("app/sweep_merge") {
  TEST_CASE("a summary is read field by field - optional fields take their defaults") {
    const RunSummary s = parse_run_summary(summary("1").dump(), "x.json");
    CHECK(s.exit_reason == "completed");
    CHECK(s.frames == 3);
    CHECK(s.cut_events == 2);
    REQUIRE(s.expectations.size() == 2);
    CHECK(s.expectations[0].value == -0.5);
    CHECK(s.expectations[1].value.is_null());
    CHECK(s.expectations[1].message == "");
    nlohmann::json bare = summary("1");
    bare.erase("cutting");
    bare["run"].erase("last_time_s");
    const RunSummary b = parse_run_summary(bare.dump(), "x.json");
    CHECK(b.cut_events == 0);
    CHECK(b.last_time_s.is_null());
    nlohmann::json long_message = summary("1");
    long_message["run"]["message"] = std::string(5000, 'm');
    CHECK(parse_run_summary(long_message.dump(), "x.json").message.size() <= kMaxMergedMessage + 3);
    nlohmann::json long_name = summary("1");
    long_name["expectations"][0]["name"] = std::string(1001, 'n');
    CHECK(contains(error_of([&] { parse_run_summary(long_name.dump(), "x.json"); }),
                   "x.json: not a summary softcut wrote: 'expectations[0].name' is 1001 bytes long, more than 1000"));
    CHECK(contains(error_of([&] { parse_run_summary("{", "x.json"); }), "x.json: not valid JSON"));
    CHECK(contains(error_of([&] { parse_run_summary("[]", "x.json"); }), "'the document' is not an object"));
  }

  TEST_CASE("merge: the table of a folder made by hand - missing runs listed - a foreign run refused") {
    const fs::path dir = softcut::test::scratch_dir("sweep_merge_unit");
    make_sweep(dir, {"1", "2"});
    put_summary(dir, "run_0000", summary("1"));
    CHECK(merge_sweep(dir).missing == std::vector<std::string>{"run_0001"});
    put_summary(dir, "run_0001", summary("2", "error"));
    const SweepMerge m = merge_sweep(dir);
    CHECK(m.passed == 1);
    CHECK(m.failed == 1);
    CHECK(m.csv ==
          "id,f,pass,exit_reason,frames,last_time_s,cut_events,detached_pieces,expect.sag,expect.holds\n"
          "run_0000,1,true,completed,3,0.2,2,1,-0.5,true\n"
          "run_0001,2,false,error,3,0.2,2,1,-0.5,false\n");
    // sweep.json, written a row at a time, is exactly nlohmann-json's text of itself.
    const auto doc = nlohmann::ordered_json::parse(m.json);
    CHECK(m.json == doc.dump(1, ' ') + "\n");
    CHECK(doc["rows"].size() == 2);
    CHECK(doc["rows"][1]["expectations"][1]["pass"] == false);
    put_summary(dir, "run_0001", summary("3"));
    CHECK(contains(error_of([&] { merge_sweep(dir); }), "run_0001/summary.json: it was not run with --set f=2"));
  }
}
