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

using Json = nlohmann::ordered_json;

// The benchmark's JSON file, strictly parsed (test_support.hpp: invalid
// JSON or a key given twice throws).
Json read_json(const fs::path& p) {
  REQUIRE(fs::exists(p));
  return softcut::test::read_json(p);
}

// A finite number greater than zero (a time, a rate, a count that must move).
bool positive(const Json& v) { return v.is_number() && v.get<double>() > 0 && std::isfinite(v.get<double>()); }

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
  TEST_CASE("the JSON reader of the tests rejects what it must") {
    using softcut::test::parse_json;
    CHECK(parse_json(R"({"a": [1, -2.5e-3, true, null, "x"], "b": {}})").at("a").at(1).get<double>() == -2.5e-3);
    CHECK(parse_json("[true]").at(0).get<bool>());
    CHECK_FALSE(parse_json("[false]").at(0).get<bool>());
    for (const char* bad : {"{\"a\": 1", "[1,]", "{\"a\": nan}", "[inf]", "{\"a\": 1, \"a\": 2}", "[1] x", "[0x10]",
                            "{\"a\": {\"b\": 1, \"b\": 1}}", "[{\"a\": 1}, {\"a\": 2, \"c\": 3, \"a\": 4}]"})
      CHECK_THROWS_AS(parse_json(bad), std::runtime_error);
    // The same key in sibling or nested objects is no duplicate.
    CHECK(parse_json(R"([{"a": 1}, {"a": {"a": 2}}])").at(1).at("a").at("a") == 2);
  }

  TEST_CASE("bench lists every benchmark and rejects an unknown one") {
    const auto help = run_cli("bench --help");
    CHECK(help.status == 0);
    for (const char* name : {"hybrid", "assembly", "gpu", "render", "springs", "cut", "nonlinear"})
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
    CHECK(j.at("benchmark").get<std::string>() == "assembly");
    CHECK(j.at("threads").get<double>() == 2);
    CHECK(j.at("repeat").get<double>() == 1);
    REQUIRE(j.at("rows").size() == 2);
    struct Expect {
      int tets, nodes, face_nodes;
      bool direct;
    };
    const Expect expect[] = {{48, 27, 9, true}, {1080, 6 * 7 * 7, 7 * 7, false}};
    for (size_t k = 0; k < 2; ++k) {
      CAPTURE(k);
      const Json& row = j.at("rows").at(k);
      CHECK(row.at("tets").get<double>() == expect[k].tets);
      CHECK(row.at("nodes").get<double>() == expect[k].nodes);
      CHECK(row.at("free_dofs").get<double>() == 3 * (expect[k].nodes - expect[k].face_nodes));  // x = 0 face clamped
      for (const char* key : {"block_ms", "block_serial_ms", "triplet_ms", "speedup_vs_triplets", "cg_ms"})
        CHECK_MESSAGE(positive(row.at(key)), key);
      CHECK(row.at("block_serial_cpu_ms").get<double>() >= 0);  // clock() ticks: may round to 0
      CHECK(row.at("cg_converged").get<bool>());
      CHECK(row.at("cg_iterations").get<double>() > 0);
      CHECK(row.at("cg_relative_residual").get<double>() <= 1e-8);
      if (expect[k].direct) {
        CHECK(positive(row.at("cholmod_factor_ms")));
        CHECK(row.at("cholmod_solve_ms").get<double>() >= 0);  // printed to 1 us
        CHECK(row.at("cg_vs_cholmod").get<double>() < 1e-5);   // CG to 1e-8 residual against the direct solve
      } else {
        CHECK(row.at("cholmod_factor_ms").is_null());
        CHECK(row.at("cholmod_solve_ms").is_null());
        CHECK(row.at("cg_vs_cholmod").is_null());
      }
    }
  }

  TEST_CASE("bench assembly: bad options") {
    CHECK(run_cli("bench assembly --help").status == 0);
    check_rejected("assembly --tets 0", "--tets 0: expected a whole number from 1 to 100000000");
    check_rejected("assembly --repeat 2x", "--repeat 2x: expected a whole number from 1 to 100000000");
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
    CHECK(j.at("benchmark").get<std::string>() == "hybrid");
    CHECK(j.at("quick").get<bool>());
    REQUIRE(j.at("models").size() == 1);
    const Json& m = j.at("models").at(0);
    CHECK(m.at("model").get<std::string>() == "ligament_factor");
    CHECK(m.at("storage").get<std::string>() == "factor");
    CHECK(m.at("frames").get<double>() == 50);
    // Node sets partition the mesh; regions partition the tets; the
    // operational sphere holds at least the paper's 71 tets.
    CHECK(m.at("set_1").get<double>() + m.at("set_I").get<double>() + m.at("set_s").get<double>() + m.at("set_i").get<double>() +
              m.at("fixed").get<double>() ==
          m.at("nodes").get<double>());
    CHECK(m.at("op_tets").get<double>() + m.at("nonop_tets").get<double>() == m.at("tets").get<double>());
    CHECK(m.at("op_tets").get<double>() >= 71);
    CHECK(m.at("set_1").get<double>() > 0);
    CHECK(m.at("set_I").get<double>() > 0);
    // The hybrid frame against the same frame solved on the whole mesh.
    CHECK(m.at("max_rel_diff_vs_monolithic").get<double>() < 1e-8);
    for (const char* key : {"pre_total_ms", "frame_ms_median", "frame_hz", "mono_cholmod_factor_solve_ms",
                            "mono_cg_ms", "speedup_vs_cholmod_factor_solve", "speedup_vs_cg", "cg_iterations_mean",
                            "mono_cg_iterations"})
      CHECK_MESSAGE(positive(m.at(key)), key);
    const Json& poke = m.at("poke_drag");
    REQUIRE(poke.size() == 5);
    const int loaded[] = {1, 10, 40, 100, 240};
    for (size_t k = 0; k < 5; ++k) {
      CHECK(poke.at(k).at("loaded_nodes").get<double>() == loaded[k]);
      CHECK(poke.at(k).at("loaded_dofs").get<double>() == 3 * loaded[k]);
      CHECK(positive(poke.at(k).at("us")));
    }
  }

  TEST_CASE("bench hybrid --gpu: two models, the gpu backend's frames against the monolithic solve") {
    const fs::path dir = softcut::test::scratch_dir("cli_bench_hybrid_gpu");
    const auto r = run_cli("bench hybrid --quick --gpu --only ligament_dense,ligament --json " +
                           (dir / "h.json").string() + " --md " + (dir / "h.md").string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const std::string md = slurp(dir / "h.md");
    CHECK(contains(md, "## The gpu backend on "));
    CHECK(rows_starting(md, "ligament_dense").size() == 3 + 5 + 1);  // tables 2, 3, frames; 5 poke rows; gpu row
    const Json j = read_json(dir / "h.json");
    CHECK_FALSE(j.at("gpu_device").get<std::string>().empty());
    REQUIRE(j.at("models").size() == 2);  // in the bench's order, whatever --only's
    CHECK(j.at("models").at(0).at("model").get<std::string>() == "ligament");
    CHECK(j.at("models").at(1).at("model").get<std::string>() == "ligament_dense");
    for (const Json& m : j.at("models")) {
      CHECK(m.at("gpu_max_rel_diff_vs_monolithic").get<double>() < 1e-8);
      CHECK(m.at("direct_device_product_rel_diff_vs_default").get<double>() < 1e-12);
      CHECK(positive(m.at("frame_direct_device_product_ms_median")));  // both have a dense K*^-1 P*
      for (const char* key : {"frame_gpu_backend_ms_median", "stage_operational_gpu_ms", "gpu_cg_iterations_mean",
                              "speedup_default_vs_gpu_backend"})
        CHECK_MESSAGE(positive(m.at(key)), key);
    }
  }

  TEST_CASE("bench hybrid: bad options") {
    CHECK(run_cli("bench hybrid --help").status == 0);
    check_rejected("hybrid --storage sparse", "--storage sparse: expected dense, product, factor or automatic");
    check_rejected("hybrid --quick --only femur", "--only femur: no model 'femur' (models: ligament, upper_leg");
    check_rejected("hybrid --quick --only ligament,", "--only ligament,: no model '' (models: ligament, upper_leg");
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
    CHECK_FALSE(j.at("device").get<std::string>().empty());
    CHECK(j.at("fp64").get<bool>());
    REQUIRE(j.at("rows").size() == 2);
    for (size_t k = 0; k < 2; ++k) {
      const Json& row = j.at("rows").at(k);
      const int n = int(k) + 2;
      CHECK(row.at("cells").get<double>() == n);
      // 2n x n x n cells, the x = 0 face clamped: 2n (n+1)^2 free nodes.
      const double dofs = 3.0 * 2 * n * (n + 1) * (n + 1);
      CHECK(row.at("dofs").get<double>() == dofs);
      const double nnz = row.at("nnz").get<double>();
      CHECK(nnz > dofs);
      CHECK(nnz <= dofs * dofs);
      CHECK(std::fmod(nnz, 9.0) == 0);  // whole 3x3 node blocks
      for (const char* key : {"cpu_spmv_us", "cpu_gbs", "gpu_spmv_us", "gpu_gbs", "cpu_iter_us", "gpu_iter_us"})
        CHECK_MESSAGE(positive(row.at(key)), key);
    }
  }

  TEST_CASE("bench gpu: bad options") {
    CHECK(run_cli("bench gpu --help").status == 0);
    check_rejected("gpu --cells 0", "--cells 0: expected a whole number from 1 to 99999");
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
        CHECK(row.at(2) == "17");  // nodes of the triangles under the jaw at the default radius
        CHECK(std::atof(row.at(3).c_str()) > 0);
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
    // --gpu: the gpu backend's frames are in the relative error too.
    const auto r = run_cli("bench cut --quick --gpu --json " + json.string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(contains(r.output, "gpu backend on "));
    const Json j = read_json(json);
    CHECK(j.at("benchmark").get<std::string>() == "cut");
    CHECK_FALSE(j.at("gpu_device").get<std::string>().empty());
    CHECK(j.at("quick").get<bool>());
    REQUIRE(j.at("sizes").size() == 2);
    const int target[] = {300, 800};
    for (size_t k = 0; k < 2; ++k) {
      CAPTURE(k);
      const Json& s = j.at("sizes").at(k);
      CHECK(s.at("target_tets").get<double>() == target[k]);
      CHECK(s.at("cells").get<double>() == 8);
      CHECK(s.at("tets").get<double>() == 6 * 8 * 8 * 8);
      CHECK(s.at("nodes").get<double>() == 9 * 9 * 9);
      CHECK(s.at("operational_tets").get<double>() >= target[k]);
      CHECK(s.at("operational_tets").get<double>() < 2 * target[k]);
      CHECK(s.at("steps").get<double>() == 10);
      CHECK(s.at("steps_changed").get<double>() > s.at("steps_snap_only").get<double>());  // some steps split tets
      CHECK(s.at("steps_changed").get<double>() <= 10);
      CHECK(s.at("tets_after").get<double>() > s.at("tets").get<double>());
      CHECK(s.at("nodes_after").get<double>() > s.at("nodes").get<double>());
      CHECK(s.at("operational_tets_after").get<double>() - s.at("operational_tets").get<double>() ==
            s.at("tets_after").get<double>() - s.at("tets").get<double>());  // only operational tets are cut
      CHECK(s.at("relative_error").get<double>() <= 1e-8);
      CHECK(positive(s.at("warm").at("cg_iterations").at("mean")));
      CHECK(positive(s.at("cold").at("cg_iterations").at("mean")));
      CHECK(positive(s.at("monolithic").at("factor_ms")));
      CHECK(positive(s.at("precompute_ms")));
      CHECK(s.at("cut_ms").at("max").get<double>() >= s.at("cut_ms").at("mean").get<double>());
      CHECK(positive(s.at("default_backend").at("frame_ms").at("mean")));
      CHECK(positive(s.at("refactor_each_cut").at("frame_ms").at("mean")));
      CHECK(s.at("default_backend").at("factors").get<double>() >= 1);
      CHECK(s.at("default_backend").at("corrected_solves_refactored").get<double>() == 0);  // every correction was exact
      CHECK(positive(s.at("gpu_backend").at("frame_ms").at("mean")));
      CHECK(positive(s.at("gpu_backend").at("cg_iterations").at("mean")));
    }
    // The larger region's system is past the dense path: its cuts go through
    // the kept factor's correction (the residual and the error above check it).
    CHECK(positive(j.at("sizes").at(1).at("default_backend").at("correction_rank").at("mean")));
    CHECK(j.at("sizes").at(1).at("operational_tets").get<double>() > j.at("sizes").at(0).at("operational_tets").get<double>());
  }

  TEST_CASE("bench nonlinear: the corotational hybrid frame equals the whole-mesh Newton solve, ratios reported") {
    const fs::path dir = softcut::test::scratch_dir("bench_nonlinear");
    const auto r =
        run_cli("bench nonlinear --cells 5 --op-tets 300 --frames 3 --paper-frames 6 --json " + (dir / "n.json").string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    const Json j = read_json(dir / "n.json");
    CHECK(j["model"] == "box_1500");
    for (const char* series : {"corotational", "linear", "monolithic"}) {
      CAPTURE(series);
      CHECK(j[series]["frame_ms_median"].get<double>() > 0);
      CHECK(j[series]["pcg_iterations_mean"].is_number());
    }
    CHECK(j["corotational"]["newton_iterations_mean"].get<double>() >= 1);
    CHECK(j["monolithic"]["newton_iterations_mean"].get<double>() >= 1);
    CHECK(j["linear"]["newton_iterations_mean"] == 0);
    CHECK(j["relative_difference_vs_monolithic"].get<double>() < 1e-8);
    CHECK(j["rotation_max_deg"].get<double>() > 5);  // the press turns tets well past the linear law's reach
    CHECK(j["speedup_vs_monolithic"].get<double>() > 0);
    CHECK(j["cost_vs_linear"].get<double>() > 0);
    CHECK(contains(r.output, "| corotational |"));
    // The paper's models at the paper's operational sizes (Table 2: 71 and 416 tets).
    REQUIRE(j["paper"].size() == 2);
    CHECK(j["paper"][0]["model"] == "ligament");
    CHECK(j["paper"][0]["operational_tets"] == 71);
    CHECK(j["paper"][1]["model"] == "upper_leg");
    CHECK(j["paper"][1]["operational_tets"] == 416);
    for (const Json& p : j["paper"]) {
      CHECK(p["frame_hz"].get<double>() > 0);
      CHECK(p["newton_iterations_mean"].get<double>() >= 1);
      CHECK(p["rotation_max_deg"].get<double>() > 3);  // the push turns the region's tets
      CHECK(p["cost_vs_linear"].get<double>() > 0);
    }
    CHECK(contains(r.output, "| upper_leg | 2580 | 416 |"));
  }

  TEST_CASE("bench nonlinear: bad options") {
    CHECK(run_cli("bench nonlinear --help").status == 0);
    check_rejected("nonlinear --cells 1", "--cells");
    check_rejected("nonlinear --frames x", "--frames");
    check_rejected("nonlinear --frames 2", "--frames");  // frame 1 makes the factor: none left to time
    check_rejected("nonlinear --paper-frames 0", "--paper-frames");
  }

  TEST_CASE("bench cut: bad options") {
    CHECK(run_cli("bench cut --help").status == 0);
    check_rejected("cut --frobnicate", "unknown option '--frobnicate'");
    check_rejected("cut --json", "--json needs a value");
  }

  TEST_CASE("bench render: a paper model at 64x48 in every frame loop, depth and labels, video, and the redraw") {
    // The default pair (knee ligament and upper leg) takes ~10 s here: the
    // ligament's dense precompute runs once per loop. The upper leg alone
    // shows the same loops; the defaults are checked by the next case.
    const fs::path json = softcut::test::scratch_dir("cli_bench_render") / "render.json";
    const auto r = run_cli("bench render --frames 3 --size 64x48 --msaa 0 scenarios/upper_leg.lua --json " + json.string());
    REQUIRE_MESSAGE(r.status == 0, r.output);
    CHECK(contains(r.output, "64x48, MSAA 0"));
    const auto rows = rows_starting(r.output, "upper_leg");
    REQUIRE(rows.size() >= 3);
    std::vector<std::string> loops;
    for (const auto& row : rows) {
      if (row.size() < 4 || row.at(1).empty()) continue;  // the ratio row
      CHECK(row.at(1) == "3");                            // frames run
      CHECK(std::atof(row.at(3).c_str()) > 0);            // wall ms / frame
      loops.push_back(row.at(2));
    }
    const bool video = contains(r.output, "worker + video");
    std::vector<std::string> want = {"no frames", "inline", "worker", "worker + depth + labels"};
    if (video) want.push_back("worker + video");
    CHECK(loops == want);
    CHECK(contains(r.output, "depth + labels / colour frame"));
    CHECK(contains(r.output, "softcut render wall / run's frame loop wall"));
    CHECK(contains(r.output, "softcut render wall / whole run wall"));
    const auto j = softcut::test::read_json(json);
    const auto& s = j.at("scenarios").at(0);
    CHECK(s.at("loops").size() == want.size());
    CHECK(s.at("loops").at(3).at("depth_labels_ms").get<double>() > 0);
    CHECK(s.at("loops").at(2).at("depth_labels_ms").get<double>() == 0);  // not asked for
    CHECK(s.at("depth_labels_over_rgb").get<double>() > 0);
    CHECK(s.at("redraw_over_run").get<double>() > 0);
    CHECK(s.at("redraw_over_run_total").get<double>() < s.at("redraw_over_run").get<double>());
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
