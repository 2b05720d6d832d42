#pragma once
// The Tresca → Coulomb fixed point of (6.3): the Coulomb bound ‖λ_τ‖ ≤ 𝔉λ_n is met by a
// sequence of Tresca problems ‖λ_τ‖ ≤ 𝔉γ, γ ← λ_n of the last one, accelerated by Aitken's Δ².
// 𝔉 is per contact node (𝔉_k of the interface temperature, interface_laws.hpp) and fixed
// while the fixed point runs.
// The QP of each Tresca bound is the caller's (the contact enforcement: nested dual or
// combined TFETI), so this file knows the iteration and its stopping rules only.
#include <functional>
#include <span>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/model/problem.hpp"

namespace tc::physics {

/// How the updates γ ← max(γ + ω r, 0), r = λ_n(γ) − γ, of the fixed point are relaxed: a
/// policy of the contact loop (choose_contact_loop), from [solver] coupling_acceleration and
/// whether any pair has friction.
enum class FrictionRelaxation {
  plain,   // ω = 1: the update of 6.3
  aitken,  // Aitken's Δ², ω from the last two residuals (ω = 1 at the first update)
};

// The Tresca → Coulomb fixed point γ = λ_n(γ) of (6.3) with Aitken's Δ² (Irons–Tuck, vector
// form as in Küttler & Wall 2008): γ ← max(γ + ω r, 0), r = λ_n(γ) − γ, ω from the last two
// residuals (ω = 1 at the first update: the plain update of 6.3).
struct TrescaIteration {
  std::vector<double> gamma, bound, residual, residual_prev;
  std::vector<double> qp_bound;  // the bound of the last QP (bound moves on with each update)
  std::vector<char> was_open;    // per node: λ_n ≤ 0 at the last update
  std::vector<char> reclosed;    // per node: closed again after an open update, in this loop
  // Aitken's ω or the plain update: the contact loop's policy (choose_contact_loop).
  FrictionRelaxation relaxation = FrictionRelaxation::plain;
  double omega = 1.0;
  double last = 1.0;  // ‖λ_n(γ) − γ‖/‖λ‖ of the last update (1 before the first of a step)
  bool converged = false;      // the last update met the tolerance, its QP solved to qp_tolerance
  bool exact_qps = false;      // the QPs of the rest of the step to qp_tolerance
  bool cut_short = false;      // stop after a 1/loop_forcing-fold fall (θ, u_free move next)
  bool defer = false;          // u formed after convergence (only B u inside: ContactCoupling)
  std::vector<double> bu_old;  // B u^k, when deferred

  // γ = λ_n of the current multipliers, the relaxation forgotten; bound_k = 𝔉_k γ_k.
  void restart(const core::Vector& lambda, int dim, std::span<const double> friction);
  // One update from λ(γ); returns ‖r‖.
  double update(const core::Vector& lambda, int dim, std::span<const double> friction);
};

/// The data of one run of the fixed point.
struct CoulombFixedPoint {
  int dim = 2;                       // rows per contact node (λ_n, λ_τ…)
  std::span<const double> friction;  // 𝔉_k per contact node
  bool frictional = false;           // the law has 𝔉 > 0 somewhere (else γ plays no part)
  double tolerance = 0;  // on ‖λ_n(γ) − γ‖/‖λ‖ ([solver] coupling_tolerance)
  double qp_tolerance = 0;
  // The forcing terms (FrictionFixedPointSettings, problem.hpp): a QP to qp_forcing × the last
  // residual within [qp_tolerance, qp_forcing_cap]; a cut-short loop stops after a
  // 1/loop_forcing-fold fall. Their defaults are the case's (one copy: problem.hpp).
  double qp_forcing = FrictionFixedPointSettings{}.qp_forcing;
  double qp_forcing_cap = FrictionFixedPointSettings{}.qp_forcing_cap;
  double loop_forcing = FrictionFixedPointSettings{}.loop_forcing;
  int max_updates = 1;
  int step = 0, outer = 0;  // for the messages: the step and the staggered iteration
};

/// QPs at the Tresca bounds t.bound, γ ← λ_n (Aitken), at most `p.max_updates` times or until
/// ‖λ_n(γ) − γ‖ ≤ tol‖λ‖; `solve_qp(rtol)` solves the contact QP at t.bound to the relative
/// tolerance rtol into `lambda` (throwing NumericalError when it fails). Returns
/// ‖λ_n(γ) − γ‖ of the last update (0 without friction: one QP, γ plays no part).
double coulomb_fixed_point(TrescaIteration& t, const core::Vector& lambda,
                           const CoulombFixedPoint& p,
                           const std::function<void(double rtol)>& solve_qp);

}  // namespace tc::physics
