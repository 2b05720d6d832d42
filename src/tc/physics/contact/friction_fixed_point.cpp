#include "tc/physics/contact/friction_fixed_point.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "tc/core/error.hpp"

namespace tc::physics {

void TrescaIteration::restart(const core::Vector& lambda, int dim,
                              std::span<const double> friction) {
  const auto lv = lambda.read();
  const auto nc = static_cast<size_t>(lambda.size() / dim);
  gamma.resize(nc);
  bound.resize(nc);
  residual.resize(nc);
  residual_prev.clear();
  was_open.assign(nc, 0);
  reclosed.assign(nc, 0);
  omega = 1.0;
  for (size_t k = 0; k < nc; ++k) {
    gamma[k] = std::max(lv[dim * static_cast<PetscInt>(k)], 0.0);
    bound[k] = friction[k] * gamma[k];
  }
}

double TrescaIteration::update(const core::Vector& lambda, int dim,
                               std::span<const double> friction) {
  const auto lv = lambda.read();
  const size_t nc = gamma.size();
  for (size_t k = 0; k < nc; ++k)
    residual[k] = std::max(lv[dim * static_cast<PetscInt>(k)], 0.0) - gamma[k];
  const bool aitken = relaxation == FrictionRelaxation::aitken;
  if (aitken && !residual_prev.empty()) {
    double num = 0, den = 0;
    for (size_t k = 0; k < nc; ++k) {
      const double dr = residual[k] - residual_prev[k];
      num += residual_prev[k] * dr;
      den += dr * dr;
    }
    // kept near the plain step: once λ is at the QP's accuracy the residuals are noise and
    // so would be ω
    if (den > 0) omega = std::clamp(-omega * num / den, 0.5, 1.5);
  }
  const double w = aitken ? omega : 1.0;
  double norm = 0;
  if (was_open.size() != nc) was_open.assign(nc, 0);
  if (reclosed.size() != nc) reclosed.assign(nc, 0);
  for (size_t k = 0; k < nc; ++k) {
    norm += residual[k] * residual[k];
    // A node whose λ_n(γ) is ≤ 0 carries no normal force: its Coulomb bound is 0, which the
    // plain update reaches at once. Aitken's ω (one secant factor for the whole vector) is
    // < 1 about half the time and would only shrink its bound geometrically: circles of
    // 1e-4 of the multipliers at open nodes, on which MPGP stagnated at the onset of sliding
    // of a lightly held pin (issue 41, docs/choices.md "Open nodes leave the friction bound
    // at once"). Not for a node that has closed again after opening in this loop: one that
    // opens and closes by turns needs the relaxation (ContactPairs' stack cycled without it).
    const bool open = lv[dim * static_cast<PetscInt>(k)] <= 0;
    gamma[k] = open && !reclosed[k] ? 0.0 : std::max(gamma[k] + w * residual[k], 0.0);
    if (!open && was_open[k]) reclosed[k] = 1;
    was_open[k] = open ? 1 : 0;
    bound[k] = friction[k] * gamma[k];
  }
  residual_prev = residual;
  return std::sqrt(norm);
}

double coulomb_fixed_point(TrescaIteration& t, const core::Vector& lambda,
                           const CoulombFixedPoint& p,
                           const std::function<void(double rtol)>& solve_qp) {
  const double tol = p.tolerance;
  const double qp_tol = p.qp_tolerance;
  double residual = 0;
  // Inexact where it cannot matter (forcing terms as in inexact Newton methods):
  // - a QP to qp_forcing of the last fixed-point residual, clamped to [qp_tolerance,
  //   qp_forcing_cap] (a cap below the QP tolerance means no forcing); a residual that
  //   doubles shows a loose QP's λ passed for converged (seen on bench/contact's long
  //   quasistatic slides: the loop cycled), and the step's QPs are exact from then on;
  // - with thermal expansion, while the residual is above the tolerance, the loop at this θ
  //   stops once its residual fell by loop_forcing (1e-2) from the loop's largest: θ moves in the
  //   next heat step, and with it u_free and λ (measured on example 06: λ_n(γ) − γ jumps back to
  //   ~2e-3 of ‖λ‖ at the next iteration whatever the accuracy reached before).
  // The outer loop stops only on an update that met the tolerance with a QP to the QP
  // tolerance, so the fixed point it returns is that of the exact scheme.
  const bool friction = p.frictional;
  double peak = 0;  // the loop's largest residual, its scale (the first can be tiny: below)
  for (int update = 1; update <= p.max_updates; ++update) {
    const double rtol = friction && !t.exact_qps ? std::clamp(p.qp_forcing * t.last, qp_tol,
                                                              std::max(p.qp_forcing_cap, qp_tol))
                                                 : qp_tol;
    solve_qp(rtol);
    t.converged = rtol <= qp_tol;
    if (!friction) break;  // γ plays no part
    t.qp_bound = t.bound;
    residual = t.update(lambda, p.dim, p.friction);
    const double ln = lambda.norm();
    const double before = t.last;
    t.last = ln > 0 ? residual / ln : residual;
    // A residual that at least doubles shows a loose QP's λ had passed for converged: exact QPs
    // from here. Not from the first update's residual: from a warm start a loose QP may stop at
    // once, so that residual measures only how little it moved (the refined pin-on-plate: one
    // MPGP iteration, 4.1e-3, then 7.4e-2 after the first real solve); and not a mere rise:
    // with exact QPs Aitken's updates are not monotone either (7.4e-2 → 8.2e-2 there).
    if (update > 2 && t.last > 2 * before) t.exact_qps = true;
    peak = std::max(peak, t.last);
    t.converged = t.last <= tol && rtol <= qp_tol;
    if (t.converged) break;
    if (t.cut_short && t.last > tol && t.last <= p.loop_forcing * peak) break;
    if (update == p.max_updates && p.max_updates > 1)
      throw NumericalError(
          fmt::format("the Tresca → Coulomb fixed point γ = λ_n (6.3) did not converge to {:.1e} "
                      "in {} updates: raise [solver] max_friction_updates (now {})",
                      tol, p.max_updates, p.max_updates),
          p.step, p.outer, residual);
  }
  return residual;
}

}  // namespace tc::physics
