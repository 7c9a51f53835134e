#pragma once
// Named tissue presets (linear isotropic stand-ins), with sources in
// tissue.cpp and docs/outputs.md. Values vary 2-10x between studies,
// specimens and strain rates: presets are plausible defaults, not truths.
#include <string>
#include <vector>

#include "fem/material.hpp"

namespace softcut::sim {

struct TissuePreset {
  std::string name;       // "liver", "kidney", "fat", "muscle", "ligament"
  fem::Material material;
  std::string source;     // short literature reference
  double density = 1000;  // kg/m^3 (gravity's body force), IT'IS tissue database v4.1 (Hasgall et al. 2022)
};

const std::vector<TissuePreset>& tissue_presets();
// Throws softcut::Error naming `where` and listing the known names.
const TissuePreset& tissue_preset(const std::string& name, const std::string& where);

}  // namespace softcut::sim
