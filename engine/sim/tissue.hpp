#pragma once
// Named tissue presets (linear isotropic stand-ins), with sources in
// tissue.cpp and docs/outputs.md. Values vary 2-10x between studies,
// specimens and strain rates: presets are plausible defaults, not truths.
#include <string>
#include <vector>

#include "core/error.hpp"
#include "fem/material.hpp"

namespace softcut::sim {

struct TissuePreset {
  std::string name;       // "liver", "kidney", "fat", "muscle", "ligament"
  fem::Material material;
  std::string source;     // short literature reference
  double density = 1000;  // kg/m^3 (gravity's body force), IT'IS tissue database v4.1 (Hasgall et al. 2022)
};

const std::vector<TissuePreset>& tissue_presets();

// A material far outside every preset's range (Young's modulus more than 10x
// below the softest preset or above the stiffest; a density outside 100 ..
// 10,000 kg/m^3) is most likely a unit slip (young = 20.7 meaning kPa):
// warns (code implausible_material) naming the nearest preset and, when a
// factor of 1000 or 1e6 brings the value into range, the unit it suggests.
// `who` prefixes the message ("scenario.lua:5: material 'cortex'").
// `density` <= 0: not given (not checked).
void warn_implausible_material(double young, double density, const std::string& who, Diagnostics& diag);
// Throws softcut::Error naming `where` and listing the known names.
const TissuePreset& tissue_preset(const std::string& name, const std::string& where);

}  // namespace softcut::sim
