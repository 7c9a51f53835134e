#include "app/sweep_plan.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <map>
#include <set>

#include "core/error.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace softcut::app;

namespace {

std::string params_of(const SweepRun& r) {
  std::string s;
  for (const auto& [k, v] : r.params) s += k + "=" + v + " ";
  return s;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const softcut::Error& e) {
    return e.what();
  }
  return "";
}

// getenv over a fixed map (the scheduler's variables in a test).
std::function<const char*(const char*)> env(std::map<std::string, std::string> vars) {
  auto held = std::make_shared<std::map<std::string, std::string>>(std::move(vars));
  return [held](const char* n) -> const char* {
    const auto it = held->find(n);
    return it == held->end() ? nullptr : it->second.c_str();
  };
}

}  // namespace

TEST_SUITE("app/sweep_plan") {
  TEST_CASE("a grid expands to its Cartesian product, the last key fastest, with stable zero-padded ids") {
    std::vector<std::string> keys;
    std::vector<SweepRun> runs = expand_grid({"a=1,2", "b=x,y,z"}, keys);
    number_runs(runs);
    CHECK(keys == std::vector<std::string>{"a", "b"});
    REQUIRE(runs.size() == 6);
    CHECK(runs[0].id == "run_0000");
    CHECK(runs[5].id == "run_0005");
    CHECK(params_of(runs[0]) == "a=1 b=x ");
    CHECK(params_of(runs[1]) == "a=1 b=y ");
    CHECK(params_of(runs[3]) == "a=2 b=x ");
    CHECK(params_of(runs[5]) == "a=2 b=z ");
    std::vector<SweepRun> many(12345);
    number_runs(many);
    CHECK(many[7].id == "run_00007");  // wider when there are more than 10000
    CHECK(many.back().id == "run_12344");
  }

  TEST_CASE("bad grids are usage errors naming the argument, and a billion runs are refused before any is listed") {
    std::vector<std::string> keys;
    for (const char* bad : {"novalue", "=1,2", "a b=1", "1a=2", "a=1,,2", "a="}) {
      CAPTURE(bad);
      keys.clear();
      CHECK_THROWS_AS(expand_grid({bad}, keys), softcut::UsageError);
    }
    keys.clear();
    CHECK(error_of([&] { expand_grid({"a=1", "a=2"}, keys); }).find("'a' is swept twice") != std::string::npos);
    const std::string thousand = [] {
      std::string s;
      for (int i = 0; i < 1000; ++i) s += (i ? "," : "") + std::to_string(i);
      return s;
    }();
    keys.clear();
    CHECK(error_of([&] { expand_grid({"a=" + thousand, "b=" + thousand, "c=" + thousand}, keys); })
              .find("more than 100000 runs") != std::string::npos);
  }

  TEST_CASE("a table gives one run per row, with RFC 4180 quotes, and names file:line for bad rows") {
    const fs::path dir = softcut::test::scratch_dir("sweep_table");
    std::ofstream(dir / "t.csv") << "# a comment\nforce,label\n0.1,plain\n\n0.2,\"with, comma and \"\"quote\"\"\"\r\n"
                                    "0.3,\"two\nlines\"\n";
    std::vector<std::string> keys;
    const std::vector<SweepRun> runs = read_table(dir / "t.csv", keys);
    CHECK(keys == std::vector<std::string>{"force", "label"});
    REQUIRE(runs.size() == 3);
    CHECK(runs[1].params[1].second == "with, comma and \"quote\"");
    CHECK(runs[2].params[1].second == "two\nlines");
    auto table_error = [&](const std::string& text) {
      std::ofstream(dir / "bad.csv") << text;
      std::vector<std::string> k;
      return error_of([&] { read_table(dir / "bad.csv", k); });
    };
    CHECK(table_error("a,b\n1,2\n3\n").find("bad.csv:3: 1 values for 2 parameters") != std::string::npos);
    CHECK(table_error("a,b c\n1,2\n").find("bad.csv:1: 'b c' is not a parameter name") != std::string::npos);
    CHECK(table_error("a,a\n1,2\n").find("bad.csv:1: the parameter 'a' is named twice") != std::string::npos);
    CHECK(table_error("a\n\"open\n").find("bad.csv:2: a quoted field is never closed") != std::string::npos);
    CHECK(table_error("a\n\"x\"y\n").find("bad.csv:2: text after a closing quote") != std::string::npos);
    CHECK(table_error("a,b\n1,\n").find("bad.csv:2: the value of 'b' is empty") != std::string::npos);
    CHECK(table_error("a\n").find("has no runs") != std::string::npos);
    CHECK(table_error("").find("empty table") != std::string::npos);
  }

  TEST_CASE("the plan round-trips through sweep_plan.json, byte-identical for equal plans") {
    const fs::path dir = softcut::test::scratch_dir("sweep_plan_json");
    SweepPlan p;
    p.scenario = "/abs/s.lua";
    p.run_options = {"--frames", "3"};
    p.runs = expand_grid({"b=1,2", "a=\"q\""}, p.keys);
    number_runs(p.runs);
    std::ofstream(dir / "sweep_plan.json") << plan_json(p);
    const SweepPlan q = read_plan(dir);
    CHECK(plan_json(q) == plan_json(p));
    CHECK(q.keys == std::vector<std::string>{"b", "a"});  // column order kept
    CHECK(q.runs[1].params[1].second == "\"q\"");
    CHECK(error_of([&] { parse_plan("{\"schema\": \"softcut-sweep-plan/1\", \"runs\": 3}", "bad.json"); })
              .find("bad.json: not a sweep plan") != std::string::npos);
  }

  TEST_CASE("values: UTF-8 text without control characters, at most 4096 bytes - bounds on keys and values") {
    CHECK(bad_value("0.5") == "");
    CHECK(bad_value("a\tb\nc\r") == "");         // a quoted field may hold these
    CHECK(bad_value("\xC3\xA9t\xC3\xA9") == "");  // été
    CHECK(bad_value("") == "is empty");
    CHECK(bad_value("0.0\xff") == "is not UTF-8 text (byte 4 is 0xFF)");
    CHECK(bad_value("\xC0\x80") == "is not UTF-8 text (byte 1 is 0xC0)");  // an overlong NUL
    CHECK(bad_value("a\x1b[31m") == "holds a control character (byte 2)");
    CHECK(bad_value("\x7f") == "holds a control character (byte 1)");
    CHECK(bad_value(std::string(4096, '1')) == "");
    CHECK(bad_value(std::string(4097, '1')).find("is 4097 bytes long, more than 4096") == 0);
    std::vector<std::string> keys;
    CHECK(error_of([&] { expand_grid({"a=1,\xfe"}, keys); }).find("value 2 of 'a' is not UTF-8 text") != std::string::npos);
    std::vector<std::string> grids;
    for (int k = 0; k < 101; ++k) grids.push_back("k" + std::to_string(k) + "=1");
    keys.clear();
    CHECK(error_of([&] { expand_grid(grids, keys); }).find("more than 100 parameters") != std::string::npos);
    const fs::path dir = softcut::test::scratch_dir("sweep_values");
    std::ofstream(dir / "t.csv") << "a\n1\n" << std::string(5000, '2') << "\n";
    keys.clear();
    CHECK(error_of([&] { read_table(dir / "t.csv", keys); }).find("t.csv:3: the value of 'a' is 5000 bytes long") !=
          std::string::npos);
  }

  TEST_CASE("a plan read back is checked field by field: ids in order, a value per key, bounds") {
    SweepPlan p;
    p.scenario = "/abs/s.lua";
    p.runs = expand_grid({"a=1,2,3"}, p.keys);
    number_runs(p.runs);
    const nlohmann::json good = nlohmann::json::parse(plan_json(p));
    auto error_with = [&](const std::function<void(nlohmann::json&)>& edit) {
      nlohmann::json j = good;
      edit(j);
      return error_of([&] { parse_plan(j.dump(), "p.json"); });
    };
    CHECK(error_with([](nlohmann::json&) {}) == "");
    CHECK(error_with([](nlohmann::json& j) { j.erase("keys"); }) == "p.json: not a sweep plan written by softcut sweep: 'keys' is missing");
    CHECK(error_with([](nlohmann::json& j) { j["runs"][2]["id"] = "run_0001"; }) ==
          "p.json: not a sweep plan written by softcut sweep: 'runs[2].id' is 'run_0001', not 'run_0002' (run ids "
          "number the runs in order)");
    CHECK(error_with([](nlohmann::json& j) { j["runs"][1]["params"].erase("a"); }).find("'runs[1].params' does not hold one value per key") != std::string::npos);
    CHECK(error_with([](nlohmann::json& j) { j["runs"][0]["params"]["a"] = 1; }).find("'runs[0].params.a' is not a string") != std::string::npos);
    CHECK(error_with([](nlohmann::json& j) { j["runs"][0]["params"]["a"] = "\x01"; }).find("'runs[0].params.a' holds a control character") != std::string::npos);
    CHECK(error_with([](nlohmann::json& j) { j["keys"] = {"a", "a"}; }).find("the key 'a' is listed twice") != std::string::npos);
    CHECK(error_with([](nlohmann::json& j) { j["keys"] = {"../x"}; }).find("'keys[0]' is not a parameter name") != std::string::npos);
    CHECK(error_with([](nlohmann::json& j) { j["run_options"] = {1}; }).find("'run_options[0]' is not a string") != std::string::npos);
    CHECK(error_with([](nlohmann::json& j) { j = nlohmann::json::array(); }).find("'the document' is not an object") != std::string::npos);
    CHECK(error_of([&] { parse_plan(std::string(100, '['), "p.json"); }).find("p.json: not valid JSON") == 0);
  }

  TEST_CASE("shards: --shard I/N, Slurm's array variables, Kubernetes' index - every run in exactly one shard") {
    const auto none = env({});
    CHECK(choose_shard(std::nullopt, std::nullopt, none).count == 1);
    const Shard a = choose_shard(std::string("2/3"), std::nullopt, none);
    CHECK((a.index == 2 && a.count == 3));
    const Shard slurm = choose_shard(std::nullopt, std::nullopt,
                                     env({{"SLURM_ARRAY_TASK_ID", "5"}, {"SLURM_ARRAY_TASK_MIN", "4"},
                                          {"SLURM_ARRAY_TASK_COUNT", "3"}}));
    CHECK((slurm.index == 1 && slurm.count == 3));
    CHECK(slurm.source.find("SLURM_ARRAY_TASK_ID=5") != std::string::npos);
    // --shard wins over the environment.
    CHECK(choose_shard(std::string("0/2"), std::nullopt, env({{"SLURM_ARRAY_TASK_ID", "1"}})).index == 0);
    const Shard k8s = choose_shard(std::nullopt, 4, env({{"JOB_COMPLETION_INDEX", "3"}}));
    CHECK((k8s.index == 3 && k8s.count == 4));
    for (const auto& c :
         std::vector<std::tuple<std::optional<std::string>, std::optional<int>, std::map<std::string, std::string>>>{
             {std::string("3/3"), std::nullopt, {}},
             {std::string("1"), std::nullopt, {}},
             {std::string("-1/3"), std::nullopt, {}},
             {std::string("0/0"), std::nullopt, {}},
             {std::string("a/b"), std::nullopt, {}},
             {std::string("0/2"), 3, {}},
             {std::nullopt, 2, {}},
             {std::nullopt, std::nullopt, {{"JOB_COMPLETION_INDEX", "0"}}},
             {std::nullopt, std::nullopt, {{"SLURM_ARRAY_TASK_ID", "0"}}},
             {std::nullopt, std::nullopt, {{"SLURM_ARRAY_TASK_ID", "6"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}},  // --array=0-6:2
             {std::nullopt, std::nullopt,  // --array=0-14:2, task 4: in range, but shards 1, 3, 5, 7 would never run
              {{"SLURM_ARRAY_TASK_ID", "4"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_MAX", "14"},
               {"SLURM_ARRAY_TASK_STEP", "2"}, {"SLURM_ARRAY_TASK_COUNT", "8"}}},
             {std::nullopt, std::nullopt,  // --array=1,5,9, task 1
              {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_MAX", "9"},
               {"SLURM_ARRAY_TASK_COUNT", "3"}}},
         }) {
      const std::optional<std::string>& arg = std::get<0>(c);  // (clang 14 captures no structured binding)
      CAPTURE(arg.value_or("-"));
      CHECK_THROWS_AS(choose_shard(arg, std::get<1>(c), env(std::get<2>(c))), softcut::UsageError);
    }
    for (int n = 1; n <= 5; ++n) {
      std::multiset<std::size_t> seen;
      for (int i = 0; i < n; ++i)
        for (std::size_t r : shard_runs(11, Shard{i, n, ""})) seen.insert(r);
      CHECK(seen.size() == 11);
      for (std::size_t r = 0; r < 11; ++r) CHECK(seen.count(r) == 1);
    }
  }
}
