#pragma once
// How the mechanical step enforces contact (6.4, 6.9): the QP at one Tresca bound, solved on top
// of each body's solver (NestedDualEnforcement: DualContactSolver, F = Σ B_i A_i⁻¹ B_iᵀ) or as
// one TFETI QP over the gluing, Dirichlet and contact multipliers of both bodies
// (CombinedTfetiEnforcement: feti::ContactFeti by SMALBE). Which one runs is chosen by
// choose_contact_method (contact_method.hpp) from [solver] contact_dual; the fixed point around
// the QPs (ContactCoupling, coulomb_fixed_point) is the same for both.
#include <memory>
#include <span>
#include <vector>

#include "tc/dual/dual_contact.hpp"
#include "tc/feti/contact_feti.hpp"
#include "tc/physics/body/bodies.hpp"
#include "tc/physics/contact/friction_fixed_point.hpp"
#include "tc/record/checkpoint.hpp"
#include "tc/record/ledger.hpp"

namespace tc::physics {

/// The contact QP at one Tresca bound within the fixed point of a step.
struct TrescaQp {
  std::span<const double> targets;  // c of (5.4)
  std::span<const double> bound;    // 𝔉γ_k per contact node
  double rtol = 0;                  // the QP's relative tolerance (coulomb_fixed_point)
  int step = 0, outer = 0;          // for the messages
};

class ContactEnforcement {
 public:
  /// `dual`: the step's rows, targets and warm-start bookkeeping (and F, when nested).
  explicit ContactEnforcement(std::unique_ptr<DualContactSolver> dual) : dual_(std::move(dual)) {}
  virtual ~ContactEnforcement() = default;
  ContactEnforcement(const ContactEnforcement&) = delete;
  ContactEnforcement& operator=(const ContactEnforcement&) = delete;

  [[nodiscard]] DualContactSolver& dual() { return *dual_; }
  [[nodiscard]] const DualContactSolver& dual() const { return *dual_; }
  /// "nested" or "combined" (summary.json).
  [[nodiscard]] virtual const char* name() const = 0;

  /// The contact rows of the step (from the mortar pairs at t^k, with each pair's bodies); the
  /// operators they define.
  virtual void set_rows(std::vector<ContactRows> rows, std::vector<PairBodies> bodies) {
    dual_->set_rows(std::move(rows), std::move(bodies));
  }
  /// True when each QP returns u as well: the bodies then need their loads (mech_load) and no
  /// free solve, and u is never deferred.
  [[nodiscard]] virtual bool qp_gives_displacements() const = 0;
  /// The QP at qp.bound into λ (warm-started from λ on entry); its iterations into `stats`.
  /// Nested: from u_free in each field's u_prev; combined: from the loads in rhs_u, and u into
  /// u_new. Throws NumericalError when it does not converge.
  virtual void solve_qp(const BodyGroup& group, const TrescaQp& qp, core::Vector& lambda,
                        ContactStatistics& stats) = 0;
  /// After the QPs at one θ: u_new = u_free − A⁻¹Bᵀλ, or (t.defer) only B(u − u^k) into
  /// `iterate_slip`, or nothing more (the QP gave u).
  virtual void finish_qps(const BodyGroup& group, const core::Vector& lambda,
                          const TrescaIteration& t, std::vector<double>& iterate_slip, int step,
                          int outer) = 0;

  /// SMALBE's outer iterations so far (combined; 0 otherwise).
  [[nodiscard]] virtual long outer_iterations() const { return 0; }
  /// The bound on contact node k's penetration (weighted gap below 0) that the last QP's
  /// stopping test guarantees (ContactLaws): its tolerance on the gradient c − B u there.
  [[nodiscard]] virtual double gap_tolerance(PetscInt k) const {
    return dual_->normal_gradient_bound(k);
  }
  /// This enforcement's part of the restart record (the dual's compliance).
  virtual void save(Checkpoint& c) const;
  virtual void restore(const Checkpoint& c);

 private:
  std::unique_ptr<DualContactSolver> dual_;
};

/// The contact QP (6.9) in the contact multipliers on top of each body's solver.
class NestedDualEnforcement final : public ContactEnforcement {
 public:
  using ContactEnforcement::ContactEnforcement;
  [[nodiscard]] const char* name() const override { return "nested"; }
  [[nodiscard]] bool qp_gives_displacements() const override { return false; }
  void solve_qp(const BodyGroup& group, const TrescaQp& qp, core::Vector& lambda,
                ContactStatistics& stats) override;
  void finish_qps(const BodyGroup& group, const core::Vector& lambda, const TrescaIteration& t,
                  std::vector<double>& iterate_slip, int step, int outer) override;
};

/// One TFETI QP per Tresca bound over the gluing, Dirichlet and contact multipliers of both
/// decomposed bodies of the one contact pair (6.4), rebuilt on each step's rows; `dual()` keeps the
/// rows and targets only (F never formed: explicit_limit 0).
class CombinedTfetiEnforcement final : public ContactEnforcement {
 public:
  /// `slave`, `master`: the contact bodies' mechanical solvers, both by FETI.
  CombinedTfetiEnforcement(std::unique_ptr<DualContactSolver> dual, const feti::Feti& slave,
                           const feti::Feti& master, int max_qp_iterations);
  [[nodiscard]] const char* name() const override { return "combined"; }
  void set_rows(std::vector<ContactRows> rows, std::vector<PairBodies> bodies) override;
  [[nodiscard]] bool qp_gives_displacements() const override { return true; }
  void solve_qp(const BodyGroup& group, const TrescaQp& qp, core::Vector& lambda,
                ContactStatistics& stats) override;
  void finish_qps(const BodyGroup& group, const core::Vector& lambda, const TrescaIteration& t,
                  std::vector<double>& iterate_slip, int step, int outer) override;
  [[nodiscard]] long outer_iterations() const override { return outer_; }
  /// SMALBE's gradient tolerance (on the whole dual, unscaled) bounds every component.
  [[nodiscard]] double gap_tolerance(PetscInt) const override { return gradient_tolerance_; }
  void save(Checkpoint& c) const override;
  void restore(const Checkpoint& c) override;

 private:
  const feti::Feti& slave_;
  const feti::Feti& master_;
  int max_qp_iterations_;
  std::unique_ptr<feti::ContactFeti> feti_;  // on the rows of the step
  feti::ContactFetiState state_;             // SMALBE's warm start from the last solve
  long outer_ = 0;
  double gradient_tolerance_ = 0;  // of the last solve
};

}  // namespace tc::physics
