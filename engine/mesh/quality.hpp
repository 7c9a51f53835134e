#pragma once
// Element quality of a tet mesh: volumes, dihedral angles and aspect ratio.
//
// Aspect ratio here is the normalized radius ratio R / (3 r), R the
// circumradius and r the inradius: 1 for the regular tet, growing without
// bound as a tet flattens (slivers, needles, caps all have r -> 0). A cube's
// Kuhn tets have (1 + sqrt 2) / sqrt 3 = 1.39.
#include <Eigen/Core>
#include <array>

#include "mesh/tet_mesh.hpp"

namespace softcut::mesh {

// The six interior dihedral angles of (a, b, c, d) in degrees, at the edges
// ab, ac, ad, bc, bd, cd; NaN for a degenerate tet.
std::array<double, 6> dihedral_angles_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, const Eigen::Vector3d& d);

// R / (3 r) >= 1; +inf for a degenerate tet (zero volume).
double aspect_ratio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    const Eigen::Vector3d& d);

struct QualityThresholds {
  double min_dihedral_deg = 10.0;   // a tet with a smaller dihedral angle is poor
  double max_dihedral_deg = 165.0;  // ... or with a larger one
  double max_aspect = 5.0;          // ... or with a larger aspect ratio
};

struct QualityStats {
  int num_tets = 0;
  double min_volume = 0, max_volume = 0, total_volume = 0;  // m^3 (signed)
  double min_dihedral_deg = 0, max_dihedral_deg = 0;
  double min_aspect = 0, max_aspect = 0, mean_aspect = 0;
  double min_edge = 0, max_edge = 0;  // m
  int num_nonpositive = 0;     // tets with volume <= 0
  int num_small_dihedral = 0;  // tets with an angle < thresholds.min_dihedral_deg
  int num_large_dihedral = 0;  // tets with an angle > thresholds.max_dihedral_deg
  int num_high_aspect = 0;     // tets with aspect > thresholds.max_aspect
  int num_poor = 0;            // tets failing any of the above (counted once)
  int worst_tet = -1;          // tet with the largest aspect ratio
};

// Statistics over all tets (zeros for a mesh without tets).
QualityStats tet_quality(const TetMesh& m, const QualityThresholds& th = {});

}  // namespace softcut::mesh
