#pragma once
// Geometric checks of a read case that need more than one mesh or PETSc (the case reader does
// without both): coincident nodes inside a body, and the contact pair in the initial
// configuration, pair by pair: surfaces that overlap (an error), or that do not face each other
// (a warning).
#include <cstddef>
#include <string>
#include <vector>

#include "tc/model/problem.hpp"

namespace tc::io {

/// The deepest point of the slave contact surface inside the master in the configuration of
/// t = 0, measured by the mortar pair (gap g_k / ∫ψ_k along the slave node's normal, < 0 when
/// inside), and the tolerance below which such a depth is taken as touching.
struct InitialContact {
  int contact_nodes = 0;  // slave nodes facing the master within the search radius
  int deepest_node = -1;  // slave mesh node of the smallest gap (−1 without contact nodes)
  double smallest_gap = 0;
  double tolerance = 0;  // 1e-6 × the largest facet of the two surfaces
};

/// Contact pair p.contacts[index] at t = 0 (needs PETSc: the mortar rows are PETSc
/// matrices).
[[nodiscard]] InitialContact initial_contact(const physics::Problem& p, size_t index = 0);

/// Throws MeshError (exit code 2) naming the case file (and the pair, when there are several)
/// when the surfaces of a contact pair overlap at t = 0 deeper than the tolerance; returns the
/// warnings: coincident nodes in a body, contact surfaces that do not face each other at t = 0.
/// Needs PETSc when the case has contact.
[[nodiscard]] std::vector<std::string> check_geometry(const physics::Problem& p);

}  // namespace tc::io
