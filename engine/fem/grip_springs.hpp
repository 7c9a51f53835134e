#pragma once
// Grasper springs inside a nonlinear solve (tools/springs.hpp makes them):
// grip point p is the weighted sum of its free nodes' displacements,
// u_p = sum_j w_j u_j (plus its rest position), and its spring pulls it with
// f_p = k_p (c_p - u_p), c_p the displacement that puts the point on its
// target; its nodes take w_j f_p. Linear in u: inside a Newton solve the
// springs add -W^T k (c - W u) to the residual's internal side and W^T k W to
// the tangent, which the preconditioner takes exactly, by the Woodbury
// identity, from the linear system's unit responses on the grasped nodes
// (R = P^-1 N^T, compliance C = N R) the spring cache already keeps:
//   (P + N^T W^T k W N)^-1 r = z - R W^T (k^-1 + W C W^T)^-1 W N z,   z = P^-1 r.
// So a stiff grasp costs no extra CG iterations.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <utility>
#include <vector>

namespace softcut::fem {

struct GripSprings {
  struct Point {
    double k = 0;                                   // N/m
    Eigen::Vector3d target = Eigen::Vector3d::Zero();  // c_p: the point's displacement at its target, m
    std::vector<std::pair<int, double>> nodes;      // (mesh node, weight): the point's free nodes
  };
  std::vector<Point> points;
  // The preconditioner's data (tools::SpringCache): the grasped nodes
  // (sorted, m), the linear system's responses to unit loads on them
  // (3 nnode x 3m, m/N), W (3P x 3m) and the factor of k^-1 + W C W^T.
  const std::vector<int>* grasped = nullptr;
  const Eigen::MatrixXd* response = nullptr;
  const Eigen::MatrixXd* W = nullptr;
  const Eigen::LLT<Eigen::MatrixXd>* A_llt = nullptr;

  bool empty() const { return points.empty(); }
};

// The springs on a system whose unknown node k has DOFs 3k .. 3k+2 and whose
// node n is unknown node unknown(n) (-1: not an unknown: a spring on it is
// the caller's error, checked by check_springs).
struct SpringMap {
  std::vector<int> unknown;  // (nnode) unknown node of each mesh node, -1 if none
};

// Throws softcut::Error when a grip point's node is not an unknown of the
// system (`what` says why such a grasp cannot be solved there).
void check_springs(const GripSprings& s, const SpringMap& map, const char* what);
// r += W^T k (c - W u) on the unknowns (x: the unknowns' values); returns the
// springs' energy 1/2 sum k |c - u_p|^2 (J).
double add_spring_forces(const GripSprings& s, const SpringMap& map, const Eigen::VectorXd& x, Eigen::VectorXd& r);
// y += N^T W^T k W N v: the springs' part of the tangent times v.
void apply_spring_stiffness(const GripSprings& s, const SpringMap& map, const Eigen::VectorXd& v, Eigen::VectorXd& y);
// z -= R W^T A^-1 W N z: turns z = P^-1 r into (P + springs)^-1 r.
void spring_correction(const GripSprings& s, const SpringMap& map, Eigen::VectorXd& z);
// Each point's spring force f_p at the unknowns' values x (N).
std::vector<Eigen::Vector3d> spring_point_forces(const GripSprings& s, const SpringMap& map, const Eigen::VectorXd& x);

}  // namespace softcut::fem
