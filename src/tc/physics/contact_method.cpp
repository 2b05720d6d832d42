#include "tc/physics/contact_method.hpp"

#include "tc/core/error.hpp"

namespace tc::physics {

ContactMethod choose_contact_method(const Problem& p, Bodies& bodies, DualContactSettings settings,
                                    core::PhaseTimers& timers) {
  const auto& c = p.contacts.at(0);
  const int sb = c.slave_body, mb = c.master_body;
  settings.qp.rtol = p.solver.qp_tolerance;
  settings.qp.max_iterations = p.solver.max_qp_iterations;
  if (p.solver.explicit_dual_limit) settings.explicit_limit = *p.solver.explicit_dual_limit;
  const auto mode = p.solver.contact_dual;
  const auto why = combined_contact_dual_unavailable(p);
  const bool combined =
      mode == ContactDual::combined || (mode == ContactDual::automatic && why.empty());
  const auto& mech_s = *bodies.fields[sb]->mech;
  const auto& mech_m = *bodies.fields[mb]->mech;
  if (combined) {
    if (!why.empty()) throw Error("contact_dual = \"combined\": " + why);
    if (!mech_s.feti() || !mech_m.feti())
      throw Error("contact_dual = \"combined\": a contact body's mechanics is not solved by FETI");
    settings.explicit_limit = 0;  // the rows, targets and bookkeeping only: F never formed
  }
  auto dual = std::make_unique<DualContactSolver>(mech_s, mech_m, bodies.systems[sb]->n_u(),
                                                  bodies.systems[mb]->n_u(), settings);
  ContactMethod m;
  if (combined)
    m.enforcement = std::make_unique<CombinedTfetiEnforcement>(
        std::move(dual), *mech_s.feti(), *mech_m.feti(), p.solver.max_qp_iterations);
  else
    m.enforcement = std::make_unique<NestedDualEnforcement>(std::move(dual));

  if (p.time.scheme == Scheme::quasistatic)
    m.scheme = std::make_unique<QuasistaticContact>();
  else if (p.time.contact_scheme == ContactScheme::plain)
    m.scheme = std::make_unique<PlainNewmarkContact>(p.time.step);
  else if (p.time.contact_scheme == ContactScheme::modified_mass)
    m.scheme = std::make_unique<ModifiedMassContact>();
  else
    m.scheme = std::make_unique<StabilisedNewmarkContact>(p, bodies, sb, mb, settings, timers);
  return m;
}

}  // namespace tc::physics
