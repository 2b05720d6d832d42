#pragma once
// The bodies of a run as the time loop holds them: per body its system (matrices, loads,
// supports), its field (factorised operators, right-hand sides, work vectors) and its state.
#include <memory>
#include <vector>

#include "tc/physics/body/body_field.hpp"
#include "tc/physics/body/body_system.hpp"

namespace tc::physics {

/// The bodies of the contact pairs within a step, each once: fields to work in, systems, states
/// at t^k. With one pair the slave is member 0 and the master member 1.
struct BodyGroup {
  std::vector<int> index;  // Problem::bodies index of each member
  std::vector<BodyField*> fields;
  std::vector<const BodySystem*> systems;
  std::vector<const BodyState*> states;

  [[nodiscard]] int size() const { return static_cast<int>(index.size()); }
  /// The member `v` of every field (of every state), in the group's order.
  [[nodiscard]] std::vector<core::Vector*> field(core::Vector BodyField::*v) const {
    std::vector<core::Vector*> out;
    for (auto* f : fields) out.push_back(&(f->*v));
    return out;
  }
  [[nodiscard]] std::vector<const core::Vector*> field_in(core::Vector BodyField::*v) const {
    std::vector<const core::Vector*> out;
    for (auto* f : fields) out.push_back(&(f->*v));
    return out;
  }
  [[nodiscard]] std::vector<const core::Vector*> state(core::Vector BodyState::*v) const {
    std::vector<const core::Vector*> out;
    for (const auto* st : states) out.push_back(&(st->*v));
    return out;
  }
};

/// Every body of the problem, indexed as Problem::bodies.
struct Bodies {
  std::vector<std::unique_ptr<BodySystem>> systems;
  std::vector<std::unique_ptr<BodyField>> fields;
  std::vector<BodyState> states;

  [[nodiscard]] int size() const { return static_cast<int>(systems.size()); }
  /// The bodies `members` (Problem::bodies indices) as a group, in that order.
  [[nodiscard]] BodyGroup group(const std::vector<int>& members) {
    BodyGroup g;
    for (const int b : members) {
      g.index.push_back(b);
      g.fields.push_back(fields[b].get());
      g.systems.push_back(systems[b].get());
      g.states.push_back(&states[b]);
    }
    return g;
  }
};

}  // namespace tc::physics
