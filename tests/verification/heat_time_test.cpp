// Backward Euler for the heat equation (5.5–5.6): first order in τ against the exact solution
// of the same semi-discrete system, θ_F(t) = Σ ψ_i e^{−μ_i t} ψ_iᵀ M (θ⁰ − θ_eq) + θ_eq.
#include <gtest/gtest.h>

#include <cmath>

#include "support/problems.hpp"
#include "tc/run/simulation.hpp"

using namespace tc;

namespace {

physics::Problem cooling_bar(double step, int n_steps) {
  auto mat = test::steel();
  mat.thermal_expansion = 0;  // heat only
  auto p =
      test::box_problem(2, {0.1, 0.02, 0}, {8, 2, 1}, mat, physics::Scheme::dynamic, step, n_steps);
  p.bodies[0].initial_temperature = 400.0;
  physics::BoundaryCondition cold;
  cold.where = "xmin";
  cold.temperature = core::TimeTable(300.0);
  p.boundaries.push_back(cold);
  return p;
}

TEST(BackwardEuler, FirstOrderOnACoolingBar) {
  physics::Simulation probe(cooling_bar(1.0, 1));
  const auto& sys = probe.system(0);
  const auto k = test::to_dense(sys.matrices().stiffness_theta);
  const auto m = test::to_dense(sys.matrices().mass_theta);
  std::vector<int> free;
  std::vector<char> fixed(sys.n_theta(), 0);
  for (const auto d : sys.theta_dirichlet_dofs()) fixed[d] = 1;
  for (int i = 0; i < sys.n_theta(); ++i)
    if (!fixed[i]) free.push_back(i);
  const auto n = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd kf(n, n), mf(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      kf(i, j) = k(free[i], free[j]), mf(i, j) = m(free[i], free[j]);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(kf, mf);
  // θ_eq = 300 everywhere (insulated elsewhere); θ⁰ − θ_eq = 100 on the free dofs.
  const Eigen::VectorXd d0 = Eigen::VectorXd::Constant(n, 100.0);
  const double mu_min = eig.eigenvalues().minCoeff();
  const double t_end = 1.0 / mu_min;  // the slowest mode has decayed by e
  auto exact = [&](double t) {
    Eigen::VectorXd th = Eigen::VectorXd::Constant(n, 300.0);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto psi = eig.eigenvectors().col(i);
      th += psi * (std::exp(-eig.eigenvalues()[i] * t) * psi.dot(mf * d0));
    }
    return th;
  };
  std::vector<double> errors, taus;
  for (int level = 0; level < 3; ++level) {
    const int steps = 40 << level;
    const double tau = t_end / steps;
    physics::Simulation sim(cooling_bar(tau, steps));
    for (int s = 0; s < steps; ++s) sim.advance();
    const auto th = test::to_eigen(sim.state(0).theta);
    const auto te = exact(sim.time());
    Eigen::VectorXd tf(n);
    for (Eigen::Index i = 0; i < n; ++i) tf[i] = th[free[i]];
    errors.push_back((tf - te).norm() / (te.array() - 300.0).matrix().norm());
    taus.push_back(tau);
  }
  for (size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log(errors[i - 1] / errors[i]) / std::log(taus[i - 1] / taus[i]);
    EXPECT_GE(order, 0.95) << "errors " << errors[i - 1] << " -> " << errors[i];
    EXPECT_LE(order, 1.3);  // and not spuriously higher: this is backward Euler
  }
}

}  // namespace
