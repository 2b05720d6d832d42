#include "tc/physics/body/rigid_coupling.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "tc/core/error.hpp"

namespace tc::physics {

RigidCoupling::RigidCoupling(const BodySystem& sys, const ConstrainedSolver& solver,
                             const std::function<void(const core::Vector&, core::Vector&)>& a)
    : sys_(&sys), faces_(&sys.coupled_faces()) {
  const int n = size();
  const auto& dirichlet = sys.u_dirichlet_dofs();
  core::Vector zero(sys.n_u()), y(sys.n_u());
  for (int j = 0; j < n; ++j) {
    core::Vector phi(sys.n_u());
    {
      auto v = phi.view();
      for (const PetscInt d : face(j).dofs) v[d] = 1.0;
    }
    a(phi, y);
    {
      const auto yv = y.read();
      double sum = 0;
      for (const PetscInt d : face(j).dofs) sum += yv[d];
      face_stiffness_.push_back(sum);
    }
    solver.solve(zero, phi);  // A_D Φ = 0 on the free dofs, Φ = e_j on the constrained ones
    a(phi, y);
    std::vector<std::pair<PetscInt, double>> r;
    {
      const auto yv = y.read();
      for (const PetscInt d : dirichlet)
        if (yv[d] != 0.0) r.emplace_back(d, yv[d]);
    }
    phi_.push_back(std::move(phi));
    a_phi_.push_back(std::move(r));
  }
  s_ = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j)
    for (int l = 0; l < n; ++l) {
      const auto& dofs = face(l).dofs;
      for (const auto& [d, v] : a_phi_[j])
        if (std::binary_search(dofs.begin(), dofs.end(), d)) s_(j, l) += v;
    }
  s_ = 0.5 * (s_ + s_.transpose());  // Φ_jᵀAΦ_l: symmetric up to round-off
  w_.assign(static_cast<size_t>(n), 0.0);
  written_ = w_;
}

void RigidCoupling::write(core::Vector& x) {
  auto v = x.view();
  for (int j = 0; j < size(); ++j)
    for (const PetscInt d : face(j).dofs) v[d] = w_[j];
  written_ = w_;
}

std::vector<double> RigidCoupling::free_resultant(const core::Vector& x,
                                                  const core::Vector& b) const {
  std::vector<double> r(static_cast<size_t>(size()));
  const auto xv = x.read();
  for (int j = 0; j < size(); ++j) {
    double sum = 0;
    for (const auto& [d, v] : a_phi_[j]) sum += v * xv[d];
    r[j] = sum - phi_[j].dot(b);
  }
  return r;
}

void RigidCoupling::balance(double t, const core::Vector& b, core::Vector& x, int step,
                            int iteration) {
  const int n = size();
  for (auto& v : w_) v = 0.0;
  write(x);
  const auto r0 = free_resultant(x, b);
  Eigen::VectorXd rhs(n);
  double scale = 0;
  for (int j = 0; j < n; ++j) {
    rhs[j] = face(j).force(t) - r0[j];
    scale = std::max(scale, s_(j, j));
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(s_);
  // S = ΦᵀAΦ ≥ 0; a zero pivot is a body that floats in a loaded direction (quasistatic,
  // held by nothing else): no w balances the load.
  const double pivot = ldlt.vectorD().cwiseAbs().minCoeff();
  if (!(pivot > 1e-12 * scale))
    throw NumericalError(
        fmt::format("load control: the face '{}' cannot balance its force: the body is not held "
                    "in the loaded direction (stiffness {:.3e} against {:.3e})",
                    face(0).label, pivot, scale),
        step, iteration, pivot);
  const Eigen::VectorXd w = ldlt.solve(rhs);
  for (int j = 0; j < n; ++j) w_[j] = w[j];
  write(x);
}

void RigidCoupling::shift_to_w(core::Vector& x) {
  for (int j = 0; j < size(); ++j)
    if (const double dw = w_[j] - written_[j]; dw != 0.0) x.axpy(dw, phi_[j]);
  written_ = w_;
}

}  // namespace tc::physics
