#include "tc/qp/smalbe.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "tc/core/error.hpp"
#include "tc/core/numeric/collective.hpp"

namespace tc::qp {

const char* name(SmalbeStatus s) {
  switch (s) {
    case SmalbeStatus::converged:
      return "converged";
    case SmalbeStatus::max_outer_iterations:
      return "max_outer_iterations";
    case SmalbeStatus::max_inner_iterations:
      return "max_inner_iterations";
    case SmalbeStatus::breakdown:
      return "breakdown";
  }
  return "?";
}

namespace {

/// Counts the applications of F (the unit of cost of a FETI dual solve: subdomain solves).
class Counted final : public LinearOperator {
 public:
  explicit Counted(const LinearOperator& f) : f_(f) {}
  void apply(const Vector& x, Vector& y) const override {
    ++count;
    f_.apply(x, y);
  }
  [[nodiscard]] Vector make_vector() const override { return f_.make_vector(); }
  mutable int count = 0;

 private:
  const LinearOperator& f_;
};

/// F + ρQ, Q = G̃ᵀG̃: the Hessian of L(·, μ, ρ).
class Augmented final : public LinearOperator {
 public:
  Augmented(const LinearOperator& f, const Smalbe& s, double rho) : f_(f), s_(s), rho(rho) {}
  void apply(const Vector& x, Vector& y) const override {
    f_.apply(x, y);
    s_.add_gt_times(rho, s_.g_times(x), y);
  }
  [[nodiscard]] Vector make_vector() const override { return f_.make_vector(); }

 private:
  const LinearOperator& f_;
  const Smalbe& s_;

 public:
  double rho;
};

}  // namespace

Smalbe::Smalbe(const LinearOperator& f, const FeasibleSet& set,
               const Eigen::SparseMatrix<double>& g_local, Eigen::VectorXd e, MPI_Comm comm,
               SmalbeOptions options)
    : f_(f), set_(set), g_(g_local), comm_(comm), options_(std::move(options)) {
  if (options_.inner.scaling) throw std::invalid_argument("Smalbe: inner scaling not supported");
  if (options_.beta <= 1) throw std::invalid_argument("Smalbe: beta must be > 1");
  if (g_.cols() != set.local_size() || e.size() != g_.rows())
    throw std::invalid_argument("Smalbe: G, e and the set disagree in size");
  Eigen::MatrixXd ggt = Eigen::MatrixXd(g_ * g_.transpose());
  core::sum_over_ranks(comm_, ggt.data(), ggt.size(), "Smalbe");
  // T = Λ^(−1/2) Vᵀ over the eigenpairs of GGᵀ above round-off: G̃ = TG has orthonormal rows
  // spanning Im G whatever the dependent rows (a body held only by contact has a rigid motion
  // that B does not see; build_deflation of Feti drops it the same way).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(ggt);
  const Eigen::VectorXd& ev = eig.eigenvalues();
  Eigen::Index dropped = 0;
  const double top = ev.size() > 0 ? ev[ev.size() - 1] : 0.0;
  while (dropped < ev.size() && ev[dropped] <= 1e-12 * top) ++dropped;
  const Eigen::Index r = ev.size() - dropped;
  t_ = ev.tail(r).cwiseSqrt().cwiseInverse().asDiagonal() *
       eig.eigenvectors().rightCols(r).transpose();
  e_tilde_ = t_ * e;
}

Eigen::VectorXd Smalbe::g_times(const Vector& x) const {
  const auto xv = x.read();
  const Eigen::Map<const Eigen::VectorXd> xl(xv.span().data(), set_.local_size());
  Eigen::VectorXd y = g_ * xl;
  core::sum_over_ranks(comm_, y.data(), y.size(), "Smalbe");
  return t_ * y;
}

void Smalbe::add_gt_times(double a, const Eigen::VectorXd& y, Vector& x) const {
  const Eigen::VectorXd z = g_.transpose() * (t_.transpose() * y);
  auto xv = x.view();
  for (Eigen::Index i = 0; i < z.size(); ++i) xv[static_cast<PetscInt>(i)] += a * z[i];
}

SmalbeResult Smalbe::solve(const Vector& d, Vector& x, Eigen::VectorXd& mu) const {
  SmalbeResult r;
  const Counted f(f_);
  double lmax = options_.max_eigenvalue;
  if (lmax <= 0) {
    const auto est =
        estimate_max_eigenvalue(f, options_.inner.lanczos_steps, options_.inner.lanczos_tolerance);
    lmax = est.bound;
  }
  r.max_eigenvalue = lmax;
  const double dnorm = d.norm();
  r.gradient_tolerance = std::max(options_.rtol * dnorm, options_.atol);
  r.equality_tolerance = options_.equality_rtol * dnorm / lmax;
  const double eta = std::max(options_.eta_factor * dnorm, r.gradient_tolerance);
  Augmented h(f, *this, options_.rho_factor * lmax);
  double m = options_.m_factor * lmax;

  Eigen::VectorXd mu_t = Eigen::VectorXd::Zero(t_.rows());  // μ̃ of the orthonormal rows
  if (options_.initial_mu) {
    if (mu.size() != g_.rows()) throw std::invalid_argument("Smalbe: initial μ of the wrong size");
    // μ = Tᵀμ̃ with T's rows orthogonal: μ̃ = (TTᵀ)⁻¹Tμ (TTᵀ = Λ⁻¹, diagonal).
    mu_t = (t_ * t_.transpose()).ldlt().solve(t_ * mu);
  }
  Vector dk = d.duplicate(), g = d.duplicate(), free = d.duplicate(), chopped = d.duplicate(),
         projected = d.duplicate();
  set_.project(x);
  Eigen::VectorXd res = g_times(x) - e_tilde_;
  double l_prev = 0;
  bool have_prev = false;
  auto finish = [&](SmalbeStatus s, std::string why) {
    r.status = s;
    r.rho = h.rho;
    r.m = m;
    r.operator_applications = f.count;
    mu = t_.transpose() * mu_t;
    r.message = fmt::format(
        "{} after {} outer / {} inner iterations, {} applications of F: ‖g^P‖ = {:.3e} "
        "(tolerance {:.3e}), ‖Gλ − e‖ = {:.3e} (tolerance {:.3e}), ρ = {:.3e}, M = {:.3e}",
        why, r.outer_iterations, r.inner_iterations, r.operator_applications, r.projected_gradient,
        r.gradient_tolerance, r.equality_residual, r.equality_tolerance, h.rho, m);
    return r;
  };

  for (;;) {
    if (r.outer_iterations >= options_.max_outer_iterations)
      return finish(SmalbeStatus::max_outer_iterations, "outer iteration cap");
    // The inner right-hand side: ∇L(λ, μ̃, ρ) = (F + ρQ)λ − (d − G̃ᵀμ̃ + ρG̃ᵀẽ).
    dk.copy_from(d);
    add_gt_times(1.0, h.rho * e_tilde_ - mu_t, dk);
    QpResult in;
    // The adaptive precision ‖g^P‖ ≤ min(M‖G̃λ − ẽ‖, η) is a test at the inner iterate, whose
    // ‖G̃λ − ẽ‖ moves while MPGP runs: solve to the bound of the current point and resume if the
    // point reached needs a tighter one. The floor at the final tolerance keeps a feasible λ
    // from asking for an exact inner solve (M‖G̃λ − ẽ‖ → 0).
    for (int pass = 0;; ++pass) {
      const double target = std::max(std::min(m * res.norm(), eta), r.gradient_tolerance);
      QpOptions o = options_.inner;
      o.rtol = 0;
      o.atol = target;
      o.max_eigenvalue = lmax + h.rho;  // ‖F + ρQ‖ ≤ ‖F‖ + ρ‖Q‖, ‖Q‖ = 1
      o.max_iterations = options_.max_inner_iterations - r.inner_iterations;
      if (o.max_iterations <= 0)
        return finish(SmalbeStatus::max_inner_iterations, "inner iteration cap");
      in = Mpgp(h, set_, o).solve(dk, x);
      r.inner_iterations += in.iterations;
      if (in.status == QpStatus::breakdown)
        return finish(SmalbeStatus::breakdown, "inner breakdown: " + in.message);
      res = g_times(x) - e_tilde_;
      if (in.status == QpStatus::max_iterations)
        return finish(SmalbeStatus::max_inner_iterations, "inner iteration cap");
      if (in.projected_gradient <= std::max(std::min(m * res.norm(), eta), r.gradient_tolerance))
        break;
      if (pass >= 20) break;  // the inner test cannot be met (round-off): go on with μ
      ++r.restarts;
    }
    ++r.outer_iterations;
    // L(λ_k, μ_k, ρ) from the gradient (one more application of F): ∇L = Fλ − d + G̃ᵀ(μ̃ + ρr).
    h.apply(x, g);
    g.axpy(-1.0, dk);
    const double l = objective_from_gradient(x, g, dk) - mu_t.dot(e_tilde_) +
                     0.5 * h.rho * e_tilde_.squaredNorm();
    set_.split_gradient(x, g, free, chopped, projected);
    r.projected_gradient = projected.norm();
    r.equality_residual = res.norm();
    // μ_{k+1} = μ_k + ρ(G̃λ − ẽ): then ∇L(λ, μ_k, ρ) is the gradient of the plain Lagrangian
    // with μ_{k+1}, so the KKT test below is the one of the returned pair (λ, μ).
    mu_t += h.rho * res;
    if (r.projected_gradient <= r.gradient_tolerance && r.equality_residual <= r.equality_tolerance)
      return finish(SmalbeStatus::converged, "converged");
    // Semi-monotonicity (Dostál 2009, Alg. 6.2, step 3): L must have grown by ½ρ‖G̃λ − ẽ‖².
    const double sq = res.squaredNorm();
    if (have_prev && l < l_prev + 0.5 * h.rho * sq) {
      ++r.updates;
      if (options_.update == SmalbeUpdate::m) {
        m /= options_.beta;
      } else {
        h.rho *= options_.beta;
        have_prev = false;  // L with another ρ: compare from the next iteration on
        continue;
      }
    }
    l_prev = l;
    have_prev = true;
  }
}

}  // namespace tc::qp
