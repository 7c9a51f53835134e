// app/reference_log.cpp: comparing displacement logs.
#include "app/reference_log.hpp"

#include <doctest/doctest.h>

#include <fstream>

#include "test_support.hpp"

namespace fs = std::filesystem;

TEST_SUITE("app/reference_log") {
  TEST_CASE("compare_logs: tolerance relative to the motion's scale") {
    const fs::path dir = softcut::test::scratch_dir("check_compare");
    std::ofstream(dir / "a.csv") << "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n1,0.1,1,0,0,-2e-3\n";
    std::ofstream(dir / "b.csv") << "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n1,0.1,1,0,1e-9,-2e-3\n";
    const auto ok = softcut::app::compare_logs(dir / "a.csv", dir / "b.csv", 1e-6);
    CHECK(ok.ok);
    CHECK(ok.scale == 2e-3);
    CHECK(ok.max_diff == 1e-9);
    CHECK_FALSE(softcut::app::compare_logs(dir / "a.csv", dir / "b.csv", 1e-7).ok);
    std::ofstream(dir / "c.csv") << "frame,time,node,ux,uy,uz\n0,0,1,0,0,-1e-3\n1,0.1,2,0,0,-2e-3\n";
    CHECK(softcut::app::compare_logs(dir / "a.csv", dir / "c.csv", 1).stale);
    std::ofstream(dir / "d.csv") << "frame,time,node,ux,uy,uz\n0,0,1,0,0\n";
    CHECK_THROWS_WITH(softcut::app::compare_logs(dir / "a.csv", dir / "d.csv", 1), doctest::Contains("d.csv:2:"));
  }

  TEST_CASE("reference_path sits next to the scenario") {
    CHECK(softcut::app::reference_path("scenarios/knee.lua") == fs::path("scenarios/knee.ref.csv"));
  }
}
