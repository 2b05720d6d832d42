// `initial_state = "equilibrium"` (docs/choices.md, "Initial state"): a body 80 K above θ₀ on
// roller supports (x held on xmin, y on ymin, z on zmin), insulated and unloaded. Its static
// state is the free thermal expansion u_i = α(θ − θ₀)(x_i − min_i), linear and so exact in
// Hex8: started in equilibrium the dynamic run must hold it, at rest, for every step (nothing
// changes in time: θ stays uniform); released from u = 0 ("rest", the default) the same body
// rings with the strain energy of the expansion. Tolerances: the equilibrium is one Cholesky
// solve and the steps reproduce it to round-off of ‖u‖ ≈ 2e-4 m (1e-10 relative is far above
// it); the kinetic energy of an exact rest state is round-off too (1e-12 of the strain energy).
#include <gtest/gtest.h>

#include <cmath>

#include "support/problems.hpp"
#include "tc/physics/body/body_field.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

constexpr double kHot = 80.0;

physics::Problem hot_block(bool equilibrium) {
  auto p = box_problem(3, {0.2, 0.1, 0.1}, {4, 2, 2}, steel(), physics::Scheme::dynamic, 1e-3, 20);
  p.physics.thermoelastic_heating = true;
  p.bodies[0].initial_temperature = p.physics.reference_temperature + kHot;
  p.bodies[0].start_in_equilibrium = equilibrium;
  p.boundaries = {hold("xmin", {0}), hold("ymin", {1}), hold("zmin", {2})};
  return p;
}

struct Energies : physics::Observer {
  double max_kinetic = 0, max_strain = 0;
  void step(const physics::Simulation& sim) override {
    max_kinetic = std::max(max_kinetic, sim.kinetic_energy());
    max_strain = std::max(max_strain, sim.strain_energy());
  }
};

TEST(InitialState, EquilibriumStartsExpandedAndStaysAtRest) {
  const auto p = hot_block(true);
  physics::Simulation sim(p);
  const double alpha = p.bodies[0].material.thermal_expansion;
  auto check_expanded = [&](const char* when) {
    const auto u = sim.state(0).u.to_std();
    const auto& mesh = p.bodies[0].mesh;
    double worst = 0, scale = 0;
    for (int a = 0; a < mesh.n_nodes(); ++a)
      for (int k = 0; k < 3; ++k) {
        const double exact = alpha * kHot * mesh.point(a)[k];
        worst = std::max(worst, std::abs(u[3 * a + k] - exact));
        scale = std::max(scale, std::abs(exact));
      }
    EXPECT_LE(worst, 1e-10 * scale) << when;
  };
  check_expanded("t = 0");
  Energies e;
  const auto status = sim.run(e);
  ASSERT_TRUE(status.completed) << status.message;
  check_expanded("t = end");
  EXPECT_GT(e.max_strain, 0.0);
  EXPECT_LE(e.max_kinetic, 1e-12 * e.max_strain);
}

TEST(InitialState, RestRingsWithTheExpansionsEnergy) {
  physics::Simulation sim(hot_block(false));
  Energies e;
  const auto status = sim.run(e);
  ASSERT_TRUE(status.completed) << status.message;
  // The thermal shock: kinetic energy of the order of the expansion's strain energy.
  EXPECT_GT(e.max_kinetic, 1e-2 * e.max_strain);
}

// ü⁰ (2.1 at t = 0) is solved by Jacobi-preconditioned CG (physics::solve_initial_acceleration)
// rather than a factorisation of M_u; checked against that factorisation on a clamped box, with
// the consistent mass and with the modified mass of the contact schemes (massless on zmax,
// where ü⁰ = 0 is imposed like a support). CG stops at ‖r‖ ≤ 1e-12‖b‖, so the error is at
// most κ·1e-12 with κ the Jacobi-scaled condition number (≤ 27 for Hex8, Wathen 1987; the
// modified mass's cells at the boundary are bounded too): 1e-9 leaves a margin of 30.
void expect_cg_equals_factorised(physics::Problem p) {
  p.boundaries = {hold("xmin", {0, 1, 2})};
  const physics::BodySystem sys(p, 0);
  core::Vector r(sys.n_u()), a_cg(sys.n_u()), a_direct(sys.n_u());
  {
    auto v = r.view();
    for (PetscInt i = 0; i < sys.n_u(); ++i) v[i] = std::sin(0.7 * static_cast<double>(i)) * 1e3;
  }
  physics::solve_initial_acceleration(sys, r, a_cg);
  a_direct.zero();
  physics::body_solver(p, sys, sys.matrices().mass_u, physics::BodyOperator::mass)
      ->solve(r, a_direct);
  const double scale = a_direct.norm();
  ASSERT_GT(scale, 0.0);
  a_cg.axpy(-1.0, a_direct);
  EXPECT_LE(a_cg.norm(), 1e-9 * scale);
}

TEST(InitialState, AccelerationByCgEqualsTheFactorisedOne) {
  expect_cg_equals_factorised(
      box_problem(3, {0.2, 0.1, 0.1}, {6, 3, 3}, steel(), physics::Scheme::dynamic, 1e-3, 1));
}

TEST(InitialState, AccelerationByCgEqualsTheFactorisedOneWithTheModifiedMass) {
  auto p = box_problem(3, {0.2, 0.1, 0.1}, {6, 3, 3}, steel(), physics::Scheme::dynamic, 1e-3, 1);
  p.time.contact_scheme = physics::ContactScheme::modified_mass;
  p.contacts = {contact_pair(0, "zmax", 0, "zmin")};  // only its surfaces matter here
  const physics::BodySystem sys(p, 0);
  ASSERT_FALSE(sys.massless_dofs().empty());
  expect_cg_equals_factorised(std::move(p));
}

}  // namespace
}  // namespace tc::test
