// bench/*.cpp through the real executable (SOFTCUT_BIN): every
// benchmark at the smallest sizes its options allow, checking the rows it
// writes (JSON parsed, counts against closed forms, the hybrid/cut results
// against the monolithic solve of the same run) and that bad options fail
// with a message naming them. No timing is asserted.
#include <doctest/doctest.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include "cli_test_support.hpp"

namespace fs = std::filesystem;
using softcut::test::contains;
using softcut::test::run_cli;
using softcut::test::slurp;

namespace {

// Just enough JSON for the benchmark files: objects, arrays, numbers,
// strings without escapes, true/false/null. Throws on anything malformed.
struct Json {
  enum class Type { null, boolean, number, string, array, object } type = Type::null;
  bool b = false;
  double num = 0;
  std::string str;
  std::vector<Json> arr;
  std::map<std::string, Json> obj;

  const Json& operator[](const std::string& key) const {
    if (type != Type::object) throw std::runtime_error("not an object looking up " + key);
    const auto it = obj.find(key);
    if (it == obj.end()) throw std::runtime_error("missing key " + key);
    return it->second;
  }
  const Json& operator[](size_t i) const {
    if (type != Type::array || i >= arr.size()) throw std::runtime_error("bad array index");
    return arr[i];
  }
  double number() const {
    if (type != Type::number) throw std::runtime_error("not a number");
    return num;
  }
  bool is_null() const { return type == Type::null; }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& text) : s_(text) {}
  Json parse() {
    Json v = value();
    skip();
    if (i_ != s_.size()) error("trailing text");
    return v;
  }

 private:
  [[noreturn]] void error(const std::string& what) const {
    throw std::runtime_error("JSON: " + what + " at offset " + std::to_string(i_));
  }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) return ++i_, true;
    return false;
  }
  void expect(char c) {
    if (!eat(c)) error(std::string("expected '") + c + "'");
  }
  bool word(const char* w) {
    const std::string ws(w);
    if (s_.compare(i_, ws.size(), ws) != 0) return false;
    i_ += ws.size();
    return true;
  }
  std::string string() {
    expect('"');
    const size_t end = s_.find('"', i_);
    if (end == std::string::npos) error("unterminated string");
    std::string out = s_.substr(i_, end - i_);
    if (out.find('\\') != std::string::npos) error("escapes are not expected here");
    i_ = end + 1;
    return out;
  }
  Json value() {
    skip();
    if (i_ >= s_.size()) error("unexpected end");
    Json v;
    const char c = s_[i_];
    if (c == '{') {
      v.type = Json::Type::object;
      ++i_;
      if (eat('}')) return v;
      do {
        const std::string k = string();
        expect(':');
        if (!v.obj.emplace(k, value()).second) error("duplicate key " + k);
      } while (eat(','));
      expect('}');
    } else if (c == '[') {
      v.type = Json::Type::array;
      ++i_;
      if (eat(']')) return v;
      do v.arr.push_back(value());
      while (eat(','));
      expect(']');
    } else if (c == '"') {
      v.type = Json::Type::string;
      v.str = string();
    } else if (word("true")) {
      v.type = Json::Type::boolean;
      v.b = true;
    } else if (word("false")) {
      v.type = Json::Type::boolean;
    } else if (word("null")) {
    } else {
      const char* begin = s_.c_str() + i_;
      char* end = nullptr;
      v.num = std::strtod(begin, &end);
      // strtod also takes "nan", "inf" and hex, which JSON does not.
      if (end == begin || !std::isfinite(v.num) ||
          s_.substr(i_, size_t(end - begin)).find_first_not_of("0123456789+-.eE") != std::string::npos)
        error("bad number");
      v.type = Json::Type::number;
      i_ += size_t(end - begin);
    }
    return v;
  }

  const std::string& s_;
  size_t i_ = 0;
};

Json read_json(const fs::path& p) {
  REQUIRE(fs::exists(p));
  return JsonParser(slurp(p)).parse();
}

// A finite number greater than zero (a time, a rate, a count that must move).
bool positive(const Json& v) { return v.type == Json::Type::number && v.num > 0 && std::isfinite(v.num); }

// Markdown table rows whose first cell is `first`, split into trimmed cells.
std::vector<std::vector<std::string>> rows_starting(const std::string& text, const std::string& first) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| " + first + " |", 0) != 0) continue;
    std::vector<std::string> cells;
    size_t at = 1;
    for (size_t bar; (bar = line.find('|', at)) != std::string::npos; at = bar + 1) {
      std::string c = line.substr(at, bar - at);
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
      cells.push_back(c);
    }
    rows.push_back(cells);
  }
  return rows;
}

// `softcut bench ARGS` must fail with exit status 1 and a message holding `part`.
// A bad option is a usage error (status 2, as softcut --help documents); a
// missing input file an error (status 1).
void check_rejected(const std::string& args, const std::string& part, int status = 2) {
  CAPTURE(args);
  const auto r = run_cli("bench " + args);
  CHECK(r.status == status);
  CHECK_MESSAGE(contains(r.output, part), r.output);
}

}  // namespace

TEST_SUITE("bench/bench") {
  TEST_CASE("the JSON reader of this suite rejects what it must") {
    CHECK(JsonParser(R"({"a": [1, -2.5e-3, true, null, "x"], "b": {}})").parse()["a"][1].number() == -2.5e-3);
    CHECK(JsonParser("[true]").parse()[0].b);
    CHECK_FALSE(JsonParser("[false]").parse()[0].b);
    for (const char* bad : {"{\"a\": 1", "[1,]", "{\"a\": nan}", "[inf]", "{\"a\": 1, \"a\": 2}", "[1] x", "[0x10]"})
      CHECK_THROWS_AS(JsonParser(bad).parse(), std::runtime_error);
  }

  TEST_CASE("bench lists every benchmark and rejects an unknown one") {
    const auto help = run_cli("bench --help");
    CHECK(help.status == 0);
    for (const char* name : {"hybrid", "assembly", "gpu", "render", "springs", "cut"})
      CHECK_MESSAGE(contains(help.output, std::string("  ") + name + " "), name);
    CHECK(run_cli("bench").status == 2);  // usage, nothing run
    check_rejected("nosuch", "unknown benchmark 'nosuch'");
  }

  TEST_CASE("bench assembly: two box sizes with and without CHOLMOD") {
    const fs::path json = softcut::test::scratch_dir("cli_bench_assembly") / "assembly.json";
    // 48 tets: 2x2x2 cells; 1000 -> 5x6x6 cells = 1080 tets, past --direct-max-tets.
    const auto r = run_cli("bench assembly --tets 48 --tets 1000 --repeat 1 --threads 2 --direct-max-tets 500 --json " +
                           json.string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(contains(r.output, "wrote " + json.string()));
    CHECK(rows_starting(r.output, "48").size() == 1);
    CHECK(rows_starting(r.output, "1080").size() == 1);
    const Json j = read_json(json);
    CHECK(j["benchmark"].str == "assembly");
    CHECK(j["threads"].number() == 2);
    CHECK(j["repeat"].number() == 1);
    REQUIRE(j["rows"].arr.size() == 2);
    struct Expect {
      int tets, nodes, face_nodes;
      bool direct;
    };
    const Expect expect[] = {{48, 27, 9, true}, {1080, 6 * 7 * 7, 7 * 7, false}};
    for (size_t k = 0; k < 2; ++k) {
      CAPTURE(k);
      const Json& row = j["rows"][k];
      CHECK(row["tets"].number() == expect[k].tets);
      CHECK(row["nodes"].number() == expect[k].nodes);
      CHECK(row["free_dofs"].number() == 3 * (expect[k].nodes - expect[k].face_nodes));  // x = 0 face clamped
      for (const char* key : {"block_ms", "block_serial_ms", "triplet_ms", "speedup_vs_triplets", "cg_ms"})
        CHECK_MESSAGE(positive(row[key]), key);
      CHECK(row["block_serial_cpu_ms"].number() >= 0);  // clock() ticks: may round to 0
      CHECK(row["cg_converged"].b);
      CHECK(row["cg_iterations"].number() > 0);
      CHECK(row["cg_relative_residual"].number() <= 1e-8);
      if (expect[k].direct) {
        CHECK(positive(row["cholmod_factor_ms"]));
        CHECK(row["cholmod_solve_ms"].number() >= 0);  // printed to 1 us
        CHECK(row["cg_vs_cholmod"].number() < 1e-5);   // CG to 1e-8 residual against the direct solve
      } else {
        CHECK(row["cholmod_factor_ms"].is_null());
        CHECK(row["cholmod_solve_ms"].is_null());
        CHECK(row["cg_vs_cholmod"].is_null());
      }
    }
  }

  TEST_CASE("bench assembly: bad options") {
    CHECK(run_cli("bench assembly --help").status == 0);
    check_rejected("assembly --tets 0", "--tets needs a positive integer, got '0'");
    check_rejected("assembly --repeat 2x", "--repeat needs a positive integer, got '2x'");
    check_rejected("assembly --tets", "--tets needs a value");
    check_rejected("assembly --json", "--json needs a file name");
    check_rejected("assembly --frobnicate", "unknown option '--frobnicate'");
  }

  TEST_CASE("bench hybrid: the ligament in factor storage agrees with the monolithic solve") {
    const fs::path dir = softcut::test::scratch_dir("cli_bench_hybrid");
    const auto r = run_cli("bench hybrid --quick --only ligament_factor --json " + (dir / "h.json").string() +
                           " --md " + (dir / "h.md").string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const std::string md = slurp(dir / "h.md");
    CHECK(md.rfind("# Hybrid condensed model: benchmark", 0) == 0);
    CHECK(contains(r.output, md));  // the same report on stdout
    CHECK(rows_starting(md, "ligament_factor").size() == 3 + 5);  // tables 2, 3, frames; 5 poke rows
    const Json j = read_json(dir / "h.json");
    CHECK(j["benchmark"].str == "hybrid");
    CHECK(j["quick"].b);
    REQUIRE(j["models"].arr.size() == 1);
    const Json& m = j["models"][0];
    CHECK(m["model"].str == "ligament_factor");
    CHECK(m["storage"].str == "factor");
    CHECK(m["frames"].number() == 50);
    // Node sets partition the mesh; regions partition the tets; the
    // operational sphere holds at least the paper's 71 tets.
    CHECK(m["set_1"].number() + m["set_I"].number() + m["set_s"].number() + m["set_i"].number() +
              m["fixed"].number() ==
          m["nodes"].number());
    CHECK(m["op_tets"].number() + m["nonop_tets"].number() == m["tets"].number());
    CHECK(m["op_tets"].number() >= 71);
    CHECK(m["set_1"].number() > 0);
    CHECK(m["set_I"].number() > 0);
    // The hybrid frame against the same frame solved on the whole mesh.
    CHECK(m["max_rel_diff_vs_monolithic"].number() < 1e-8);
    for (const char* key : {"pre_total_ms", "frame_ms_median", "frame_hz", "mono_cholmod_factor_solve_ms",
                            "mono_cg_ms", "speedup_vs_cholmod_factor_solve", "speedup_vs_cg", "cg_iterations_mean",
                            "mono_cg_iterations"})
      CHECK_MESSAGE(positive(m[key]), key);
    const Json& poke = m["poke_drag"];
    REQUIRE(poke.arr.size() == 5);
    const int loaded[] = {1, 10, 40, 100, 240};
    for (size_t k = 0; k < 5; ++k) {
      CHECK(poke[k]["loaded_nodes"].number() == loaded[k]);
      CHECK(poke[k]["loaded_dofs"].number() == 3 * loaded[k]);
      CHECK(positive(poke[k]["us"]));
    }
  }

  TEST_CASE("bench hybrid: bad options") {
    CHECK(run_cli("bench hybrid --help").status == 0);
    check_rejected("hybrid --storage sparse", "--storage takes dense, product, factor or automatic, got 'sparse'");
    check_rejected("hybrid --quick --only femur", "--only femur: no such model (models: ligament, upper_leg");
    check_rejected("hybrid --frobnicate", "unknown option '--frobnicate'");
  }

  TEST_CASE("bench gpu: two small systems in double precision") {
    const fs::path json = softcut::test::scratch_dir("cli_bench_gpu") / "gpu.json";
    const auto r =
        run_cli("bench gpu --cells 2 --cells 3 --iterations 5 --fp64 --peak-gbs 100 --json " + json.string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(contains(r.output, "device: "));
    CHECK(contains(r.output, "GB/s (of peak)"));
    const Json j = read_json(json);
    CHECK_FALSE(j["device"].str.empty());
    CHECK(j["fp64"].b);
    REQUIRE(j["rows"].arr.size() == 2);
    for (size_t k = 0; k < 2; ++k) {
      const Json& row = j["rows"][k];
      const int n = int(k) + 2;
      CHECK(row["cells"].number() == n);
      // 2n x n x n cells, the x = 0 face clamped: 2n (n+1)^2 free nodes.
      const double dofs = 3.0 * 2 * n * (n + 1) * (n + 1);
      CHECK(row["dofs"].number() == dofs);
      const double nnz = row["nnz"].number();
      CHECK(nnz > dofs);
      CHECK(nnz <= dofs * dofs);
      CHECK(std::fmod(nnz, 9.0) == 0);  // whole 3x3 node blocks
      for (const char* key : {"cpu_spmv_us", "cpu_gbs", "gpu_spmv_us", "gpu_gbs", "cpu_iter_us", "gpu_iter_us"})
        CHECK_MESSAGE(positive(row[key]), key);
    }
  }

  TEST_CASE("bench gpu: bad options") {
    CHECK(run_cli("bench gpu --help").status == 0);
    check_rejected("gpu --cells 0", "--cells needs a positive integer, got '0'");
    check_rejected("gpu --iterations", "--iterations needs a value");
    check_rejected("gpu --peak-gbs fast", "--peak-gbs fast: expected a positive bandwidth in GB/s");
    check_rejected("gpu --frobnicate", "unknown option '--frobnicate'");
  }

  TEST_CASE("bench springs: the compliance cache builds once and without it every frame") {
    const auto r = run_cli("bench springs --frames 2");
    REQUIRE_MESSAGE(r.status == 0, r.output);
    for (const char* backend : {"cpu", "direct"}) {
      CAPTURE(backend);
      CHECK(contains(r.output, std::string("(") + backend + ": 784 nodes"));  // 16 x 7 x 7 box nodes
      const auto rows = rows_starting(r.output, backend);
      REQUIRE(rows.size() == 3);
      std::map<std::string, std::vector<std::string>> by;
      for (const auto& row : rows) {
        REQUIRE(row.size() >= 8);
        CHECK(row[2] == "17");  // nodes of the triangles under the jaw at the default radius
        CHECK(std::atof(row[3].c_str()) > 0);
        by[row[1]] = row;
      }
      REQUIRE(by.size() == 3);
      CHECK(by["explicit"][5] == "0");
      CHECK(by["explicit"][7] == "1.00");
      CHECK(by["implicit, cached"][5] == "1");
      CHECK(by["implicit, no cache"][5] == "2");  // one per frame
    }
  }

  TEST_CASE("bench springs: bad options") {
    CHECK(run_cli("bench springs --help").status == 0);
    check_rejected("springs --frames many", "--frames many: expected a whole number");
    check_rejected("springs --radius -1", "--radius -1: expected a grasper radius in m");
    check_rejected("springs --radius 5mm", "--radius 5mm: expected a grasper radius in m");
    check_rejected("springs --frobnicate", "unknown option '--frobnicate'");
  }

  TEST_CASE("bench cut: the quick series stays equal to the monolithic solve of the cut mesh") {
    const fs::path json = softcut::test::scratch_dir("cli_bench_cut") / "cut.json";
    const auto r = run_cli("bench cut --quick --json " + json.string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const Json j = read_json(json);
    CHECK(j["benchmark"].str == "cut");
    CHECK(j["quick"].b);
    REQUIRE(j["sizes"].arr.size() == 2);
    const int target[] = {300, 800};
    for (size_t k = 0; k < 2; ++k) {
      CAPTURE(k);
      const Json& s = j["sizes"][k];
      CHECK(s["target_tets"].number() == target[k]);
      CHECK(s["cells"].number() == 8);
      CHECK(s["tets"].number() == 6 * 8 * 8 * 8);
      CHECK(s["nodes"].number() == 9 * 9 * 9);
      CHECK(s["operational_tets"].number() >= target[k]);
      CHECK(s["operational_tets"].number() < 2 * target[k]);
      CHECK(s["steps"].number() == 10);
      CHECK(s["steps_changed"].number() > s["steps_snap_only"].number());  // some steps split tets
      CHECK(s["steps_changed"].number() <= 10);
      CHECK(s["tets_after"].number() > s["tets"].number());
      CHECK(s["nodes_after"].number() > s["nodes"].number());
      CHECK(s["operational_tets_after"].number() - s["operational_tets"].number() ==
            s["tets_after"].number() - s["tets"].number());  // only operational tets are cut
      CHECK(s["relative_error"].number() <= 1e-8);
      CHECK(positive(s["warm"]["cg_iterations"]["mean"]));
      CHECK(positive(s["cold"]["cg_iterations"]["mean"]));
      CHECK(positive(s["monolithic"]["factor_ms"]));
      CHECK(positive(s["precompute_ms"]));
      CHECK(s["cut_ms"]["max"].number() >= s["cut_ms"]["mean"].number());
      CHECK(positive(s["default_backend"]["frame_ms"]["mean"]));
      CHECK(positive(s["refactor_each_cut"]["frame_ms"]["mean"]));
      CHECK(s["default_backend"]["factors"].number() >= 1);
      CHECK(s["default_backend"]["corrected_solves_refactored"].number() == 0);  // every correction was exact
    }
    // The larger region's system is past the dense path: its cuts go through
    // the kept factor's correction (the residual and the error above check it).
    CHECK(positive(j["sizes"][1]["default_backend"]["correction_rank"]["mean"]));
    CHECK(j["sizes"][1]["operational_tets"].number() > j["sizes"][0]["operational_tets"].number());
  }

  TEST_CASE("bench cut: bad options") {
    CHECK(run_cli("bench cut --help").status == 0);
    check_rejected("cut --frobnicate", "unknown option '--frobnicate'");
    check_rejected("cut --json", "unknown option '--json'");  // its value is missing
  }

  TEST_CASE("bench render: a paper model at 64x48 in the three frame loops") {
    // The default pair (knee ligament and upper leg) takes ~10 s here: the
    // ligament's dense precompute runs once per loop. The upper leg alone
    // shows the same loops; the defaults are checked by the next case.
    const auto r = run_cli("bench render --frames 3 --size 64x48 --msaa 0 scenarios/upper_leg.lua");
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(contains(r.output, "64x48, MSAA 0"));
    const auto rows = rows_starting(r.output, "upper_leg");
    REQUIRE(rows.size() >= 3);
    std::vector<std::string> loops;
    for (const auto& row : rows) {
      if (row.size() < 4 || row[1].empty()) continue;  // the ratio row
      CHECK(row[1] == "3");                            // frames run
      CHECK(std::atof(row[3].c_str()) > 0);            // wall ms / frame
      loops.push_back(row[2]);
    }
    CHECK(loops == std::vector<std::string>{"no frames", "inline", "worker"});
  }

  TEST_CASE("bench render: bad options and missing scenarios") {
    CHECK(run_cli("bench render --help").status == 0);
    check_rejected("render --size 64", "--size");
    check_rejected("render --msaa four", "--msaa four");
    check_rejected("render --frames", "--frames needs a value");
    check_rejected("render --frobnicate", "unknown option '--frobnicate'");
    check_rejected("render no_such.lua", "no_such.lua not found", 1);
    // The defaults are looked up in the working directory.
    const auto r = run_cli("bench render --frames 1", softcut::test::scratch_dir("cli_bench_render_cwd"));
    CHECK(r.status == 1);
    CHECK(contains(r.output, "scenarios/knee_ligament.lua not found (run from the repository root"));
  }
}
