#include "app/sweep_merge.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "app/sweep_plan.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace softcut::app {

namespace {

// RFC 4180: quoted when it holds a comma, quote or line break.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string text_of(const json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  return v.dump();  // numbers: the shortest form that reads back the same
}

// The run passed as `softcut run` judges it: no error, interrupt or timeout,
// and every expectation passed (one not reached counts only when the run
// completed).
bool run_passed(const json& summary) {
  const std::string reason = summary.at("run").at("exit_reason").get<std::string>();
  if (reason == "error" || reason == "interrupted" || reason == "timeout") return false;
  for (const json& e : summary.at("expectations"))
    if (!e.at("pass").get<bool>() && (e.at("reached").get<bool>() || reason == "completed")) return false;
  return true;
}

}  // namespace

SweepMerge merge_sweep(const fs::path& dir) {
  const SweepPlan plan = read_plan(dir / "sweep_plan.json");
  SweepMerge m;
  m.runs = int(plan.runs.size());
  std::vector<json> summaries;
  for (const SweepRun& r : plan.runs) {
    const fs::path file = dir / r.id / "summary.json";
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(file, ec))) {
      m.missing.push_back(r.id);
      continue;
    }
    json s;
    try {
      s = json::parse(read_regular_file(file, "a run's summary", std::size_t(256) << 20));
      // The run's own command line says which values it was given (params
      // holds them as the scenario read them: "1e3" becomes "1000.0").
      const auto words = s.at("command_line").get<std::vector<std::string>>();
      for (const auto& [k, v] : r.params) {
        bool given = false;
        for (size_t w = 0; w + 1 < words.size(); ++w) given = given || (words[w] == "--set" && words[w + 1] == k + "=" + v);
        if (!given)
          fail("it was not run with --set ", k, "=", printable(v, 40), " as the plan says: the folder holds runs of "
               "another sweep (use a fresh --out)");
      }
      run_passed(s);  // the fields it reads are there
      (void)s.at("run").at("frames");
    } catch (const json::exception& e) {
      fail(file.string(), ": not a softcut summary (", e.what(), ")");
    } catch (const Error& e) {
      fail(file.string(), ": ", e.what());
    }
    summaries.push_back(std::move(s));
  }
  if (!m.missing.empty()) return m;

  // Expectation columns: every name, in the order runs first report them.
  std::vector<std::string> expect_names;
  for (const json& s : summaries)
    for (const json& e : s.at("expectations")) {
      const std::string n = e.at("name").get<std::string>();
      if (std::find(expect_names.begin(), expect_names.end(), n) == expect_names.end()) expect_names.push_back(n);
    }
  // Tool columns: every tool name, in the order runs first report them
  // (summary.json "tools"; older summaries have none).
  std::vector<std::string> tool_names;
  for (const json& s : summaries)
    for (const json& t : s.value("tools", json::array())) {
      const std::string n = t.at("name").get<std::string>();
      if (std::find(tool_names.begin(), tool_names.end(), n) == tool_names.end()) tool_names.push_back(n);
    }
  const char* const tool_fields[] = {"peak_force_n", "mean_force_n", "frames_engaged"};
  // A key named like a fixed column ("frames") gets the column "param.frames".
  const std::vector<std::string> fixed = {"id", "pass", "exit_reason", "frames", "last_time_s", "cut_events",
                                          "detached_pieces"};
  std::vector<std::string> header = {"id"};
  for (const auto& k : plan.keys)
    header.push_back(std::find(fixed.begin(), fixed.end(), k) == fixed.end() ? k : "param." + k);
  header.insert(header.end(), fixed.begin() + 1, fixed.end());
  for (const auto& n : expect_names) header.push_back("expect." + n);
  for (const auto& n : tool_names)
    for (const char* f : tool_fields) header.push_back("tool." + n + "." + f);
  auto line = [](const std::vector<std::string>& cells) {
    std::string l;
    for (size_t i = 0; i < cells.size(); ++i) l += (i ? "," : "") + csv_field(cells[i]);
    return l + "\n";
  };
  m.csv = line(header);
  json rows = json::array();
  for (size_t i = 0; i < plan.runs.size(); ++i) {
    const SweepRun& r = plan.runs[i];
    const json& s = summaries[i];
    const bool pass = run_passed(s);
    (pass ? m.passed : m.failed)++;
    const json& run = s.at("run");
    const json cutting = s.contains("cutting") ? s.at("cutting") : json::object();
    const json events = cutting.value("events", json(0)), pieces = cutting.value("detached_pieces", json(0));
    std::vector<std::string> cells = {r.id};
    json params = json::object(), expectations = json::array();
    for (const auto& [k, v] : r.params) cells.push_back(v), params[k] = v;
    for (const std::string& c : {std::string(pass ? "true" : "false"), text_of(run.at("exit_reason")),
                                 text_of(run.at("frames")), text_of(run.value("last_time_s", json())),
                                 text_of(events), text_of(pieces)})
      cells.push_back(c);
    for (const auto& n : expect_names) {
      std::string cell;
      for (const json& e : s.at("expectations"))
        if (e.at("name") == n) {
          const json value = e.value("value", json());
          cell = value.is_null() ? (e.at("pass").get<bool>() ? "true" : "false") : text_of(value);  // a check: its verdict
          expectations.push_back({{"name", n}, {"value", e.value("value", json())}, {"pass", e.at("pass")},
                                  {"reached", e.at("reached")}, {"message", e.value("message", json(""))}});
          break;
        }
      cells.push_back(cell);
    }
    json tools = json::array();
    const json run_tools = s.value("tools", json::array());
    for (const auto& n : tool_names) {
      const json* found = nullptr;
      for (const json& t : run_tools)
        if (t.at("name") == n) found = &t;
      for (const char* f : tool_fields) cells.push_back(found ? text_of(found->value(f, json())) : "");
      if (found) tools.push_back(*found);
    }
    m.csv += line(cells);
    rows.push_back({{"id", r.id}, {"params", params}, {"pass", pass}, {"exit_reason", run.at("exit_reason")},
                    {"message", run.value("message", json(""))}, {"frames", run.at("frames")},
                    {"last_time_s", run.value("last_time_s", json())}, {"cut_events", events},
                    {"detached_pieces", pieces}, {"expectations", expectations}, {"tools", tools},
                    {"summary", r.id + "/summary.json"}});
  }
  const json out = {{"schema", "softcut-sweep/1"}, {"scenario", plan.scenario}, {"run_options", plan.run_options},
                    {"keys", plan.keys}, {"runs", m.runs}, {"passed", m.passed}, {"failed", m.failed},
                    {"rows", rows}};
  m.json = out.dump(1, ' ', false, json::error_handler_t::replace) + "\n";
  return m;
}

}  // namespace softcut::app
