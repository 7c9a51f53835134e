#include "bench/cut_steps.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/timer.hpp"
#include "bench/box_problem.hpp"

namespace softcut::bench {

using namespace cut;

CutStepsResult cut_steps(int cells, int steps, double region_fraction, const CutOptions& opt) {
  if (cells < 1 || steps < 1 || !(region_fraction > 0 && region_fraction <= 1))
    fail("cut_steps: need cells >= 1, steps >= 1 and region_fraction in (0, 1], got ", cells, ", ", steps,
         ", ", region_fraction);
  mesh::TetMesh m = box_problem({{cells, cells, cells}, Eigen::Vector3d::Ones(), 0.15, -1}).mesh;
  std::vector<char> cuttable(size_t(m.num_tets()), 0);
  CutStepsResult r;
  r.cells = cells;
  r.steps = steps;
  for (int t = 0; t < m.num_tets(); ++t) {
    double z = 0;
    for (int k = 0; k < 4; ++k) z += m.nodes(m.tets(t, k), 2) / 4;
    cuttable[size_t(t)] = z > 1 - region_fraction;
    r.region_tets += cuttable[size_t(t)];
  }
  CutState st = make_cut_state(m, cuttable, std::vector<char>(size_t(m.num_nodes()), 0));
  // Blade through the box centre, slanted against the lattice, lowered along z.
  const Eigen::Vector3d b = Eigen::Vector3d(0.31, -1, 0.17).normalized();
  const Eigen::Vector3d c(0.5, 0.5, 0.5);
  const double top = 0.7, bottom = -0.7 + (1 - region_fraction);  // relative to the centre
  int split = 0;
  for (int k = 0; k < steps; ++k) {
    const Eigen::Vector3d p0 = c + Eigen::Vector3d(0, 0, top + (bottom - top) * k / steps);
    const Eigen::Vector3d p1 = c + Eigen::Vector3d(0, 0, top + (bottom - top) * (k + 1) / steps);
    const SweptSurface s = sweep_segment(p0 - 2 * b, p0 + 2 * b, p1 - 2 * b, p1 + 2 * b);
    Timer timer;
    const CutRecord rec = cut_step(m, st, s, opt);
    const double ms = timer.ms();
    r.total_ms += ms;
    r.max_ms = std::max(r.max_ms, ms);
    split += int(rec.split_tets.size());
    r.pieces_separated += rec.faces_separated;
    r.worst_dihedral_deg = std::min(r.worst_dihedral_deg, rec.worst_dihedral_deg);
  }
  r.mean_ms = r.total_ms / steps;
  r.cells_crossed = double(split) / steps;
  for (char c2 : st.cuttable) r.region_tets_after += c2;
  return r;
}

}  // namespace softcut::bench
