#pragma once
// SMALBE (Dostál 2009, ch. 6; Dostál & Kučera 2010 for the semi-monotonic variant): minimise
//   f(λ) = ½ λᵀFλ − λᵀd   over λ ∈ Ω and Gλ = e,
// the TFETI dual QP (6.9) with the floating subdomains' condition G = RᵀBᵀ, e = Rᵀf (6.2,
// 6.4) written as an equality. An augmented Lagrangian in the equality only: with the rows of
// G orthonormalised (G̃ = TG, ẽ = Te, G̃G̃ᵀ = I, so Q = G̃ᵀG̃ is the orthogonal projector onto
// Im Gᵀ, as in PERMON's SMALXE),
//   L(λ, μ, ρ) = f(λ) + μᵀ(G̃λ − ẽ) + ½ρ ‖G̃λ − ẽ‖²,
// each outer iteration minimises L(·, μ_k, ρ) over Ω by MPGP/MPRGP (the Hessian F + ρQ)
// only until ‖g^P‖ ≤ min(M ‖G̃λ − ẽ‖, η), then μ_{k+1} = μ_k + ρ(G̃λ − ẽ). When L did not grow
// by at least ½ρ‖G̃λ − ẽ‖² the inner solve was too rough for the multiplier step: M falls by β
// (or ρ grows by β). This keeps L increasing ("semi-monotonic") and gives a bound on the
// outer iterations independent of the condition of G — the optimality of TFETI for contact.
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <string>

#include "tc/qp/mpgp.hpp"

namespace tc::qp {

enum class SmalbeUpdate {
  m,    // M ← M/β: the inner solves get more precise (SMALBE-M, Dostál's default)
  rho,  // ρ ← βρ: the penalty grows instead (the original SMALBE)
};

struct SmalbeOptions {
  /// Stop when ‖g^P‖ ≤ max(rtol ‖d‖, atol) (the projected gradient of the Lagrangian with the
  /// final μ) and ‖G̃λ − ẽ‖ ≤ equality_rtol ‖d‖/λ_max(F): the residual measured in units of
  /// λ, ‖d‖/λ_max(F) being the smallest λ that produces the load d.
  double rtol = 1e-8;
  double atol = 1e-30;
  double equality_rtol = 1e-8;
  int max_outer_iterations = 100;
  int max_inner_iterations = 20000;  // over all outer iterations
  /// ρ = rho_factor · λ_max(F): with Q a projector the Hessian's spectrum stays within
  /// [λ_min, λ_max(F) + ρ] on Im Gᵀ, so ρ of the size of ‖F‖ costs at most a factor 2 in the
  /// expansion step (Dostál 2009, §6.6 on the choice of ρ).
  double rho_factor = 1.0;
  /// M₀ = m_factor · λ_max(F) (M has the units of F: ‖g^P‖ against ‖G̃λ − ẽ‖).
  double m_factor = 100.0;
  double beta = 10.0;  // the factor of the M (or ρ) update, > 1
  /// η = eta_factor · ‖d‖: the cap on the inner tolerance while the equality is far off.
  double eta_factor = 0.1;
  SmalbeUpdate update = SmalbeUpdate::m;
  /// The inner solver's options: rtol, atol, max_iterations and max_eigenvalue are set per
  /// outer iteration; `scaling` is not supported (the eigenvalue bound would not apply).
  QpOptions inner;
  double max_eigenvalue = 0;  // λ_max(F) if known; 0 = Lanczos estimate (inner.lanczos_*)
  /// Warm start: μ on entry to solve() is the initial multiplier (that of a previous solve
  /// with the same G); otherwise μ starts at 0.
  bool initial_mu = false;
};

enum class SmalbeStatus { converged, max_outer_iterations, max_inner_iterations, breakdown };
[[nodiscard]] const char* name(SmalbeStatus s);

struct [[nodiscard]] SmalbeResult {
  SmalbeStatus status = SmalbeStatus::breakdown;
  int outer_iterations = 0;
  int inner_iterations = 0;       // MPGP iterations over all outer iterations
  int operator_applications = 0;  // of F, including the eigenvalue estimate
  double projected_gradient = 0;  // final ‖g^P‖ of the Lagrangian with the returned μ
  double equality_residual = 0;   // final ‖G̃λ − ẽ‖ (orthonormalised rows)
  double gradient_tolerance = 0;  // the ‖g^P‖ required
  double equality_tolerance = 0;  // the ‖G̃λ − ẽ‖ required
  double rho = 0, m = 0;          // the final penalty and M
  double max_eigenvalue = 0;      // λ_max(F) used (to reuse)
  int updates = 0;                // M (or ρ) updates
  int restarts = 0;               // inner solves resumed because ‖G̃λ − ẽ‖ fell meanwhile
  std::string message;
  [[nodiscard]] bool converged() const { return status == SmalbeStatus::converged; }
};

class Smalbe {
 public:
  /// `g_local`: the rows of G (all of them, on every rank) restricted to the columns of this
  /// rank's components of the dual vector; `e` the right-hand side (replicated). Dependent
  /// rows are dropped (e must be consistent with them).
  Smalbe(const LinearOperator& f, const FeasibleSet& set,
         const Eigen::SparseMatrix<double>& g_local, Eigen::VectorXd e, MPI_Comm comm,
         SmalbeOptions options = {});

  /// x: initial guess on entry (projected onto Ω), the solution on exit. mu: on exit the
  /// multiplier of Gλ = e, with Fλ − d + Gᵀμ the gradient of the Lagrangian (so that g^P of
  /// it vanishes at the KKT point); on entry the initial one if options.initial_mu (its
  /// component in Im G: dropped rows of G carry none). Collective.
  SmalbeResult solve(const Vector& d, Vector& x, Eigen::VectorXd& mu) const;

  [[nodiscard]] Eigen::Index n_equalities() const { return t_.rows(); }
  /// y = G̃ x (G̃ = T G, orthonormal rows) and x += a G̃ᵀ y. Collective / local.
  [[nodiscard]] Eigen::VectorXd g_times(const Vector& x) const;
  void add_gt_times(double a, const Eigen::VectorXd& y, Vector& x) const;

 private:
  const LinearOperator& f_;
  const FeasibleSet& set_;
  Eigen::SparseMatrix<double> g_;  // local columns, all rows
  Eigen::MatrixXd t_;              // T: G̃ = T G, rank(G) × rows(G)
  Eigen::VectorXd e_tilde_;        // T e
  MPI_Comm comm_;
  SmalbeOptions options_;
};

}  // namespace tc::qp
