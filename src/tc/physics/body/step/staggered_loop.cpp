#include "tc/physics/body/step/staggered_loop.hpp"

#include <algorithm>

namespace tc::physics {

double SweepState::change() const {
  return std::max({primal.relative(), theta.relative(), residual.relative()});
}

bool ChangesWithin::after_sweep(const SweepState& s) const {
  return s.primal.within(tol_) && s.theta.within(tol_) && s.friction_met(tol_);
}

bool FinalHeat::theta_done(const SweepState& s) const {
  return !theta_iterates_ || s.theta.within(tol_);
}

bool FinalHeat::after_heat(const SweepState& s) const {
  // λ of the previous sweep's mechanical half: its fixed point met by its own criterion.
  return order_ == SweepOrder::heat_first && s.inner_converged && theta_done(s);
}

bool FinalHeat::after_sweep(const SweepState& s) const {
  return order_ == SweepOrder::mechanics_first && s.friction_met(tol_) && theta_done(s);
}

bool ContractionEstimate::after_sweep(const SweepState& s) const {
  return s.friction_met(tol_) && s.previous_primal > 0 &&
         fixed_point_reached(s.primal.relative(), s.theta.relative(), s.previous_primal, tol_);
}

// The heat–mechanics sweep λ → θ(λ) → λ(θ) of the nested loop contracts (measured on the ch. 7
// examples: by 1e-3 per sweep), so the distance to its fixed point is known before the next
// sweep: with ρ = ‖λ^p − λ^{p−1}‖/‖λ^{p−1} − λ^{p−2}‖, ‖λ* − λ^p‖ ≤ ρ/(1 − ρ)‖λ^p − λ^{p−1}‖
// (contraction mapping), and θ answers λ as in the last sweep, θ^{p+1} − θ^p ≈
// (‖θ^p − θ^{p−1}‖/‖λ^{p−1} − λ^{p−2}‖)(λ^p − λ^{p−1}). Stopping when both are within the
// tolerance saves the sweep that would only confirm it (3.1 → 2.4 sweeps per step on example
// 05). All arguments are relative to ‖λ‖ and ‖θ‖.
bool fixed_point_reached(double lambda_change, double theta_change, double previous_lambda_change,
                         double tol) {
  const double rho = lambda_change / previous_lambda_change;
  if (!(rho <= 0.5)) return false;  // no clear contraction: confirm by another sweep
  const double lambda_left = rho / (1 - rho) * lambda_change;
  const double theta_left = theta_change / previous_lambda_change * lambda_change / (1 - rho);
  return lambda_left <= tol && theta_left <= tol;
}

LoopResult StaggeredLoop::run(const StaggeredSweep& sweep) const {
  const auto any = [&](bool (StoppingRule::*ask)(const SweepState&) const, const SweepState& s) {
    return std::any_of(rules_.begin(), rules_.end(), [&](const auto& r) { return (*r.*ask)(s); });
  };
  SweepState s;
  for (s.iteration = 1; s.iteration <= max_; ++s.iteration) {
    sweep.begin(s);
    if (order_ == SweepOrder::heat_first) {
      sweep.heat(s);
      if (any(&StoppingRule::after_heat, s)) return {s.iteration, true, s.theta.relative()};
      sweep.mechanics(s);
    } else {
      sweep.mechanics(s);
      sweep.heat(s);
    }
    sweep.end(s);
    if (any(&StoppingRule::after_sweep, s)) return {s.iteration, true, s.change()};
    s.previous_primal = s.primal.relative();
  }
  return {max_, false, s.change()};
}

}  // namespace tc::physics
