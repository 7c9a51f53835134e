#include "mesh/generate/presets.hpp"

namespace softcut::mesh {

BandOptions ligament_preset() {
  BandOptions o;  // anterior-cruciate-like: 35 mm long, 10 mm x 4 mm mid-section, 90 degree twist
  o.length = 0.035;
  o.width = 0.010;
  o.thickness = 0.004;
  o.flare = 1.6;
  o.twist_deg = 90;
  o.target_nodes = kLigamentNodes;
  o.target_tets = kLigamentTets;
  return o;
}

TubeOptions upper_leg_preset() {
  TubeOptions o;  // femoral shaft of 12 mm radius inside a 12 mm layer of soft tissue, 30 mm long
  o.inner_radius = 0.012;
  o.outer_radius = 0.024;
  o.length = 0.03;
  o.target_nodes = kUpperLegNodes;
  o.target_tets = kUpperLegTets;
  return o;
}

}  // namespace softcut::mesh
