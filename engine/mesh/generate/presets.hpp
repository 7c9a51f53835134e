#pragma once
// The two models of Wu & Heng 2005 (§5, Table 2), rebuilt from generators at
// the paper's sizes (the originals came from the Visible Human data set):
//   ligament   615 nodes, 1900 tets (human knee ligament) -> a twisted band
//   upper_leg  785 nodes, 2550 tets (small portion of the upper leg, the hole
//              is the thighbone whose surface nodes are fixed) -> a thick tube
// The presets set target_nodes / target_tets; the generators pick the
// resolution, within 10% of both counts (checked by tests).
#include "mesh/generate/band.hpp"
#include "mesh/generate/tube.hpp"

namespace softcut::mesh {

inline constexpr int kLigamentNodes = 615, kLigamentTets = 1900;
inline constexpr int kUpperLegNodes = 785, kUpperLegTets = 2550;

BandOptions ligament_preset();
TubeOptions upper_leg_preset();

}  // namespace softcut::mesh
