#include "tc/physics/contact/contact_enforcement.hpp"

#include <fmt/format.h>

#include "tc/core/error.hpp"
#include "tc/physics/body/step/finite_checks.hpp"

namespace tc::physics {

void ContactEnforcement::save(Checkpoint& c) const {
  c.compliance.clear();
  dual_->save_compliance(c.compliance);
}

void ContactEnforcement::restore(const Checkpoint& c) {
  dual_->replay_compliance(c.compliance);
}

void NestedDualEnforcement::solve_qp(const BodyGroup& group, const TrescaQp& qp,
                                     core::Vector& lambda, ContactStatistics& stats) {
  // u stays u_free here (recover = false): finish_qps forms it, or only B u, once per θ.
  const auto r = dual().solve(group.field_in(&BodyField::u_prev), qp.targets, qp.bound, lambda,
                              group.field(&BodyField::u_new), false, qp.rtol);
  stats.qp_iterations += r.iterations;
  stats.operator_applications += r.operator_applications;
  ++stats.friction_iterations;
  if (!r.converged())
    throw NumericalError(
        fmt::format("the contact QP (6.9) did not converge: {}{}", r.message,
                    r.status == qp::QpStatus::max_iterations
                        ? fmt::format("; raise [solver] max_qp_iterations (now {})", r.iterations)
                        : std::string()),
        qp.step, qp.outer, r.projected_gradient);
}

void NestedDualEnforcement::finish_qps(const BodyGroup& group, const core::Vector& lambda,
                                       const TrescaIteration& t, std::vector<double>& iterate_slip,
                                       int step, int outer) {
  if (t.defer) {  // B u = B u_free − Fλ: the frictional heat's slip without forming u
    core::Vector bu;
    dual().constraint_values(group.field_in(&BodyField::u_prev), lambda, bu);
    iterate_slip = bu.to_std();
    for (size_t i = 0; i < iterate_slip.size(); ++i) iterate_slip[i] -= t.bu_old[i];
  } else {
    dual().recover(lambda, group.field(&BodyField::u_new));
    for (const auto* f : group.fields) require_finite(f->u_new, "u = u_free − A⁻¹Bᵀλ", step, outer);
  }
}

CombinedTfetiEnforcement::CombinedTfetiEnforcement(std::unique_ptr<DualContactSolver> dual,
                                                   const feti::Feti& slave,
                                                   const feti::Feti& master, int max_qp_iterations)
    : ContactEnforcement(std::move(dual)),
      slave_(slave),
      master_(master),
      max_qp_iterations_(max_qp_iterations) {}

void CombinedTfetiEnforcement::set_rows(std::vector<ContactRows> rows,
                                        std::vector<PairBodies> bodies) {
  if (rows.size() != 1) throw Error("the combined contact dual takes one contact pair");
  dual().set_rows(std::move(rows), std::move(bodies));
  const auto& r = dual().rows();  // the combined B and G on this step's contact rows
  feti_ = std::make_unique<feti::ContactFeti>(slave_, master_, r.slave, r.master, r.dim);
}

void CombinedTfetiEnforcement::solve_qp(const BodyGroup& group, const TrescaQp& qp,
                                        core::Vector& lambda, ContactStatistics& stats) {
  // The whole mechanical step at this Tresca bound: one TFETI QP over the gluing, Dirichlet
  // and contact multipliers (6.4), SMALBE warm-started from the last one's λ and μ; u comes
  // with it. Its tolerance is that of the nested QP on both ‖g^P‖ and ‖Gλ − e‖.
  feti::ContactFetiOptions o;
  o.smalbe.rtol = qp.rtol;
  o.smalbe.equality_rtol = qp.rtol;
  o.smalbe.max_inner_iterations = max_qp_iterations_;
  auto& slave = *group.fields[0];  // the one pair: slave, master
  auto& master = *group.fields[1];
  const auto r = feti_->solve(slave.rhs_u, master.rhs_u, qp.targets, qp.bound, slave.u_new,
                              master.u_new, lambda, o, &state_);
  stats.qp_iterations += r.inner_iterations;
  stats.operator_applications += r.operator_applications;
  outer_ += r.outer_iterations;
  gradient_tolerance_ = r.gradient_tolerance;
  ++stats.friction_iterations;
  if (!r.converged())
    throw NumericalError(
        fmt::format("the combined TFETI contact QP (6.4, SMALBE) did not converge: {}", r.message),
        qp.step, qp.outer, r.projected_gradient);
}

void CombinedTfetiEnforcement::finish_qps(const BodyGroup& group, const core::Vector&,
                                          const TrescaIteration&, std::vector<double>&, int step,
                                          int outer) {
  for (const auto* f : group.fields) require_finite(f->u_new, "displacement", step, outer);
}

void CombinedTfetiEnforcement::save(Checkpoint& c) const {
  ContactEnforcement::save(c);
  c.feti_body_lambda.assign(state_.body.data(), state_.body.data() + state_.body.size());
  c.feti_mu.assign(state_.mu.data(), state_.mu.data() + state_.mu.size());
  c.total_smalbe_outer = outer_;
}

void CombinedTfetiEnforcement::restore(const Checkpoint& c) {
  ContactEnforcement::restore(c);
  state_.body = Eigen::Map<const Eigen::VectorXd>(
      c.feti_body_lambda.data(), static_cast<Eigen::Index>(c.feti_body_lambda.size()));
  state_.mu = Eigen::Map<const Eigen::VectorXd>(c.feti_mu.data(),
                                                static_cast<Eigen::Index>(c.feti_mu.size()));
  outer_ = c.total_smalbe_outer;
}

}  // namespace tc::physics
