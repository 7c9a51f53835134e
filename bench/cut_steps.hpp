#pragma once
// Time per cut step against the size of the operational region, on a box
// (cut::cut_step alone: no solve, no rebuild; `softcut bench cut` measures
// whole cut frames).
#include <vector>

#include "cut/cutter.hpp"

namespace softcut::bench {

struct CutStepsResult {
  int cells = 0;              // box cells per axis
  int region_tets = 0;        // operational (cuttable) tets before cutting
  int region_tets_after = 0;  // ... after the whole cut
  int steps = 0;              // blade steps
  double mean_ms = 0, max_ms = 0, total_ms = 0;  // per cut_step
  double cells_crossed = 0;   // mean tets split per step
  double worst_dihedral_deg = 180;
  int pieces_separated = 0;   // faces separated over the whole cut
};

// A unit box of cells^3 cubes (6 tets each, jittered), the upper
// `region_fraction` of its height operational, the rest locked behind the
// interface; a slanted blade lowered through the whole operational part in
// `steps` equal steps. Deterministic.
CutStepsResult cut_steps(int cells, int steps, double region_fraction = 1.0, const cut::CutOptions& opt = {});

}  // namespace softcut::bench
