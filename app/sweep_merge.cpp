#include "app/sweep_merge.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "app/json_input.hpp"
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

std::string text_of(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  return v.dump();  // numbers: the shortest form that reads back the same
}

// The run passed as `softcut run` judges it: no error, interrupt or timeout,
// and every expectation passed (one not reached counts only when the run
// completed).
bool run_passed(const RunSummary& s) {
  if (s.exit_reason == "error" || s.exit_reason == "interrupted" || s.exit_reason == "timeout") return false;
  for (const auto& e : s.expectations)
    if (!e.pass && (e.reached || s.exit_reason == "completed")) return false;
  return true;
}

// Field access with messages naming the field.
struct Reader {
  [[noreturn]] static void bad(const std::string& path, const char* what) {
    fail("'", path, "' ", what);
  }
  static const nlohmann::json* find(const nlohmann::json& obj, const std::string& parent, const char* key,
                                    bool required) {
    if (!obj.is_object()) bad(parent.empty() ? "the document" : parent, "is not an object");
    const auto it = obj.find(key);
    if (it == obj.end()) {
      if (required) bad(field_path(parent, key), "is missing");
      return nullptr;
    }
    return &*it;
  }
  static std::string text(const nlohmann::json& v, const std::string& path) {
    if (!v.is_string()) bad(path, "is not a string");
    return v.get<std::string>();
  }
  static bool boolean(const nlohmann::json& v, const std::string& path) {
    if (!v.is_boolean()) bad(path, "is not true or false");
    return v.get<bool>();
  }
  static nlohmann::json number(const nlohmann::json& v, const std::string& path, bool null_ok) {
    if (!v.is_number() && !(null_ok && v.is_null())) bad(path, null_ok ? "is not a number or null" : "is not a number");
    return v;
  }
};

std::string cut(std::string s, std::size_t n) {
  if (s.size() > n) s = printable(s, n);
  return s;
}

}  // namespace

RunSummary parse_run_summary(const std::string& text, const std::string& file) {
  RunSummary s;
  const nlohmann::json j = parse_bounded_json(text, file, 2000000, 16);
  using R = Reader;
  try {
    const nlohmann::json& words = *R::find(j, "", "command_line", true);
    if (!words.is_array()) R::bad("command_line", "is not a list");
    if (words.size() > 100000) R::bad("command_line", "has more than 100000 words");
    for (std::size_t i = 0; i < words.size(); ++i) s.command_line.push_back(R::text(words[i], field_path("command_line", i)));
    const nlohmann::json& run = *R::find(j, "", "run", true);
    s.exit_reason = R::text(*R::find(run, "run", "exit_reason", true), "run.exit_reason");
    s.frames = R::number(*R::find(run, "run", "frames", true), "run.frames", false);
    if (const auto* t = R::find(run, "run", "last_time_s", false)) s.last_time_s = R::number(*t, "run.last_time_s", true);
    if (const auto* m = R::find(run, "run", "message", false)) s.message = cut(R::text(*m, "run.message"), kMaxMergedMessage);
    if (const auto* c = R::find(j, "", "cutting", false); c && !c->is_null()) {
      if (const auto* e = R::find(*c, "cutting", "events", false)) s.cut_events = R::number(*e, "cutting.events", false);
      if (const auto* p = R::find(*c, "cutting", "detached_pieces", false))
        s.detached_pieces = R::number(*p, "cutting.detached_pieces", false);
    }
    const nlohmann::json& list = *R::find(j, "", "expectations", true);
    if (!list.is_array()) R::bad("expectations", "is not a list");
    if (list.size() > kMaxSummaryExpectations)
      fail("'expectations' lists ", list.size(), " expectations, more than the ", kMaxSummaryExpectations,
           " a scenario may declare");
    s.expectations.reserve(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = field_path("expectations", i);
      RunSummary::Expectation e;
      e.name = R::text(*R::find(list[i], at, "name", true), field_path(at, "name"));
      if (e.name.size() > kMaxExpectationName)
        fail("'", field_path(at, "name"), "' is ", e.name.size(), " bytes long, more than ", kMaxExpectationName);
      e.pass = R::boolean(*R::find(list[i], at, "pass", true), field_path(at, "pass"));
      e.reached = R::boolean(*R::find(list[i], at, "reached", true), field_path(at, "reached"));
      if (const auto* v = R::find(list[i], at, "value", false)) e.value = R::number(*v, field_path(at, "value"), true);
      if (const auto* m = R::find(list[i], at, "message", false))
        e.message = cut(R::text(*m, field_path(at, "message")), kMaxMergedMessage);
      s.expectations.push_back(std::move(e));
    }
    if (const auto* list = R::find(j, "", "tools", false)) {  // older summaries have none
      if (!list->is_array()) R::bad("tools", "is not a list");
      if (list->size() > kMaxSummaryTools)
        fail("'tools' lists ", list->size(), " tools, more than the ", kMaxSummaryTools, " a summary holds");
      for (std::size_t i = 0; i < list->size(); ++i) {
        const std::string at = field_path("tools", i);
        RunSummary::Tool t;
        t.name = R::text(*R::find((*list)[i], at, "name", true), field_path(at, "name"));
        if (t.name.size() > kMaxExpectationName)
          fail("'", field_path(at, "name"), "' is ", t.name.size(), " bytes long, more than ", kMaxExpectationName);
        t.peak_force_n = R::number(*R::find((*list)[i], at, "peak_force_n", true), field_path(at, "peak_force_n"), true);
        t.mean_force_n = R::number(*R::find((*list)[i], at, "mean_force_n", true), field_path(at, "mean_force_n"), true);
        t.frames_engaged =
            R::number(*R::find((*list)[i], at, "frames_engaged", true), field_path(at, "frames_engaged"), false);
        t.entry = {{"name", t.name}, {"peak_force_n", t.peak_force_n}, {"mean_force_n", t.mean_force_n},
                   {"frames_engaged", t.frames_engaged}};
        s.tools.push_back(std::move(t));
      }
    }
    if (const auto* list = R::find(j, "", "metrics", false)) {  // older summaries have none
      if (!list->is_array()) R::bad("metrics", "is not a list");
      if (list->size() > kMaxSummaryMetrics)
        fail("'metrics' lists ", list->size(), " metrics, more than the ", kMaxSummaryMetrics, " a summary holds");
      for (std::size_t i = 0; i < list->size(); ++i) {
        const std::string at = field_path("metrics", i);
        RunSummary::Metric mt;
        mt.name = R::text(*R::find((*list)[i], at, "name", true), field_path(at, "name"));
        if (mt.name.size() > kMaxExpectationName)
          fail("'", field_path(at, "name"), "' is ", mt.name.size(), " bytes long, more than ", kMaxExpectationName);
        mt.entry = {{"name", mt.name}};
        for (const char* f : {"value", "min", "max", "mean", "samples"})
          mt.entry[f] = R::number(*R::find((*list)[i], at, f, true), field_path(at, f), false);
        mt.value = mt.entry["value"];
        s.metrics.push_back(std::move(mt));
      }
    }
  } catch (const Error& e) {
    fail(file, ": not a summary softcut wrote: ", e.what(), " (rerun the run)");
  }
  return s;
}

SweepMerge merge_sweep(const fs::path& dir) {
  const SweepPlan plan = read_plan(dir);
  SweepMerge m;
  m.runs = int(plan.runs.size());
  std::vector<RunSummary> summaries;
  summaries.reserve(plan.runs.size());
  for (const SweepRun& r : plan.runs) {
    const fs::path rel = fs::path(r.id) / "summary.json";
    const std::string file = (dir / rel).string();
    int missing = 0;
    // Below DIR without following a link: a linked run_NNNN is refused.
    const UniqueFd fd = open_below_if_exists(dir, rel, Access::read, "softcut sweep merge", &missing);
    if (!fd) {
      m.missing.push_back(r.id);
      continue;
    }
    struct stat st {};
    if (::fstat(fd.get(), &st) == 0 && std::uint64_t(st.st_size) > kMaxSummaryBytes)
      fail(file, ": holds ", std::uint64_t(st.st_size), " bytes, more than the ", kMaxSummaryBytes,
           " bytes of a summary softcut reads (not a summary softcut wrote)");
    RunSummary s = parse_run_summary(read_whole(fd, "a run's summary", file, kMaxSummaryBytes), file);
    // The run's own command line says which values it was given (params
    // holds them as the scenario read them: "1e3" becomes "1000.0").
    std::unordered_set<std::string> given;
    for (size_t w = 0; w + 1 < s.command_line.size(); ++w)
      if (s.command_line[w] == "--set") given.insert(s.command_line[w + 1]);
    for (const auto& [k, v] : r.params)
      if (!given.count(k + "=" + v))
        fail(file, ": it was not run with --set ", k, "=", printable(v, 40), " as the plan says: the folder holds runs "
             "of another sweep (use a fresh --out)");
    summaries.push_back(std::move(s));
  }
  if (!m.missing.empty()) return m;

  // Expectation columns: every name, in the order runs first report them.
  std::vector<std::string> expect_names;
  std::unordered_map<std::string, std::size_t> column_of;
  for (const RunSummary& s : summaries)
    for (const auto& e : s.expectations)
      if (column_of.emplace(e.name, expect_names.size()).second) {
        expect_names.push_back(e.name);
        if (expect_names.size() > kMaxExpectationColumns)
          fail((dir / "sweep_plan.json").string(), ": the runs' summaries name more than ", kMaxExpectationColumns,
               " different expectations; merge fewer runs");
      }
  if (double(summaries.size()) * double(expect_names.size()) > double(kMaxMergeCells))
    fail((dir / "sweep_plan.json").string(), ": the table would hold ", summaries.size(), " runs x ",
         expect_names.size(), " expectation columns, more than ", kMaxMergeCells, " cells; merge fewer runs");
  // Tool columns: every tool name, in the order runs first report them
  // (summary.json "tools"; older summaries have none).
  std::vector<std::string> tool_names;
  std::unordered_map<std::string, std::size_t> tool_column;
  for (const RunSummary& s : summaries)
    for (const auto& t : s.tools)
      if (tool_column.emplace(t.name, tool_names.size()).second) tool_names.push_back(t.name);
  if (double(summaries.size()) * double(3 * tool_names.size()) > double(kMaxMergeCells))
    fail((dir / "sweep_plan.json").string(), ": the table would hold ", summaries.size(), " runs x ",
         3 * tool_names.size(), " tool columns, more than ", kMaxMergeCells, " cells; merge fewer runs");
  const char* const tool_fields[] = {"peak_force_n", "mean_force_n", "frames_engaged"};
  // Metric columns (Frame:record): every name, in the order runs first report them.
  std::vector<std::string> metric_names;
  std::unordered_map<std::string, std::size_t> metric_column;
  for (const RunSummary& s : summaries)
    for (const auto& mt : s.metrics)
      if (metric_column.emplace(mt.name, metric_names.size()).second) metric_names.push_back(mt.name);
  if (double(summaries.size()) * double(metric_names.size()) > double(kMaxMergeCells))
    fail((dir / "sweep_plan.json").string(), ": the table would hold ", summaries.size(), " runs x ",
         metric_names.size(), " metric columns, more than ", kMaxMergeCells, " cells; merge fewer runs");
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
  for (const auto& n : metric_names) header.push_back("metric." + n);
  auto line = [](const std::vector<std::string>& cells) {
    std::string l;
    for (size_t i = 0; i < cells.size(); ++i) l += (i ? "," : "") + csv_field(cells[i]);
    return l + "\n";
  };
  m.csv = line(header);
  // sweep.json's rows as text, one row at a time: the document is never
  // held whole as JSON values (that took ~3x the text).
  std::string rows_text;
  std::vector<const RunSummary::Expectation*> cell_of(expect_names.size());
  for (size_t i = 0; i < plan.runs.size(); ++i) {
    const SweepRun& r = plan.runs[i];
    const RunSummary& s = summaries[i];
    const bool pass = run_passed(s);
    (pass ? m.passed : m.failed)++;
    std::fill(cell_of.begin(), cell_of.end(), nullptr);
    for (const auto& e : s.expectations) {
      const RunSummary::Expectation*& c = cell_of[column_of.at(e.name)];
      if (!c) c = &e;  // the first of a name
    }
    std::vector<std::string> cells = {r.id};
    json params = json::object(), expectations = json::array();
    for (const auto& [k, v] : r.params) cells.push_back(v), params[k] = v;
    for (const std::string& c : {std::string(pass ? "true" : "false"), s.exit_reason, text_of(s.frames),
                                 text_of(s.last_time_s), text_of(s.cut_events), text_of(s.detached_pieces)})
      cells.push_back(c);
    for (size_t c = 0; c < expect_names.size(); ++c) {
      const RunSummary::Expectation* e = cell_of[c];
      if (!e) {
        cells.emplace_back();
        continue;
      }
      cells.push_back(e->value.is_null() ? (e->pass ? "true" : "false") : text_of(e->value));  // a check: its verdict
      expectations.push_back({{"name", e->name}, {"value", e->value}, {"pass", e->pass}, {"reached", e->reached},
                              {"message", e->message}});
    }
    json tools = json::array();
    std::vector<const RunSummary::Tool*> tool_of(tool_names.size(), nullptr);
    for (const auto& t : s.tools)
      if (!tool_of[tool_column.at(t.name)]) tool_of[tool_column.at(t.name)] = &t;
    for (const RunSummary::Tool* t : tool_of) {
      if (!t) {  // a run without this tool: empty cells
        cells.insert(cells.end(), std::size(tool_fields), "");
        continue;
      }
      for (const nlohmann::json* v : {&t->peak_force_n, &t->mean_force_n, &t->frames_engaged}) cells.push_back(text_of(*v));
      tools.emplace_back(t->entry);
    }
    json metrics = json::array();
    std::vector<const RunSummary::Metric*> metric_of(metric_names.size(), nullptr);
    for (const auto& mt : s.metrics)
      if (!metric_of[metric_column.at(mt.name)]) metric_of[metric_column.at(mt.name)] = &mt;
    for (const RunSummary::Metric* mt : metric_of) {
      cells.push_back(mt ? text_of(mt->value) : "");
      if (mt) metrics.emplace_back(mt->entry);
    }
    m.csv += line(cells);
    const json row = {{"id", r.id}, {"params", params}, {"pass", pass}, {"exit_reason", s.exit_reason},
                      {"message", s.message}, {"frames", s.frames}, {"last_time_s", s.last_time_s},
                      {"cut_events", s.cut_events}, {"detached_pieces", s.detached_pieces},
                      {"expectations", expectations}, {"tools", tools}, {"metrics", metrics},
                      {"summary", r.id + "/summary.json"}};
    // Indented as a member of the document's "rows" list (JSON text holds no
    // raw line break inside a string: every one is structure).
    rows_text += i ? ",\n  " : "  ";
    for (const char c : row.dump(1, ' ', false, json::error_handler_t::replace)) {
      rows_text += c;
      if (c == '\n') rows_text += "  ";
    }
  }
  const json out = {{"schema", "softcut-sweep/1"}, {"scenario", plan.scenario}, {"run_options", plan.run_options},
                    {"keys", plan.keys}, {"runs", m.runs}, {"passed", m.passed}, {"failed", m.failed},
                    {"rows", json::array()}};
  m.json = out.dump(1, ' ', false, json::error_handler_t::replace);  // ends with "rows": []\n}
  if (!rows_text.empty()) m.json.replace(m.json.size() - 4, 4, "[\n" + rows_text + "\n ]\n}");
  m.json += "\n";
  return m;
}

}  // namespace softcut::app
