#pragma once
// Per-tet strain and stress of a displacement field (constant in a linear
// tet), for checks and for saying when a model is out of its depth.
#include <Eigen/Core>
#include <vector>

#include "fem/material.hpp"
#include "mesh/tet_mesh.hpp"

namespace softcut::fem {

using StrainField = Eigen::Matrix<double, Eigen::Dynamic, 6>;  // (ntet x 6) Voigt [xx yy zz yz zx xy]

// Constant strain of every tet (engineering shears, dimensionless) for a
// displacement field u (nnode x 3, m).
StrainField element_strains(const mesh::TetMesh& m, const Eigen::MatrixX3d& u);
// Stress sigma = D (eps - eps0) of every tet, Pa, same Voigt order (shear
// stresses); eps0 the material's initial strain.
StrainField element_stresses(const mesh::TetMesh& m, const std::vector<Material>& tet_material,
                             const Eigen::MatrixX3d& u);

}  // namespace softcut::fem
