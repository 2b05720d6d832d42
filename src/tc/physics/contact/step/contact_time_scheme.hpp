#pragma once
// How the time scheme meets contact ([time] contact_scheme, docs/choices.md): what a step does
// before its QPs (the stabilised predictor) and where the
// slip is measured from (5.4). One implementation per scheme; choose_contact_method
// (contact_method.hpp) picks it.
#include <memory>

#include "tc/core/timer.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/physics/body/bodies.hpp"
#include "tc/record/checkpoint.hpp"
#include "tc/record/ledger.hpp"

namespace tc::physics {

class ContactTimeScheme {
 public:
  virtual ~ContactTimeScheme() = default;
  /// Before the QPs of the step, with its rows set and λ^k moved onto them (`lambda`).
  virtual void prepare(const BodyGroup& /*group*/, DualContactSolver& /*dual*/,
                       const core::Vector& /*lambda*/, ContactStatistics& /*stats*/, int /*step*/) {
  }
  /// The displacement the slip is measured from, into each field's work_u: c_τ = B_τ of it.
  virtual void slip_reference(const BodyGroup& group) const = 0;
  /// The mean contact traction of the step per unit of λ (traction_per_multiplier).
  [[nodiscard]] virtual double traction_per_multiplier() const;
  /// The stabilised predictor's mass projection and its compliance (the checkpoint's
  /// stabiliser_compliance); nothing for the other schemes.
  virtual void save(Checkpoint& /*c*/) const {}
  virtual void restore(const Checkpoint& /*c*/) {}
};

/// Quasistatic: slip from u^k, B_τu − c_τ = τ B_τu̇^{k+1}.
class QuasistaticContact final : public ContactTimeScheme {
 public:
  void slip_reference(const BodyGroup& group) const override;
};

/// The thesis' Newmark (5.1–5.4): slip from u^k + τ/2 u̇^k, B_τu − c_τ = τ/2 B_τu̇^{k+1}.
class PlainNewmarkContact : public ContactTimeScheme {
 public:
  explicit PlainNewmarkContact(double tau) : tau_(tau) {}
  void slip_reference(const BodyGroup& group) const override;

 protected:
  double tau_;
};

/// Newmark with the modified mass of Hager, Hüeber & Wohlmuth: the contact nodes have no
/// inertia (massless_rates) and the slip is measured from u^k. Complementarity holds at
/// t^{k+1} (λ_n ≥ 0): a releasing node adds ½λ_n^k g^{k+1} = O(τ) to the energy, the price of
/// end-of-step forces that are physical (docs/choices.md, "No release floor").
class ModifiedMassContact final : public ContactTimeScheme {
 public:
  void slip_reference(const BodyGroup& group) const override;
};

/// The contact-stabilised Newmark of Deuflhard, Krause & Ertel: the predictor projected onto
/// the admissible set in the mass norm (a frictionless QP with F_M = Σ B_i M_i⁻¹ B_iᵀ), the
/// position update without the last step's contact force; λ is twice the mean traction.
class StabilisedNewmarkContact final : public PlainNewmarkContact {
 public:
  /// Factorises M_u of the contact bodies `members` (taking the one of the initial
  /// acceleration when kept).
  StabilisedNewmarkContact(const Problem& p, Bodies& bodies, const std::vector<int>& members,
                           const DualContactSettings& settings, core::PhaseTimers& timers);
  void prepare(const BodyGroup& group, DualContactSolver& dual, const core::Vector& lambda,
               ContactStatistics& stats, int step) override;
  [[nodiscard]] double traction_per_multiplier() const override;
  void save(Checkpoint& c) const override;
  void restore(const Checkpoint& c) override;

 private:
  core::PhaseTimers& timers_;
  std::unique_ptr<DualContactSolver> projection_;
};

}  // namespace tc::physics
