#include "hybrid/operational_system.hpp"

#include <atomic>

#include "core/error.hpp"
#include "fem/assembly.hpp"

namespace softcut::hybrid {

namespace {
std::atomic<long> next_generation{1};
}

void OperationalSystem::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int nb = size() / 3;
  if (int(block.row_start.size()) == nb + 1) {
    y.resize(size());
    for (int i = 0; i < nb; ++i) {
      Eigen::Vector3d acc = Eigen::Vector3d::Zero();
      for (int k = block.row_start[size_t(i)]; k < block.row_start[size_t(i) + 1]; ++k)
        acc.noalias() += block.blocks[size_t(k)] * x.segment<3>(3 * Eigen::Index(block.col[size_t(k)]));
      y.segment<3>(3 * Eigen::Index(i)) = acc;
    }
  } else {
    y.noalias() = K * x;
  }
  if (num_interface > 0) {
    const Eigen::Index off = interface_offset(), n = 3 * Eigen::Index(num_interface);
    // K' is symmetric: reading one triangle halves the memory traffic of the
    // dense product, which dominates a CG iteration for large interfaces.
    y.segment(off, n).noalias() += K_prime->selfadjointView<Eigen::Lower>() * x.segment(off, n);
  }
}

SparseMatrix OperationalSystem::assembled() const {
  // Written column by column (K's columns are sorted): K' is dense, and
  // setFromTriplets over its entries took a third of a refactor at 8k
  // operational tets (~200 of ~600 ms). Each entry is K's, K''s or their
  // sum, as the triplets summed them: the same bits.
  const int n = size(), off = interface_offset();
  if (num_interface == 0 || n == 0) return K;
  const Eigen::Index ni = K_prime->rows();
  SparseMatrix copy;  // only for a hand-made K in uncompressed form
  if (!K.isCompressed()) {
    copy = K;
    copy.makeCompressed();
  }
  const SparseMatrix& Kc = K.isCompressed() ? K : copy;
  const int* kp = Kc.outerIndexPtr();
  const int* ki = Kc.innerIndexPtr();
  const double* kx = Kc.valuePtr();
  Eigen::Index nnz = 0;
  for (int j = 0; j < n; ++j) {
    if (j < off) {
      nnz += kp[j + 1] - kp[j];
      continue;
    }
    for (int q = kp[j]; q < kp[j + 1] && ki[q] < off; ++q) ++nnz;
    nnz += ni;
  }
  SparseMatrix A(n, n);
  A.resizeNonZeros(nnz);
  int* ap = A.outerIndexPtr();
  int* ai = A.innerIndexPtr();
  double* ax = A.valuePtr();
  Eigen::Index w = 0;
  for (int j = 0; j < n; ++j) {
    ap[j] = int(w);
    int q = kp[j];
    for (; q < kp[j + 1] && (j < off || ki[q] < off); ++q) ai[w] = ki[q], ax[w++] = kx[q];
    if (j < off) continue;
    const double* kpj = K_prime->data() + (j - off) * ni;  // column j - off of K'
    for (Eigen::Index r = 0; r < ni; ++r) {
      const int row = off + int(r);
      double v = kpj[r];
      if (q < kp[j + 1] && ki[q] == row) v = kx[q++] + v;
      ai[w] = row, ax[w++] = v;
    }
  }
  ap[n] = int(w);
  return A;
}

Eigen::VectorXd OperationalSystem::rhs(const Eigen::MatrixX3d& forces, const Eigen::VectorXd& P_prime) const {
  Eigen::VectorXd b(size());
  for (size_t k = 0; k < nodes.size(); ++k) b.segment<3>(3 * Eigen::Index(k)) = forces.row(nodes[k]).transpose();
  if (prestress.size() > 0) {
    if (prestress.size() != b.size())
      fail("operational system: the initial-strain forces have ", prestress.size(), " entries for ", b.size(), " unknowns");
    b += prestress;
  }
  if (num_interface > 0) b.tail(3 * Eigen::Index(num_interface)) -= P_prime;
  return b;
}

OperationalSystem build_operational_system(const mesh::TetMesh& m, const std::vector<fem::Material>& tet_material,
                                           const std::vector<int>& operational_tets,
                                           const std::vector<int>& interface_nodes,
                                           const std::vector<char>& node_fixed,
                                           const std::vector<char>& node_nonoperational,
                                           std::shared_ptr<const Eigen::MatrixXd> K_prime,
                                           const OperationalSystem* before, fem::ReassemblyReport* report) {
  const int nn = m.num_nodes();
  const Eigen::Index ni = 3 * Eigen::Index(interface_nodes.size());
  if (!K_prime || K_prime->rows() != ni || K_prime->cols() != ni)
    fail("operational system: K' must be ", ni, " x ", ni, " for ", interface_nodes.size(), " interface nodes");
  auto flag = [](const std::vector<char>& v, int i) { return size_t(i) < v.size() && v[size_t(i)]; };
  std::vector<char> is_interface(size_t(nn), 0), touched(size_t(nn), 0);
  for (int v : interface_nodes) {
    if (v < 0 || v >= nn) fail("operational system: interface node ", v, " is not a node of the mesh");
    is_interface[size_t(v)] = 1;
  }
  for (int t : operational_tets) {
    if (t < 0 || t >= m.num_tets()) fail("operational system: tet ", t, " is not a tet of the mesh");
    for (int k = 0; k < 4; ++k) {
      const int v = m.tets(t, k);
      if (flag(node_nonoperational, v))
        fail("operational system: operational tet ", t, " uses node ", v, ", a nonoperational node that is "
             "not an interface node; cutting and remeshing may touch only operational tets and must not "
             "reach past the interface");
      touched[size_t(v)] = 1;
    }
  }
  OperationalSystem sys;
  for (int v = 0; v < nn; ++v)
    if (touched[size_t(v)] && !is_interface[size_t(v)] && !flag(node_fixed, v)) sys.nodes.push_back(v);
  sys.num_operational = int(sys.nodes.size());
  sys.nodes.insert(sys.nodes.end(), interface_nodes.begin(), interface_nodes.end());
  sys.num_interface = int(interface_nodes.size());
  sys.node_index = node_positions(sys.nodes, nn);
  // K in 3x3 node blocks (apply() runs on them), and as a sparse matrix.
  // After a cut, the rows no changed tet touches come from the system before
  // it (the same bits: fem/reassembly.hpp).
  const int np = int(sys.nodes.size());
  fem::AssemblyInputs inputs;
  if (operational_tets.empty()) {
    sys.block.row_start.assign(size_t(np) + 1, 0);
  } else if (before && before->assembly) {
    sys.block = fem::reassemble_node_blocks(before->block, *before->assembly, m, tet_material, operational_tets,
                                            sys.node_index, np, report, &inputs);
  } else {
    sys.block = fem::assemble_node_blocks(m, tet_material, operational_tets, sys.node_index, np);
    inputs = fem::assembly_inputs(m, tet_material, operational_tets, sys.node_index, np);
  }
  sys.assembly = std::make_shared<const fem::AssemblyInputs>(std::move(inputs));
  sys.K = sys.block.to_sparse();
  // Initial strains and body forces of the operational tets (split tets
  // carry their parent's).
  bool loaded = false;
  for (int t : operational_tets)
    loaded = loaded || fem::has_initial_strain(tet_material[size_t(t)]) || fem::has_body_force(tet_material[size_t(t)]);
  if (loaded) sys.prestress = gather_nodes(fem::element_loads(m, tet_material, operational_tets), sys.nodes);
  // The tets whose force a frame evaluates itself (fem/nonlinear_tets.hpp):
  // a nonlinear law, or a fixed corner (whose prescribed motion, if any, they
  // carry). Only when some tet has a nonlinear law or a fixed corner.
  std::vector<int> own;
  for (int t : operational_tets) {
    bool take = tet_material[size_t(t)].model != fem::MaterialModel::linear;
    sys.nonlinear_law = sys.nonlinear_law || take;
    for (int k = 0; k < 4 && !take; ++k) take = flag(node_fixed, m.tets(t, k));
    if (take) own.push_back(t);
  }
  if (!own.empty()) sys.nonlinear = std::make_shared<const fem::NonlinearTets>(m, tet_material, std::move(own), sys.node_index);
  sys.K_prime = std::move(K_prime);
  sys.generation = next_generation++;
  return sys;
}

}  // namespace softcut::hybrid
