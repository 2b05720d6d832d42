#include "tc/model/checks.hpp"

#include <Eigen/Dense>

namespace tc::physics {

int free_rigid_modes(const Problem& p, int b) {
  const int dim = p.dimension;
  const int n_modes = dim == 2 ? 3 : 6;
  const auto& m = p.bodies.at(b).mesh;
  // Centre and scale coordinates so rotations and translations have comparable size.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& x : m.points())
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], x[k]), hi[k] = std::max(hi[k], x[k]);
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double scale = std::max((hi - lo).maxCoeff(), 1e-300);

  // The rigid modes' values on dof k of node a (a row of R).
  const auto mode_row = [&](int a, int k) {
    const auto& x = m.point(a);
    const double X = (x[0] - centre[0]) / scale, Y = (x[1] - centre[1]) / scale,
                 Z = (x[2] - centre[2]) / scale;
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n_modes);
    r[k] = 1.0;  // translations
    if (dim == 2) {
      r[2] = k == 0 ? -Y : X;  // rotation about z
    } else {
      const double rot[3][3] = {{0, Z, -Y}, {-Z, 0, X}, {Y, -X, 0}};  // ω × x, row = k
      for (int w = 0; w < 3; ++w) r[3 + w] = rot[k][w];
    }
    return r;
  };
  bool in_contact = false;
  for (const auto& c : p.contacts)
    in_contact = in_contact || c.slave_body == b || c.master_body == b;
  // Gram matrix Σ r_i r_jᵀ over the constraints' rows of the rigid modes r (columns).
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n_modes, n_modes);
  for (const auto& bc : p.boundaries) {
    if (bc.body != b) continue;
    const auto nodes = m.boundary_nodes(bc.where);
    for (int k = 0; k < dim; ++k) {
      if (bc.displacement[k])
        for (const int a : nodes) {
          const auto r = mode_row(a, k);
          gram += r * r.transpose();
        }
      if (bc.force[k] && !nodes.empty()) {
        // A rigid coupling makes dof k equal over the face (rows r_a − r̄): it holds the
        // rotations that would tilt the face, not the translation along k, which only the
        // contact can hold (then checked when the load is balanced: rigid_coupling.hpp).
        Eigen::VectorXd mean = Eigen::VectorXd::Zero(n_modes);
        for (const int a : nodes) mean += mode_row(a, k);
        mean /= static_cast<double>(nodes.size());
        for (const int a : nodes) {
          const Eigen::VectorXd r = mode_row(a, k) - mean;
          gram += r * r.transpose();
        }
        if (in_contact) {
          Eigen::VectorXd t = Eigen::VectorXd::Zero(n_modes);
          t[k] = 1.0;
          gram += t * t.transpose();
        }
      }
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram);
  // Each constrained node adds O(1) to the Gram matrix; 1e-8 separates "held" from round-off.
  int free = 0;
  for (int i = 0; i < n_modes; ++i) free += eig.eigenvalues()[i] < 1e-8 ? 1 : 0;
  return free;
}

}  // namespace tc::physics
