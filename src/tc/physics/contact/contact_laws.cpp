#include "tc/physics/contact/contact_laws.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "tc/core/error.hpp"

namespace tc::physics {

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

std::string where(const PairLaws& p, size_t k) {
  const std::string node =
      k < p.nodes.size() ? fmt::format("slave node {}", p.nodes[k]) : fmt::format("node {}", k);
  return p.name.empty() ? node : fmt::format("{} of contact pair '{}'", node, p.name);
}

}  // namespace

void LawViolation::offer(double v, double b, int at_step, int at_node, const std::string& at_pair) {
  const double r = b > 0 ? v / b : (v > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  if (node >= 0 && !(r > ratio)) return;  // the first offer names the law's place
  value = v;
  bound = b;
  ratio = r;
  step = at_step;
  node = at_node;
  pair = at_pair;
}

void ContactLaws::check(const PairLaws& p, double unit, double coupling_tolerance,
                        double lambda_norm, double qp_tolerance, int step) {
  const int dim = p.dim;
  const size_t n = p.weights.size();
  for (size_t k = 0; k < n; ++k) {
    if (!p.held.empty() && p.held[k]) continue;  // no multiplier of its own (crosspoint)
    const size_t r = static_cast<size_t>(dim) * k;
    const int node = k < p.nodes.size() ? p.nodes[k] : static_cast<int>(k);
    const double w = p.weights[k] > 0 ? p.weights[k] : 1.0;
    // Non-penetration: the gradient of the QP is c − B u, so a penetration is part of its
    // projected gradient, ≤ ε_QP/σ_n (docs/choices.md); 2× and a round-off term for u formed by
    // solves rather than by the QP's F.
    const double g = p.targets[r] - p.constraint_values[r];
    const double gap_bound =
        2 * p.gap_tolerance[k] +
        1e3 * eps * (std::abs(p.targets[r]) + std::abs(p.constraint_values[r]));
    const double gap_length_bound = gap_bound / w + p.solve_error;
    gap.offer(-g / w, gap_length_bound, step, node, p.name);
    if (-g / w > gap_length_bound)
      throw NumericalError(
          fmt::format("the contact penetrates at {} after the step: a weighted gap of {:.3e} m "
                      "below 0, beyond the {:.3e} m that the contact QP (6.9) and the bodies' "
                      "solves guarantee: lower [solver] qp_tolerance (now {:g}){}",
                      where(p, k), -g / w, gap_length_bound, qp_tolerance,
                      p.solve_error > 0
                          ? fmt::format(" or [solver] feti_tolerance (now {:g})", p.feti_tolerance)
                          : std::string()),
          step, 0, -g / w);
    // The friction cone: ‖λ_τ‖ ≤ 𝔉γ exactly (the QP's projection), γ within the fixed point's
    // tolerance of max(λ_n, 0).
    double lt2 = 0;
    for (int l = 1; l < dim; ++l) lt2 += p.lambda[r + l] * p.lambda[r + l];
    const double lt = std::sqrt(lt2);
    const double f = k < p.friction.size() ? p.friction[k] : 0.0;
    const double qb = k < p.qp_bound.size() ? p.qp_bound[k] : 0.0;
    const double c = lt - f * std::max(p.lambda[r], 0.0);
    // Never the user's looser tolerance: with one, the nodes outside their cone were scaled
    // onto it before (ContactCoupling::scale_into_cones), so that no row has T/N above 𝔉.
    const double cone_bound =
        f * std::min(coupling_tolerance, cone_tolerance) * lambda_norm + 16 * eps * (qb + lt);
    cone.offer(unit * c, unit * cone_bound, step, node, p.name);
    if (c > cone_bound)
      throw NumericalError(
          fmt::format("the friction cone ‖λ_τ‖ ≤ 𝔉λ_n is violated at {} after the step: "
                      "‖λ_τ‖ − 𝔉λ_n = {:.3e} Pa (‖λ_τ‖ = {:.3e} Pa, 𝔉 = {:g}, λ_n = {:.3e} Pa), "
                      "beyond the {:.3e} Pa that the Tresca → Coulomb fixed point (6.3) "
                      "guarantees: lower [solver] coupling_tolerance (now {:g}) or "
                      "[solver] qp_tolerance (now {:g})",
                      where(p, k), unit * c, unit * lt, f, unit * p.lambda[r], unit * cone_bound,
                      coupling_tolerance, qp_tolerance),
          step, 0, unit * c);
  }
}

void ContactLaws::merge(const ContactLaws& sub, int step) {
  for (auto [to, from] : {std::pair{&gap, &sub.gap}, {&cone, &sub.cone}})
    if (from->node >= 0 && (to->node < 0 || from->ratio > to->ratio)) {
      *to = *from;
      to->step = step;
    }
}

}  // namespace tc::physics
