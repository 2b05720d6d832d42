#pragma once
// The staggered fixed point (6.3) of a time step, written once: sweeps of a heat half (6.1)
// and a mechanical half in a chosen order until one of its stopping rules holds. A body
// outside contact (BodySteps::couple) and the bodies of the contact pairs
// (ContactCoupling::couple) differ only in what their halves do (StaggeredSweep) and in the
// rules they stop by; the loop, its order and its count are here.
#include <functional>
#include <memory>
#include <vector>

namespace tc::physics {

/// ‖x^{p+1} − x^p‖ and ‖x^{p+1}‖ of one unknown over a sweep (or a residual and the norm it is
/// relative to).
struct Change {
  double difference = 0, norm = 0;
  /// ‖Δx‖/‖x‖ (‖Δx‖ when x = 0).
  [[nodiscard]] double relative() const { return norm > 0 ? difference / norm : difference; }
  /// ‖Δx‖ ≤ tol‖x‖.
  [[nodiscard]] bool within(double tol) const { return difference <= tol * norm; }
};

/// Which half of a sweep comes first.
enum class SweepOrder { heat_first, mechanics_first };

/// What the halves of a sweep leave for the stopping rules.
struct SweepState {
  int iteration = 0;  // 1, 2, … (the sweep being taken)
  Change theta;       // of the sweep's heat half (θ^{p+1} − θ^p)
  Change primal;      // u of a body, or λ of the contact bodies, over the sweep
  // The Tresca → Coulomb fixed point's ‖λ_n(γ) − γ‖ against ‖λ‖, and whether it met its own
  // criterion (the QP to qp_tolerance): zero and true without friction.
  Change residual;
  bool inner_converged = true;
  double previous_primal = -1;  // primal.relative() of the previous sweep (-1: none yet)

  /// The friction fixed point is met: its residual within tol and its own criterion.
  [[nodiscard]] bool friction_met(double tol) const {
    return residual.within(tol) && inner_converged;
  }
  /// The largest relative change of the sweep (the failure's message).
  [[nodiscard]] double change() const;
};

/// A rule the loop stops by. `after_heat` is asked right after the heat half when the heat
/// comes first (before the mechanical half of that sweep), `after_sweep` after every sweep.
class StoppingRule {
 public:
  virtual ~StoppingRule() = default;
  [[nodiscard]] virtual bool after_heat(const SweepState&) const { return false; }
  [[nodiscard]] virtual bool after_sweep(const SweepState&) const = 0;
};

/// One pass is the exact solution of the step: the coupling is one-way (only θ → u, or only
/// u → θ), the halves taken in the order of the dependence.
class OnePass final : public StoppingRule {
 public:
  [[nodiscard]] bool after_sweep(const SweepState&) const override { return true; }
};

/// ‖Δx‖ ≤ ε‖x‖ for the primal unknown and θ, and the friction fixed point met (6.3).
class ChangesWithin final : public StoppingRule {
 public:
  explicit ChangesWithin(double tol) : tol_(tol) {}
  [[nodiscard]] bool after_sweep(const SweepState& s) const override;

 private:
  double tol_;
};

/// The heat half just taken was the last one needed: λ is final once the friction fixed point
/// is met (no thermal expansion and 𝔉 independent of θ: u_free does not depend on θ), and θ no
/// longer iterates or is within ε (`theta_iterates`: lagged conductance or γ_C(θ)). With the
/// heat first it is asked after the heat half with the previous mechanical half's λ, with the
/// mechanics first after the sweep.
class FinalHeat final : public StoppingRule {
 public:
  FinalHeat(SweepOrder order, double tol, bool theta_iterates)
      : order_(order), tol_(tol), theta_iterates_(theta_iterates) {}
  [[nodiscard]] bool after_heat(const SweepState& s) const override;
  [[nodiscard]] bool after_sweep(const SweepState& s) const override;

 private:
  [[nodiscard]] bool theta_done(const SweepState& s) const;
  SweepOrder order_;
  double tol_;
  bool theta_iterates_;
};

/// The sweeps contract fast enough that what is left is within ε (the friction fixed point
/// nested in each sweep, met): fixed_point_reached.
class ContractionEstimate final : public StoppingRule {
 public:
  explicit ContractionEstimate(double tol) : tol_(tol) {}
  [[nodiscard]] bool after_sweep(const SweepState& s) const override;

 private:
  double tol_;
};

/// Whether the sweeps have contracted to within tol: ρ = ‖λ^p − λ^{p−1}‖/‖λ^{p−1} − λ^{p−2}‖ ≤
/// 1/2 and the estimated changes left, ρ/(1 − ρ)‖λ^p − λ^{p−1}‖ and the θ change carried by
/// them, within tol. All arguments relative to ‖λ‖ and ‖θ‖.
[[nodiscard]] bool fixed_point_reached(double lambda_change, double theta_change,
                                       double previous_lambda_change, double tol);

/// What one sweep's halves do: `begin` keeps the iterates the sweep starts from, `heat` and
/// `mechanics` take the halves (filling theta, and residual and inner_converged), `end`
/// measures the primal change.
struct StaggeredSweep {
  std::function<void(SweepState&)> begin, heat, mechanics, end;
};

/// How a loop ended: its sweeps (the last one taken) and whether a rule stopped it.
struct LoopResult {
  int iterations = 0;
  bool converged = false;
  double change = 0;  // the last sweep's largest relative change (when not converged)
};

class StaggeredLoop {
 public:
  StaggeredLoop(SweepOrder order, int max_iterations) : order_(order), max_(max_iterations) {}
  StaggeredLoop& stop_when(std::unique_ptr<StoppingRule> rule) {
    rules_.push_back(std::move(rule));
    return *this;
  }
  [[nodiscard]] SweepOrder order() const { return order_; }

  /// Sweeps until a rule holds or max_iterations sweeps are taken (then converged = false).
  [[nodiscard]] LoopResult run(const StaggeredSweep& sweep) const;

 private:
  SweepOrder order_;
  int max_;
  std::vector<std::unique_ptr<StoppingRule>> rules_;
};

}  // namespace tc::physics
