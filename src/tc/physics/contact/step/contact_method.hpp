#pragma once
// The one place where the settings choose how contact is enforced (nested dual or combined
// TFETI, [solver] contact_dual) and how the time scheme meets it (quasistatic, or [time]
// contact_scheme of a dynamic run).
#include <memory>
#include <vector>

#include "tc/core/timer.hpp"
#include "tc/model/problem.hpp"
#include "tc/physics/body/bodies.hpp"
#include "tc/physics/contact/contact_enforcement.hpp"
#include "tc/physics/contact/step/contact_time_scheme.hpp"

namespace tc::physics {

/// The bodies of the contact pairs, each once in the order they first appear in p.contacts
/// (with one pair: slave, master), and each pair's slave and master among them.
struct ContactGroup {
  ContactGroup() = default;
  explicit ContactGroup(const Problem& p);
  std::vector<int> members;  // Problem::bodies indices
  std::vector<PairBodies> pairs;
};

struct ContactMethod {
  std::unique_ptr<ContactEnforcement> enforcement;
  std::unique_ptr<ContactTimeScheme> scheme;
};

/// The enforcement and the contact time scheme of p.contacts' pairs (their bodies as in
/// ContactGroup). `settings`: the nested
/// dual's (its QP tolerance and iteration cap are p.solver's, and its explicit_limit when the
/// case sets explicit_dual_limit). Factorises what the scheme needs
/// (the stabilised scheme's M_u). Throws Error when contact_dual = "combined" cannot run.
[[nodiscard]] ContactMethod choose_contact_method(const Problem& p, Bodies& bodies,
                                                  DualContactSettings settings,
                                                  core::PhaseTimers& timers);

}  // namespace tc::physics
