#include "tc/physics/contact/step/contact_method.hpp"

#include <algorithm>

#include "tc/core/error.hpp"

namespace tc::physics {

ContactGroup::ContactGroup(const Problem& p) {
  const auto position = [&](int body) {
    const auto it = std::find(members.begin(), members.end(), body);
    if (it != members.end()) return static_cast<int>(it - members.begin());
    members.push_back(body);
    return static_cast<int>(members.size()) - 1;
  };
  for (const auto& c : p.contacts) {
    const int s = position(c.slave_body);
    pairs.push_back({s, position(c.master_body)});
  }
}

ContactMethod choose_contact_method(const Problem& p, Bodies& bodies, DualContactSettings settings,
                                    core::PhaseTimers& timers) {
  const ContactGroup group(p);
  settings.qp.rtol = p.solver.qp_tolerance;
  settings.qp.max_iterations = p.solver.max_qp_iterations;
  if (p.solver.explicit_dual_limit) settings.explicit_limit = *p.solver.explicit_dual_limit;
  const auto mode = p.solver.contact_dual;
  const auto why = combined_contact_dual_unavailable(p);
  const bool combined =
      mode == ContactDual::combined || (mode == ContactDual::automatic && why.empty());
  std::vector<const ConstrainedSolver*> mech;
  std::vector<PetscInt> n_u;
  for (const int b : group.members) {
    mech.push_back(bodies.fields[b]->mech.get());
    n_u.push_back(bodies.systems[b]->n_u());
  }
  if (combined) {
    if (!why.empty()) throw Error("contact_dual = \"combined\": " + why);
    if (!mech[0]->feti() || !mech[1]->feti())
      throw Error("contact_dual = \"combined\": a contact body's mechanics is not solved by FETI");
    settings.explicit_limit = 0;  // the rows, targets and bookkeeping only: F never formed
  }
  const auto* feti_s = mech[0]->feti();  // the one pair's, when combined
  const auto* feti_m = mech[1]->feti();
  auto dual = std::make_unique<DualContactSolver>(std::move(mech), std::move(n_u), settings);
  ContactMethod m;
  if (combined)
    m.enforcement = std::make_unique<CombinedTfetiEnforcement>(std::move(dual), *feti_s, *feti_m,
                                                               p.solver.max_qp_iterations);
  else
    m.enforcement = std::make_unique<NestedDualEnforcement>(std::move(dual));

  if (p.time.scheme == Scheme::quasistatic)
    m.scheme = std::make_unique<QuasistaticContact>();
  else if (p.time.contact_scheme == ContactScheme::plain)
    m.scheme = std::make_unique<PlainNewmarkContact>(p.time.step);
  else if (p.time.contact_scheme == ContactScheme::modified_mass)
    m.scheme = std::make_unique<ModifiedMassContact>();
  else
    m.scheme =
        std::make_unique<StabilisedNewmarkContact>(p, bodies, group.members, settings, timers);
  return m;
}

}  // namespace tc::physics
