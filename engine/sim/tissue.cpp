#include "sim/tissue.hpp"

#include "core/error.hpp"

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

const TissuePreset& tissue_preset(const std::string& name, const std::string& where) {
  std::string known;
  for (const auto& p : tissue_presets()) {
    if (p.name == name) return p;
    known += (known.empty() ? "" : ", ") + p.name;
  }
  fail(where, ": unknown tissue preset '", name, "' (known: ", known, ")");
}

}  // namespace softcut::sim
