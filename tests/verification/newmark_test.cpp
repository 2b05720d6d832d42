// Newmark average acceleration (5.1–5.3): second order and energy conserving. The reference
// is the exact solution of the same semi-discrete system, u_F(t) = Σ φ_i (φ_iᵀ f)/ω_i² (1 −
// cos ω_i t) for a load switched on at t = 0 (modal superposition, computed densely here).
#include <gtest/gtest.h>

#include <cmath>

#include "support/problems.hpp"
#include "tc/run/simulation.hpp"

using namespace tc;

namespace {

struct Modal {
  Eigen::VectorXd omega;   // ω_i
  Eigen::MatrixXd phi;     // M-orthonormal modes on the free dofs
  std::vector<int> free;   // free dof indices
  Eigen::VectorXd f_free;  // load on the free dofs
};

physics::Problem cantilever(double step, int n_steps) {
  auto mat = test::steel();
  mat.thermal_expansion = 0;  // purely mechanical
  auto p =
      test::box_problem(2, {1.0, 0.25, 0}, {6, 2, 1}, mat, physics::Scheme::dynamic, step, n_steps);
  p.boundaries.push_back(test::hold("xmin", {0, 1}));
  physics::BoundaryCondition tip;
  tip.where = "xmax";
  tip.traction[1] = core::TimeTable(-1.0e6);  // a step load at t = 0
  p.boundaries.push_back(tip);
  return p;
}

Modal modal_analysis(const physics::Simulation& sim) {
  const auto& sys = sim.system(0);
  const auto k = test::to_dense(sys.matrices().stiffness_u);
  const auto m = test::to_dense(sys.matrices().mass_u);
  core::Vector f(sys.n_u());
  sys.mechanical_load(1.0, f);
  const auto fe = test::to_eigen(f);
  Modal out;
  std::vector<char> fixed(sys.n_u(), 0);
  for (const auto d : sys.u_dirichlet_dofs()) fixed[d] = 1;
  for (int i = 0; i < sys.n_u(); ++i)
    if (!fixed[i]) out.free.push_back(i);
  const auto n = static_cast<Eigen::Index>(out.free.size());
  Eigen::MatrixXd kf(n, n), mf(n, n);
  out.f_free.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    out.f_free[i] = fe[out.free[i]];
    for (Eigen::Index j = 0; j < n; ++j) {
      kf(i, j) = k(out.free[i], out.free[j]);
      mf(i, j) = m(out.free[i], out.free[j]);
    }
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(kf, mf);
  out.omega = eig.eigenvalues().cwiseSqrt();
  out.phi = eig.eigenvectors();
  return out;
}

Eigen::VectorXd exact(const Modal& md, double t) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(md.phi.rows());
  for (Eigen::Index i = 0; i < md.omega.size(); ++i) {
    const double w = md.omega[i];
    u += md.phi.col(i) * (md.phi.col(i).dot(md.f_free) / (w * w) * (1 - std::cos(w * t)));
  }
  return u;
}

TEST(Newmark, SecondOrderOnAForcedVibration) {
  // Resolve the stiffest mode (τ ω_max ≤ 0.4) so the error is in the asymptotic range.
  physics::Simulation probe(cantilever(1.0, 1));
  const auto md = modal_analysis(probe);
  const double t_end = 2 * M_PI / md.omega.minCoeff();  // one period of the lowest mode
  const double tau0 = 0.4 / md.omega.maxCoeff();
  std::vector<double> errors, taus;
  for (int level = 0; level < 3; ++level) {
    const int n = static_cast<int>(std::ceil(t_end / tau0)) << level;
    const double tau = t_end / n;
    const auto p = cantilever(tau, n);
    physics::Simulation sim(p);
    for (int s = 0; s < n; ++s) sim.advance();
    const auto u = test::to_eigen(sim.state(0).u);
    const auto ue = exact(md, sim.time());
    Eigen::VectorXd uf(ue.size());
    for (Eigen::Index i = 0; i < ue.size(); ++i) uf[i] = u[md.free[i]];
    errors.push_back((uf - ue).norm() / ue.norm());
    taus.push_back(tau);
  }
  for (size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log(errors[i - 1] / errors[i]) / std::log(taus[i - 1] / taus[i]);
    RecordProperty("order_" + std::to_string(i), std::to_string(order));
    EXPECT_GE(order, 1.9) << "errors " << errors[i - 1] << " -> " << errors[i];
  }
}

TEST(Newmark, EnergyConservedOver1000Steps) {
  // The tip load acts for 0.5 ms and is then released: afterwards the vibration is free and
  // E = ½u̇ᵀMu̇ + ½uᵀKu must stay constant. Throughout, E − W_ext is constant (= 0).
  auto p = cantilever(1e-5, 1000);
  p.boundaries[1].traction[1] = core::TimeTable({0.0, 5e-4, 5.1e-4}, {-1.0e6, -1.0e6, 0.0});
  physics::Simulation sim(p);
  double e_free = -1, worst_free = 0, worst_balance = 0, e_max = 0;
  for (int s = 0; s < 1000; ++s) {
    sim.advance();
    const double e = sim.kinetic_energy() + sim.strain_energy();
    e_max = std::max(e_max, e);
    worst_balance = std::max(worst_balance, std::abs(e - sim.history("external_work")));
    if (sim.time() > 5.1e-4 + 1e-12) {
      if (e_free < 0) e_free = e;
      worst_free = std::max(worst_free, std::abs(e - e_free));
    }
  }
  ASSERT_GT(e_max, 0);
  // Average acceleration conserves the discrete energy exactly; what is left is the direct
  // solver's round-off accumulated over 1000 steps (~1e-13 per step).
  EXPECT_LT(worst_free / e_free, 1e-10);
  EXPECT_LT(worst_balance / e_max, 1e-10);
}

}  // namespace
