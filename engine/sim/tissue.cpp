#include "sim/tissue.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/warning.hpp"

namespace softcut::sim {

// Young's moduli from shear moduli mu measured by elastography use E = 3 mu
// (nearly incompressible). Poisson's ratio 0.45: soft tissue is nearly
// incompressible (nu -> 0.5) but linear tets lock as nu -> 0.5, so 0.45 is
// the usual compromise in surgical simulation.
const std::vector<TissuePreset>& tissue_presets() {
  static const std::vector<TissuePreset> presets = {
      {"liver", {5.4e3, 0.45},
       "healthy liver shear modulus 1.8 +- 0.4 kPa (Palmeri et al., Ultrasound Med Biol 34:546, 2008; "
       "tabulated in Phys Med Biol 64:225001, 2019, Table 1), E = 3 mu", 1079},
      {"kidney", {20.7e3, 0.45},
       "in vivo pig renal cortex shear modulus 6.9 +- 1.4 kPa (Gennisson et al., Ultrasound Med Biol "
       "38:1559, 2012), E = 3 mu", 1066},
      {"fat", {3.25e3, 0.45},
       "normal breast fat E = 3.25 +- 0.91 kPa (Samani, Zubovits & Plewes, Phys Med Biol 52:1565, 2007)", 911},
      {"muscle", {12e3, 0.45},
       "relaxed skeletal muscle (biceps) shear modulus about 4 kPa along the fibres by supersonic shear "
       "imaging (Gennisson et al., Ultrasound Med Biol 36:789, 2010), E = 3 mu", 1090},
      {"ligament", {11e6, 0.45},
       "human medial collateral ligament transverse modulus 11.0 MPa (Quapp & Weiss, J Biomech Eng "
       "120:757, 1998; along the fibres 332 MPa): an isotropic stand-in", 1142},
  };
  return presets;
}

namespace {

std::string modulus(double pa) {
  char buf[64];
  if (pa >= 1e6) std::snprintf(buf, sizeof buf, "%.3g MPa", pa / 1e6);
  else if (pa >= 1e3) std::snprintf(buf, sizeof buf, "%.3g kPa", pa / 1e3);
  else std::snprintf(buf, sizeof buf, "%.3g Pa", pa);
  return buf;
}

// The preset whose Young's modulus is nearest to E on a log scale.
const TissuePreset& nearest_preset(double young) {
  const TissuePreset* best = &tissue_presets().front();
  for (const TissuePreset& p : tissue_presets())
    if (std::abs(std::log(p.material.young / young)) < std::abs(std::log(best->material.young / young))) best = &p;
  return *best;
}

}  // namespace

void warn_implausible_material(double young, double density, const std::string& who, Diagnostics& diag) {
  constexpr double kFar = 10;  // how far outside the presets' range is implausible
  double lo = HUGE_VAL, hi = 0;
  const TissuePreset *softest = nullptr, *stiffest = nullptr;
  for (const TissuePreset& p : tissue_presets()) {
    if (p.material.young < lo) lo = p.material.young, softest = &p;
    if (p.material.young > hi) hi = p.material.young, stiffest = &p;
  }
  if (young > 0 && std::isfinite(young) && (young < lo / kFar || young > hi * kFar)) {
    const bool low = young < lo / kFar;
    const TissuePreset& near = nearest_preset(young);
    std::string hint;  // a value in kPa or MPa written as Pa
    for (const auto& [factor, unit] : {std::pair{1e3, "kPa"}, std::pair{1e6, "MPa"}}) {
      const double v = young * factor;
      if (!low || v < lo / kFar || v > hi * kFar) continue;
      const TissuePreset& p = nearest_preset(v);
      char num[32];
      std::snprintf(num, sizeof num, "%.6g", v);
      hint = cat("; ", unit, " given as Pa? young = ", num, " (", modulus(v), ") is near '", p.name, "' (",
                 modulus(p.material.young), ")");
      break;
    }
    warn_coded(diag, "implausible_material", who, ": young = ", modulus(young), " is far ", low ? "below" : "above",
               " every tissue preset (", softest->name, " ", modulus(lo), " .. ", stiffest->name, " ", modulus(hi),
               "); the nearest is '", near.name, "' (", modulus(near.material.young), ")", hint,
               ". Young's modulus is in Pa");
  }
  if (density > 0 && std::isfinite(density) && (density < 100 || density > 1e4)) {
    const double v = density * 1e3;
    const std::string hint = v >= 100 && v <= 1e4 ? cat("; g/cm^3 given as kg/m^3? density = ", v) : std::string();
    warn_coded(diag, "implausible_material", who, ": density = ", density, " kg/m^3 is far outside soft tissue's "
               "(about 900 .. 1150 kg/m^3; the presets' are in softcut.tissues)", hint);
  }
}

const TissuePreset& tissue_preset(const std::string& name, const std::string& where) {
  std::string known;
  for (const auto& p : tissue_presets()) {
    if (p.name == name) return p;
    known += (known.empty() ? "" : ", ") + p.name;
  }
  fail(where, ": unknown tissue preset '", name, "' (known: ", known, ")");
}

}  // namespace softcut::sim
