#include "app/sweep_plan.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <set>

#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"
#include "app/json_input.hpp"

namespace fs = std::filesystem;

namespace softcut::app {

namespace {

// A parameter name as softcut.params declares them: a Lua identifier.
bool is_key(const std::string& k) {
  if (k.empty() || k.size() > 100 || std::isdigit(static_cast<unsigned char>(k[0]))) return false;
  for (const char c : k)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out(1);
  for (const char c : s) {
    if (c == sep) out.emplace_back();
    else out.back().push_back(c);
  }
  return out;
}

// One CSV record starting at `pos` (RFC 4180: quoted fields, "" inside quotes,
// CRLF or LF line ends; a quoted field may span lines). `line` counts lines.
std::vector<std::string> csv_record(const std::string& text, size_t& pos, int& line, const std::string& file) {
  std::vector<std::string> fields(1);
  const int first_line = line;
  bool quoted = false, was_quoted = false;
  for (; pos < text.size(); ++pos) {
    const char c = text[pos];
    if (quoted) {
      if (c == '"' && pos + 1 < text.size() && text[pos + 1] == '"') fields.back() += '"', ++pos;
      else if (c == '"') quoted = false;
      else {
        if (c == '\n') ++line;
        fields.back() += c;
      }
    } else if (c == '"' && fields.back().empty() && !was_quoted) {
      quoted = was_quoted = true;
    } else if (c == ',') {
      fields.emplace_back(), was_quoted = false;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && pos + 1 < text.size() && text[pos + 1] == '\n') ++pos;
      ++pos, ++line;
      return fields;
    } else if (was_quoted) {
      fail(file, ":", line, ": text after a closing quote (write \"\" for a quote inside a quoted field)");
    } else {
      fields.back() += c;
    }
  }
  if (quoted) fail(file, ":", first_line, ": a quoted field is never closed");
  ++line;
  return fields;
}

constexpr std::size_t kMaxPlanValues = kMaxSweepValues + 4 * kMaxSweepRuns + 10000;

void check_runs(std::size_t n, const std::string& what) {
  if (n > kMaxSweepRuns)
    usage_fail(what, " expands to more than ", kMaxSweepRuns, " runs; split the study into several sweeps");
}

void check_values(std::size_t runs, std::size_t keys, const std::string& what) {
  if (keys > kMaxSweepKeys) usage_fail(what, " sweeps more than ", kMaxSweepKeys, " parameters");
  if (double(runs) * double(keys) > double(kMaxSweepValues))
    usage_fail(what, " gives ", runs, " runs of ", keys, " parameters, more than ", kMaxSweepValues,
               " values in all; split the study into several sweeps");
}

}  // namespace

std::string bad_value(const std::string& value) {
  if (value.empty()) return "is empty";
  if (value.size() > kMaxValueBytes)
    return cat("is ", value.size(), " bytes long, more than ", kMaxValueBytes, " (put long data in a file the "
               "scenario reads)");
  for (std::size_t i = 0; i < value.size();) {
    const auto c = static_cast<unsigned char>(value[i]);
    const std::size_t n = utf8_sequence_length(std::string_view(value).substr(i));
    if (n == 0) return cat("is not UTF-8 text (byte ", i + 1, " is 0x", "0123456789ABCDEF"[c >> 4], "0123456789ABCDEF"[c & 15], ")");
    if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7F)
      return cat("holds a control character (byte ", i + 1, ")");
    i += n;
  }
  return "";
}

std::vector<SweepRun> expand_grid(const std::vector<std::string>& grids, std::vector<std::string>& keys) {
  std::vector<std::vector<std::string>> values;
  std::size_t total = 1;
  for (const std::string& g : grids) {
    const size_t eq = g.find('=');
    const std::string key = g.substr(0, eq);
    if (eq == std::string::npos || !is_key(key))
      usage_fail("softcut sweep: --grid '", printable(g, 80), "' must be key=v1,v2,... with key a parameter name");
    for (const auto& k : keys)
      if (k == key) usage_fail("softcut sweep: the parameter '", key, "' is swept twice (--grid/--set)");
    std::vector<std::string> vs = split(g.substr(eq + 1), ',');
    for (size_t i = 0; i < vs.size(); ++i)
      if (const std::string why = bad_value(vs[i]); !why.empty())
        usage_fail("softcut sweep: --grid '", printable(g, 80), "': value ", i + 1, " of '", key, "' ", why);
    keys.push_back(key);
    total *= vs.size();
    check_runs(total, "the grid");
    check_values(total, keys.size(), "the grid");
    values.push_back(std::move(vs));
  }
  std::vector<SweepRun> runs(grids.empty() ? 0 : total);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    std::size_t rest = i;
    runs[i].params.resize(values.size());
    for (std::size_t k = values.size(); k-- > 0;) {  // the last key varies fastest
      runs[i].params[k] = {keys[k], values[k][rest % values[k].size()]};
      rest /= values[k].size();
    }
  }
  return runs;
}

std::vector<SweepRun> read_table(const fs::path& csv, std::vector<std::string>& keys) {
  const std::string file = csv.string();
  const std::string text = read_regular_file(csv, "the sweep table", std::size_t(64) << 20);
  if (text.find('\0') != std::string::npos)
    fail(file, ":", 1 + std::count(text.begin(), text.begin() + std::ptrdiff_t(text.find('\0')), '\n'),
         ": a NUL byte (not a text table; a program's argument cannot hold one)");
  size_t pos = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;  // a UTF-8 byte order mark (spreadsheet exports)
  int line = 1;
  std::vector<SweepRun> runs;
  bool header = true;
  while (pos < text.size()) {
    const int at = line;
    if (text[pos] == '#' || text[pos] == '\n' || text[pos] == '\r') {  // comment or blank line
      const size_t nl = text.find('\n', pos);
      pos = nl == std::string::npos ? text.size() : nl + 1;
      ++line;
      continue;
    }
    std::vector<std::string> fields = csv_record(text, pos, line, file);
    if (header) {
      for (const auto& k : fields) {
        if (!is_key(k)) fail(file, ":", at, ": '", printable(k, 80), "' is not a parameter name (the first line "
                             "names the parameters: key1,key2,...)");
        for (const auto& seen : keys)
          if (seen == k) fail(file, ":", at, ": the parameter '", k, "' is named twice");
        keys.push_back(k);
        if (keys.size() > kMaxSweepKeys) fail(file, ":", at, ": more than ", kMaxSweepKeys, " parameters");
      }
      header = false;
      continue;
    }
    if (fields.size() != keys.size())
      fail(file, ":", at, ": ", fields.size(), " values for ", keys.size(), " parameters (", keys.size() == 1 ? "" : "quote values holding commas; ", "every row gives one value per column)");
    SweepRun r;
    for (size_t k = 0; k < keys.size(); ++k) {
      if (const std::string why = bad_value(fields[k]); !why.empty())
        fail(file, ":", at, ": the value of '", keys[k], "' ", why);
      r.params.emplace_back(keys[k], fields[k]);
    }
    runs.push_back(std::move(r));
    if (runs.size() > kMaxSweepRuns) fail(file, ":", at, ": more than ", kMaxSweepRuns, " runs; split the table");
    if (runs.size() * keys.size() > kMaxSweepValues)
      fail(file, ":", at, ": more than ", kMaxSweepValues, " values in all (runs x parameters); split the table");
  }
  if (header) fail(file, ": empty table (the first line names the parameters, each further line is one run)");
  if (runs.empty()) fail(file, ": the table has no runs (one line per run after the header)");
  return runs;
}

void number_runs(std::vector<SweepRun>& runs) {
  const int width = std::max<int>(4, int(std::to_string(runs.empty() ? 0 : runs.size() - 1).size()));
  for (size_t i = 0; i < runs.size(); ++i) {
    std::string n = std::to_string(i);
    runs[i].id = "run_" + std::string(size_t(width) - std::min(n.size(), size_t(width)), '0') + n;
  }
}

std::string plan_json(const SweepPlan& plan) {
  nlohmann::json j;
  j["schema"] = "softcut-sweep-plan/1";
  j["scenario"] = plan.scenario;
  j["run_options"] = plan.run_options;
  j["keys"] = plan.keys;
  j["runs"] = nlohmann::json::array();
  for (const SweepRun& r : plan.runs) {
    nlohmann::json p = nlohmann::json::object();
    for (const auto& [k, v] : r.params) p[k] = v;
    j["runs"].push_back({{"id", r.id}, {"params", p}});
  }
  return j.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

SweepPlan parse_plan(const std::string& text, const std::string& file) {
  // Values: the runs' ids and parameters, plus a few per run and the options.
  const nlohmann::json j = parse_bounded_json(text, file, kMaxPlanValues, 8);
  SweepPlan plan;
  auto string_at = [&](const nlohmann::json& v, const std::string& where) {
    if (!v.is_string()) fail("'", where, "' is not a string");
    return v.get<std::string>();
  };
  auto field = [&](const nlohmann::json& obj, const std::string& parent, const char* key) -> const nlohmann::json& {
    const std::string where = field_path(parent, key);
    if (!obj.is_object()) fail("'", parent.empty() ? "the document" : parent, "' is not an object");
    const auto it = obj.find(key);
    if (it == obj.end()) fail("'", where, "' is missing");
    return *it;
  };
  try {
    if (string_at(field(j, "", "schema"), "schema") != "softcut-sweep-plan/1")
      fail("unknown schema ", printable(j.at("schema").get<std::string>(), 40));
    plan.scenario = string_at(field(j, "", "scenario"), "scenario");
    const nlohmann::json& options = field(j, "", "run_options");
    if (!options.is_array()) fail("'run_options' is not a list");
    for (size_t i = 0; i < options.size(); ++i) plan.run_options.push_back(string_at(options[i], field_path("run_options", i)));
    const nlohmann::json& keys = field(j, "", "keys");
    if (!keys.is_array()) fail("'keys' is not a list");
    if (keys.size() > kMaxSweepKeys) fail("more than ", kMaxSweepKeys, " keys");
    for (size_t i = 0; i < keys.size(); ++i) {
      const std::string k = string_at(keys[i], field_path("keys", i));
      if (!is_key(k)) fail("'", field_path("keys", i), "' is not a parameter name");
      if (std::find(plan.keys.begin(), plan.keys.end(), k) != plan.keys.end()) fail("the key '", k, "' is listed twice");
      plan.keys.push_back(k);
    }
    const nlohmann::json& runs = field(j, "", "runs");
    if (!runs.is_array()) fail("'runs' is not a list");
    if (runs.size() > kMaxSweepRuns) fail("more than ", kMaxSweepRuns, " runs");
    if (runs.size() * std::max<std::size_t>(1, plan.keys.size()) > kMaxSweepValues)
      fail("more than ", kMaxSweepValues, " values (runs x keys)");
    plan.runs.resize(runs.size());
    number_runs(plan.runs);  // the ids a plan must hold, in order: unique by construction
    for (size_t i = 0; i < runs.size(); ++i) {
      const std::string where = field_path("runs", i);
      const std::string id = string_at(field(runs[i], where, "id"), field_path(where, "id"));
      if (id != plan.runs[i].id)
        fail("'", field_path(where, "id"), "' is '", printable(id, 40), "', not '", plan.runs[i].id,
             "' (run ids number the runs in order)");
      const nlohmann::json& params = field(runs[i], where, "params");
      if (!params.is_object() || params.size() != plan.keys.size())
        fail("'", field_path(where, "params"), "' does not hold one value per key");
      for (const auto& k : plan.keys) {
        const std::string v = string_at(field(params, field_path(where, "params"), k.c_str()),
                                        field_path(field_path(where, "params"), k));
        if (const std::string why = bad_value(v); !why.empty())
          fail("'", field_path(field_path(where, "params"), k), "' ", why);
        plan.runs[i].params.emplace_back(k, v);
      }
    }
  } catch (const Error& e) {
    fail(file, ": not a sweep plan written by softcut sweep: ", e.what());
  }
  return plan;
}

SweepPlan read_plan(const fs::path& dir) {
  return parse_plan(read_file_below(dir, "sweep_plan.json", "the sweep plan", kMaxPlanBytes), (dir / "sweep_plan.json").string());
}

Shard choose_shard(const std::optional<std::string>& shard_arg, std::optional<int> shards,
                   const std::function<const char*(const char*)>& getenv) {
  auto number = [](const std::string& text, const std::string& what) {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end || errno || v < 0 || v > 1000000)
      usage_fail("softcut sweep: ", what, " = '", printable(text, 40), "' is not a whole number from 0 to 1000000");
    return int(v);
  };
  Shard s;
  if (shard_arg) {
    const size_t slash = shard_arg->find('/');
    if (slash == std::string::npos) usage_fail("softcut sweep: --shard takes I/N (e.g. 0/3: the first of 3 slices)");
    s.index = number(shard_arg->substr(0, slash), "--shard's I");
    s.count = number(shard_arg->substr(slash + 1), "--shard's N");
    if (shards && *shards != s.count) usage_fail("softcut sweep: --shard ", *shard_arg, " and --shards ", *shards, " disagree");
    s.source = "--shard " + *shard_arg;
  } else if (const char* id = getenv("SLURM_ARRAY_TASK_ID")) {
    const char* count = getenv("SLURM_ARRAY_TASK_COUNT");
    const char* min = getenv("SLURM_ARRAY_TASK_MIN");
    if (!count) usage_fail("softcut sweep: SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not");
    const int task = number(id, "SLURM_ARRAY_TASK_ID"), lo = min ? number(min, "SLURM_ARRAY_TASK_MIN") : 0;
    s.count = number(count, "SLURM_ARRAY_TASK_COUNT");
    s.index = task - lo;
    if (shards && *shards != s.count)
      usage_fail("softcut sweep: --shards ", *shards, " but the Slurm array has ", s.count, " tasks");
    // Task ids must be min, min + 1, ..., max: a step or a list (--array=0-14:2,
    // --array=1,5,9) would leave shards no task runs.
    const char* max = getenv("SLURM_ARRAY_TASK_MAX");
    const char* step = getenv("SLURM_ARRAY_TASK_STEP");
    if ((step && number(step, "SLURM_ARRAY_TASK_STEP") != 1) ||
        (max && number(max, "SLURM_ARRAY_TASK_MAX") - lo + 1 != number(count, "SLURM_ARRAY_TASK_COUNT")))
      usage_fail("softcut sweep: the Slurm array's task ids are not consecutive (SLURM_ARRAY_TASK_MIN=", lo,
                 ", MAX=", max ? max : "?", ", STEP=", step ? step : "?", ", COUNT=", count,
                 "): some shards would never run; submit with --array=0-N (no step, no list)");
    s.source = cat("SLURM_ARRAY_TASK_ID=", task, " (min ", lo, ", count ", s.count, ")");
  } else if (const char* k8s = getenv("JOB_COMPLETION_INDEX")) {
    if (!shards)
      usage_fail("softcut sweep: JOB_COMPLETION_INDEX is set: give the Job's completions as --shards N");
    s.index = number(k8s, "JOB_COMPLETION_INDEX");
    s.count = *shards;
    s.source = cat("JOB_COMPLETION_INDEX=", s.index, " of --shards ", s.count);
  } else if (shards) {
    usage_fail("softcut sweep: --shards ", *shards, " needs the index: --shard I/", *shards,
               ", or SLURM_ARRAY_TASK_ID / JOB_COMPLETION_INDEX in the environment");
  }
  if (s.count < 1) usage_fail("softcut sweep: ", s.source, ": the number of shards must be at least 1");
  if (s.index < 0 || s.index >= s.count)
    usage_fail("softcut sweep: ", s.source, ": the shard index must be from 0 to ", s.count - 1,
               " (Slurm: submit with --array=0-", s.count - 1, ", no step)");
  return s;
}

std::vector<std::size_t> shard_runs(std::size_t num_runs, const Shard& shard) {
  std::vector<std::size_t> out;
  for (std::size_t i = std::size_t(shard.index); i < num_runs; i += std::size_t(shard.count)) out.push_back(i);
  return out;
}

}  // namespace softcut::app
