#include "ccx.hpp"

#include <Eigen/LU>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace softcut::test {

namespace fs = std::filesystem;

namespace {

std::string read_all(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

Eigen::MatrixX3d run_ccx(const CcxProblem& p, const fs::path& dir) {
  const int nn = p.mesh.num_nodes();
  fs::create_directories(dir);
  {
    std::ofstream f(dir / "job.inp");
    // ccx reads at most 20 characters of a number ("-9.25925925925926e-05"
    // loses its exponent's last digit): 12 significant digits fit any value.
    f.precision(12);
    f << "*NODE, NSET=NALL\n";
    for (int n = 0; n < nn; ++n) f << n + 1 << ", " << p.mesh.nodes(n, 0) << ", " << p.mesh.nodes(n, 1) << ", " << p.mesh.nodes(n, 2) << "\n";
    // C3D4: the first three corners counterclockwise seen from the fourth,
    // which is softcut's positive orientation.
    f << "*ELEMENT, TYPE=C3D4, ELSET=EALL\n";
    for (int t = 0; t < p.mesh.num_tets(); ++t)
      f << t + 1 << ", " << p.mesh.tets(t, 0) + 1 << ", " << p.mesh.tets(t, 1) + 1 << ", " << p.mesh.tets(t, 2) + 1 << ", "
        << p.mesh.tets(t, 3) + 1 << "\n";
    f << "*MATERIAL, NAME=TISSUE\n";
    if (p.law == CcxProblem::Law::elastic) {
      f << "*ELASTIC\n" << p.young << ", " << p.poisson << "\n";
    } else {
      const double mu = p.young / (2 * (1 + p.poisson)), K = p.young / (3 * (1 - 2 * p.poisson));
      f << "*HYPERELASTIC, NEO HOOKE\n" << mu / 2 << ", " << 2 / K << "\n";
    }
    f << "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE\n";
    f << "*BOUNDARY\n";
    for (int n : p.fixed)
      for (int a = 0; a < 3; ++a) f << n + 1 << ", " << a + 1 << ", " << a + 1 << ", " << (p.prescribed.size() ? p.prescribed(n, a) : 0.0) << "\n";
    // Small increments (ccx halves them as it needs), tight convergence:
    // residual and correction at 1e-10 of their references.
    f << "*STEP, NLGEOM, INC=10000\n*STATIC\n0.02, 1.0, 1e-8, 0.05\n";
    f << "*CONTROLS, PARAMETERS=FIELD\n1e-10, 1e-10\n";
    f << "*CONTROLS, PARAMETERS=TIME INCREMENTATION\n40, 60, 90, 100, 30, 40, 10, 100\n";
    if (p.forces.size()) {
      f << "*CLOAD\n";
      for (int n = 0; n < nn; ++n)
        for (int a = 0; a < 3; ++a)
          if (p.forces(n, a) != 0) f << n + 1 << ", " << a + 1 << ", " << p.forces(n, a) << "\n";
    }
    f << "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
  }
  const std::string cmd = "cd '" + dir.string() + "' && ccx -i job > ccx.log 2>&1";
  if (std::system(cmd.c_str()) != 0 || !fs::exists(dir / "job.dat"))
    throw std::runtime_error("ccx (Debian's calculix-ccx, installed by scripts/install-deps.sh --test) failed: " +
                             read_all(dir / "ccx.log").substr(0, 4000));
  const std::string log = read_all(dir / "ccx.log");
  if (log.find("*ERROR") != std::string::npos) throw std::runtime_error("ccx reported an error: " + log.substr(0, 4000));
  // The last "displacements" block is the end of the step (time 1.0).
  const std::string dat = read_all(dir / "job.dat");
  const size_t at = dat.rfind("displacements (vx,vy,vz)");
  if (at == std::string::npos) throw std::runtime_error("ccx wrote no displacements: " + log.substr(0, 4000));
  if (dat.find("time  0.1000000E+01", at) == std::string::npos)
    throw std::runtime_error("ccx did not reach the end of the step: " + log.substr(log.size() > 4000 ? log.size() - 4000 : 0));
  std::istringstream in(dat.substr(dat.find('\n', at) + 1));
  Eigen::MatrixX3d u = Eigen::MatrixX3d::Zero(nn, 3);
  int read = 0, id;
  double x, y, z;
  while (in >> id >> x >> y >> z) {
    if (id < 1 || id > nn) break;
    u.row(id - 1) << x, y, z;
    ++read;
  }
  if (read != nn) throw std::runtime_error("ccx's .dat gave " + std::to_string(read) + " of " + std::to_string(nn) + " nodes");
  return u;
}

double deformed_volume(const mesh::TetMesh& m, const Eigen::MatrixX3d& u) {
  double v = 0;
  for (int t = 0; t < m.num_tets(); ++t) {
    Eigen::Matrix3d D;
    for (int k = 0; k < 3; ++k)
      D.col(k) = (m.node(m.tets(t, k + 1)) + u.row(m.tets(t, k + 1)).transpose()) -
                 (m.node(m.tets(t, 0)) + u.row(m.tets(t, 0)).transpose());
    v += D.determinant() / 6;
  }
  return v;
}

}  // namespace softcut::test
