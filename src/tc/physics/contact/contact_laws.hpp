#pragma once
// The discrete contact laws checked after every step (issue 41; docs/robustness.md, "The
// contact laws are checked after every step"): at every contact node of the step's rows,
//   non-penetration   g_k = c_n,k − (B u^{k+1})_n,k ≥ −b_gap,k   (the weighted gap of 5.4)
//   friction cone     ‖λ_τ,k‖ ≤ 𝔉_k max(λ_n,k, 0) + b_cone,k
// with bounds that the solvers guarantee (docs/choices.md, "The bounds of the contact laws"):
//   b_gap,k  = 2 ε_QP/σ_n,k + 1e3 ε_mach (|c_n,k| + |(Bu)_n,k|) + w_k e_solve: the QP stops
//              at ‖Σ g^P‖ ≤ ε_QP, and g = Fλ − d = c − B u, so a penetration is a component of
//              g^P; e_solve = 10 × the FETI misfit ‖B u − c‖ of the step's solves of a body cut
//              into subdomains (0 when factorised), what u misses the glued body by;
//   b_cone,k = 𝔉_k min(tol, 1e-6) ‖λ‖ + 16 ε_mach (𝔉_kγ_k + ‖λ_τ,k‖): the Tresca QP keeps
//              ‖λ_τ,k‖ ≤ 𝔉_kγ_k exactly (a projection), and the fixed point (6.3) stops at
//              ‖max(λ_n, 0) − γ‖ ≤ tol ‖λ‖ (tol = [solver] coupling_tolerance); with tol
//              above 1e-6 the nodes outside their cone are scaled onto it after it.
// A violation beyond its bound is a defect, never a result: the step stops (NumericalError,
// naming the node, the step and the setting), and Simulation cuts it back.
#include <span>
#include <string>
#include <vector>

namespace tc::physics {

/// The worst violation of one law so far, as a fraction of its bound, and where.
struct LawViolation {
  double value = 0;  // the violation in the law's unit (m for the gap, Pa for the cone)
  double bound = 0;  // its bound, same unit
  double ratio = 0;  // value / bound: ≤ 1 holds the law
  int step = 0;
  int node = -1;  // slave mesh node (−1: none yet)
  std::string pair;

  /// Keeps (value, bound) if its ratio is the worst so far.
  void offer(double v, double b, int at_step, int at_node, const std::string& at_pair);
};

/// One contact pair's part of a step's check: spans over its contact nodes (node-major
/// multipliers, dim rows per node).
struct PairLaws {
  std::string name;
  int dim = 3;
  std::span<const int> nodes;                 // slave mesh node per contact node (may be empty)
  std::span<const double> weights;            // ∫ψ_k: weighted gap / weight = a length
  std::span<const double> targets;            // c of (5.4), dim per node
  std::span<const double> constraint_values;  // B u^{k+1}, dim per node
  std::span<const double> lambda;             // λ^{k+1}, dim per node
  std::span<const double> friction;           // 𝔉_k the last QP's bound was formed with
  std::span<const double> qp_bound;           // 𝔉_kγ_k of the last QP (empty: no friction)
  std::span<const double> gap_tolerance;      // ε_QP/σ_n,k per node (the last QP's)
  std::span<const char> held;                 // crosspoints held at 0 (empty: none)
  /// What the bodies' solves left in B u beyond the QP's view of it, per unit of weight (m):
  /// K_FETI × the largest ‖B_FETI u − c‖ of the step's FETI solves of the slave and of the
  /// master (0 for bodies solved by a factorisation), and the tolerance that sets it.
  double solve_error = 0, feti_tolerance = 0;
};

/// The run's record of the laws (summary.json "contact_laws").
struct ContactLaws {
  /// The largest distance a FETI body's nodes may lie from the glued, supported solution per
  /// unit of its solve's misfit ‖B u − c‖ (PairLaws::solve_error; docs/choices.md).
  static constexpr double feti_misfit_factor = 10.0;
  /// The friction cone's tolerance relative to ‖λ‖ when [solver] coupling_tolerance is looser:
  /// the multipliers of a node outside its cone are then scaled onto it after the fixed point
  /// (ContactCoupling::scale_into_cones), and the check holds it (docs/choices.md).
  static constexpr double cone_tolerance = 1e-6;

  LawViolation gap, cone;

  /// Checks one pair after step `step` (before the state moves on). `unit`: traction per
  /// multiplier; `coupling_tolerance`, `lambda_norm`: the fixed point's stopping test.
  /// Throws NumericalError when a law is violated beyond its bound.
  void check(const PairLaws& p, double unit, double coupling_tolerance, double lambda_norm,
             double qp_tolerance, int step);
  /// The record of the sub-steps of a cut-back (Simulation::advance_by_halves), its steps
  /// counted as `step` of this run.
  void merge(const ContactLaws& sub, int step);
};

}  // namespace tc::physics
