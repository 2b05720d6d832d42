#include "tc/physics/contact/step/contact_loop.hpp"

#include <memory>

namespace tc::physics {

StaggeredLoop ContactLoopPolicy::loop(const SolverSettings& s) const {
  const double tol = s.coupling_tolerance;
  StaggeredLoop l(order, s.max_coupling_iterations);
  l.stop_when(std::make_unique<ChangesWithin>(tol));
  if (lambda_final) l.stop_when(std::make_unique<FinalHeat>(order, tol, theta_iterates));
  if (friction == FrictionPlacement::nested)
    l.stop_when(std::make_unique<ContractionEstimate>(tol));
  return l;
}

ContactLoopPolicy choose_contact_loop(const SolverSettings& s, const ContactLoopPhysics& p) {
  ContactLoopPolicy c;
  c.order = heat_before_mechanics(s.coupling_order, p.heating) ? SweepOrder::heat_first
                                                               : SweepOrder::mechanics_first;
  c.friction = s.friction_loop == FrictionLoop::nested ? FrictionPlacement::nested
                                                       : FrictionPlacement::staggered;
  // Aitken only where γ matters: without friction the QP is taken once (coulomb_fixed_point).
  c.relaxation = s.friction.acceleration && p.frictional ? FrictionRelaxation::aitken
                                                         : FrictionRelaxation::plain;
  // u = u_free − A⁻¹Bᵀλ costs a solve per body; inside the fixed point only B u is needed
  // unless the thermoelastic term wants u̇ of the whole body. Combined, u comes with every QP.
  c.feedback = p.qp_gives_displacements ? DisplacementFeedback::from_qp
               : !p.heating             ? DisplacementFeedback::deferred
                                        : DisplacementFeedback::per_iterate;
  const bool one_way = !p.expansion;  // u_free does not depend on θ
  c.cut_short = c.friction == FrictionPlacement::nested && !one_way;
  c.lambda_final = one_way && !p.friction_varies;
  c.theta_iterates = p.theta_iterates;
  return c;
}

}  // namespace tc::physics
