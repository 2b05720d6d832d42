#pragma once
// The bodies of a run as the time loop holds them: per body its system (matrices, loads,
// supports), its field (factorised operators, right-hand sides, work vectors) and its state.
#include <memory>
#include <vector>

#include "tc/physics/body_field.hpp"
#include "tc/physics/body_system.hpp"

namespace tc::physics {

/// The two bodies of the contact pair within a step: fields to work in, systems, states at t^k.
struct BodyPair {
  BodyField& slave;
  BodyField& master;
  const BodySystem& slave_system;
  const BodySystem& master_system;
  const BodyState& slave_state;  // at t^k
  const BodyState& master_state;
};

/// Every body of the problem, indexed as Problem::bodies.
struct Bodies {
  std::vector<std::unique_ptr<BodySystem>> systems;
  std::vector<std::unique_ptr<BodyField>> fields;
  std::vector<BodyState> states;

  [[nodiscard]] int size() const { return static_cast<int>(systems.size()); }
  [[nodiscard]] BodyPair pair(int slave, int master) {
    return {*fields[slave],   *fields[master], *systems[slave],
            *systems[master], states[slave],   states[master]};
  }
};

}  // namespace tc::physics
