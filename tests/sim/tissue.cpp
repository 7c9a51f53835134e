#include "sim/tissue.hpp"

#include <doctest/doctest.h>

#include "core/warning.hpp"

using namespace softcut;

TEST_SUITE("sim/tissue") {
  TEST_CASE("every preset is plausible, values 10x outside their range warn naming the nearest and the unit") {
    for (const sim::TissuePreset& p : sim::tissue_presets()) {
      Diagnostics d;
      sim::warn_implausible_material(p.material.young, p.density, p.name, d);
      CHECK(d.warnings.empty());
    }
    Diagnostics d;
    sim::warn_implausible_material(20.7, 0, "kidney.lua:5: material 'cortex'", d);
    REQUIRE(d.warnings.size() == 1);
    CHECK(d.warnings[0] ==
          "kidney.lua:5: material 'cortex': young = 20.7 Pa is far below every tissue preset (fat 3.25 kPa .. ligament "
          "11 MPa); the nearest is 'fat' (3.25 kPa); kPa given as Pa? young = 20700 (20.7 kPa) is near 'kidney' "
          "(20.7 kPa). Young's modulus is in Pa [implausible_material]");
    CHECK(warning_code(d.warnings[0]) == "implausible_material");
    // MPa written as Pa; far above; a density in g/cm^3; the edges of the range.
    Diagnostics m;
    sim::warn_implausible_material(0.0054, 0, "m", m);
    REQUIRE(m.warnings.size() == 1);
    CHECK(m.warnings[0].find("MPa given as Pa? young = 5400 (5.4 kPa) is near 'liver'") != std::string::npos);
    Diagnostics hi;
    sim::warn_implausible_material(2e11, 1.06, "steel", hi);
    REQUIRE(hi.warnings.size() == 2);
    CHECK(hi.warnings[0].find("young = 2e+05 MPa is far above every tissue preset") != std::string::npos);
    CHECK(hi.warnings[1].find("density = 1.06 kg/m^3 is far outside soft tissue's") != std::string::npos);
    CHECK(hi.warnings[1].find("g/cm^3 given as kg/m^3? density = 1060 [implausible_material]") != std::string::npos);
    Diagnostics edge;
    sim::warn_implausible_material(3.25e3 / 10, 100, "e", edge);
    sim::warn_implausible_material(11e6 * 10, 1e4, "e", edge);
    CHECK(edge.warnings.empty());
  }
}
