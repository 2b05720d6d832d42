#include "tc/physics/checks.hpp"

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

  // Gram matrix Σ r_i r_jᵀ over the constrained dofs of the rigid modes r (columns).
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n_modes, n_modes);
  for (const auto& bc : p.boundaries) {
    if (bc.body != b) continue;
    for (const int a : m.boundary_nodes(bc.where)) {
      const auto& x = m.point(a);
      const double X = (x[0] - centre[0]) / scale, Y = (x[1] - centre[1]) / scale,
                   Z = (x[2] - centre[2]) / scale;
      for (int k = 0; k < dim; ++k) {
        if (!bc.displacement[k]) continue;
        Eigen::VectorXd r = Eigen::VectorXd::Zero(n_modes);
        r[k] = 1.0;  // translations
        if (dim == 2) {
          r[2] = k == 0 ? -Y : X;  // rotation about z
        } else {
          const double rot[3][3] = {{0, Z, -Y}, {-Z, 0, X}, {Y, -X, 0}};  // ω × x, row = k
          for (int w = 0; w < 3; ++w) r[3 + w] = rot[k][w];
        }
        gram += r * r.transpose();
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
