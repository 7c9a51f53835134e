#include "sim/validity.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/warning.hpp"
#include "fem/hyperelastic.hpp"
#include "sim/cutting.hpp"
#include "sim/model.hpp"

namespace softcut::sim {

namespace {

// The value 1 % of `v` exceed (the largest for fewer than 100); 0 for none.
double p99(std::vector<double>& v) {
  if (v.empty()) return 0;
  const auto k = v.begin() + std::ptrdiff_t(0.99 * double(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), k, v.end());
  return *k;
}

}  // namespace

Validity measure_validity(const Model& m, const State& s) {
  const mesh::TetMesh& mesh = current_mesh(m, s);
  const std::vector<fem::Material>& mat = s.cut ? s.cut->tet_material : m.tet_material;
  const std::vector<char>& op = s.cut ? s.cut->operational_tet : m.partition.operational_tet;
  const bool whole_body = m.spec.solver.whole_body;
  const bool interior = m.solver->interior_valid();
  Validity v;
  std::vector<double> rotations, strains, condensed_rotations;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const bool operational = op[size_t(t)] != 0;
    const bool linear_law = mat[size_t(t)].model == fem::MaterialModel::linear || (!operational && !whole_body);
    if (!linear_law) continue;  // its own law carries its rotation
    // The mixed model's linear region: condensed by the hybrid backends,
    // solved whole (still linear) by the monolithic one; measured the same
    // way so every backend warns alike. Only whole_body gives it its law.
    const bool condensed = !operational && !whole_body;
    bool solved = true;  // a condensed tet with an interior node the frame did not solve is not measured
    for (int k = 0; k < 4 && condensed && !interior && solved; ++k) {
      const int n = mesh.tets(t, k);
      solved = !(n < m.mesh.num_nodes() && m.partition.node_set[size_t(n)] == hybrid::NodeSet::interior);
    }
    if (!solved) continue;
    Eigen::Matrix3d Dm, Du;
    for (int k = 0; k < 3; ++k) {
      Dm.col(k) = (mesh.node(mesh.tets(t, k + 1)) - mesh.node(mesh.tets(t, 0)));
      Du.col(k) = (s.displacement.row(mesh.tets(t, k + 1)) - s.displacement.row(mesh.tets(t, 0))).transpose();
    }
    const Eigen::Matrix3d G = Du * Dm.inverse();  // grad u
    const Eigen::Matrix3d W = 0.5 * (G - G.transpose());
    // The polar rotation of F = I + grad u; below 0.05 rad |skew grad u|,
    // the same to second order, spares the polar decomposition.
    const double w = Eigen::Vector3d(W(2, 1), W(0, 2), W(1, 0)).norm();
    const double rotation =
        w < 0.05 ? std::asin(w) : fem::deformation(Eigen::Matrix3d::Identity() + G).rotation;
    if (condensed) {
      if (rotation > v.condensed_rotation) v.condensed_rotation = rotation, v.condensed_tet = t;
      condensed_rotations.push_back(rotation);
      continue;
    }
    const double strain =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(0.5 * (G + G.transpose()), Eigen::EigenvaluesOnly)
            .eigenvalues()
            .cwiseAbs()
            .maxCoeff();
    if (rotation > v.linear_rotation) v.linear_rotation = rotation, v.linear_tet = t;
    v.linear_strain = std::max(v.linear_strain, strain);
    rotations.push_back(rotation), strains.push_back(strain);
  }
  v.linear_rotation_p99 = p99(rotations), v.linear_strain_p99 = p99(strains);
  v.condensed_rotation_p99 = p99(condensed_rotations);
  return v;
}

namespace {

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

// The scenario file as its other messages spell it (the file part of a
// call's "file:line"), else its name; with ": ".
static std::string script_name(const Model& m) {
  for (const auto& mat : m.spec.materials)
    if (const auto colon = mat.where.rfind(':'); colon != std::string::npos && colon > 0)
      return mat.where.substr(0, colon) + ": ";
  return m.spec.source.empty() ? "" : m.spec.source.filename().string() + ": ";
}

const char* const kValidityLogHeader =
    "frame,time,cg_iterations,newton_iterations,linear_rotation_deg,linear_rotation_p99_deg,linear_strain,"
    "linear_strain_p99,condensed_rotation_deg,condensed_rotation_p99_deg\n";

std::string validity_log_row(const State& s) {
  constexpr double kDeg = 180.0 / M_PI;
  const Validity& v = s.last_validity;
  char buf[320];
  const int n = std::snprintf(buf, sizeof buf, "%d,%.9e,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", s.frame, s.time,
                              s.last_cg_iterations, s.last_newton_iterations, v.linear_rotation * kDeg,
                              v.linear_rotation_p99 * kDeg, v.linear_strain, v.linear_strain_p99,
                              v.condensed_rotation * kDeg, v.condensed_rotation_p99 * kDeg);
  return std::string(buf, std::size_t(n));
}

std::vector<std::string> validity_warnings(const Model& m, const State& s) {
  constexpr double kDeg = 180.0 / M_PI;
  const RunStatistics& r = s.stats;
  const std::string where = script_name(m);
  const auto at = [&](int frame) { return cat("at t = ", fixed(m.frame_time(frame), 3), " s"); };
  std::vector<std::string> out;
  if (r.linear_rotation_p99_max * kDeg > kLinearRotationBoundDeg)
    out.push_back(coded_warning(
        "linear_large_rotation",
        cat(where, "1 % of the tets with the linear law rotated by more than ",
            fixed(r.linear_rotation_p99_max * kDeg, 1), " deg ", at(r.linear_rotation_p99_frame), " (the most ",
            fixed(r.linear_rotation_max * kDeg, 1), " deg), past the ", fixed(kLinearRotationBoundDeg, 0),
            " deg the law is good for (a rotation of theta stretches a linear tet by about theta^2 / 2): give the "
            "moving tissue s:material{ model = \"corotational\" } (docs/fidelity.md)")));
  if (r.linear_strain_p99_max > kLinearStrainBound)
    out.push_back(coded_warning(
        "linear_large_strain",
        cat(where, "1 % of the tets with the linear law were strained by more than ",
            fixed(r.linear_strain_p99_max * 100, 1), " % ", at(r.linear_strain_p99_frame), " (the most ",
            fixed(r.linear_strain_max * 100, 1), " %), past the ", fixed(kLinearStrainBound * 100, 0),
            " % the law is good for: give them a nonlinear model, s:material{ model = \"corotational\" } or "
            "\"neohookean\" (docs/fidelity.md)")));
  if (r.condensed_rotation_p99_max * kDeg > kCondensedRotationBoundDeg)
    out.push_back(coded_warning(
        "condensed_rotation",
        cat(where, "1 % of the nonoperational region's tets (condensed, linear whatever their material) rotated "
            "by more than ", fixed(r.condensed_rotation_p99_max * kDeg, 1), " deg ", at(r.condensed_rotation_p99_frame),
            " (the most ", fixed(r.condensed_rotation_max * kDeg, 1), " deg), past ",
            fixed(kCondensedRotationBoundDeg, 0), " deg: widen the operational region so the large motion stays "
            "inside it, or solve the whole body (s:solver{ whole_body = true }) (docs/fidelity.md)")));
  return out;
}

}  // namespace softcut::sim
