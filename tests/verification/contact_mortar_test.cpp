// Frictional contact of two elastic bodies end to end through Simulation with the mortar pair
// (contact::MortarPair) on NON-MATCHING meshes, each figure against a closed form.
//  - Patch test (quasistatic): a block pressed by a prescribed displacement −δ of its top onto a
//    block standing on its bottom; rollers on x = 0 (and y = 0) leave the state uniaxial, so
//    every contact multiplier is the pressure E' δ/(h_s + h_m) (E' = E in 3D, E/(1 − ν²) in plane
//    strain) and the displacement is linear in the height. Segment-based mortar integration
//    passes it to round-off (Farah, Popp & Wall 2015); swapping slave and master must not
//    change it.
//  - Sliding (3D, quasistatic): the top pressed down, then pulled along x. Past the stick limit
//    Σ‖λ_τ‖w = 𝔉 Σλ_n w to the fixed-point tolerance, the dissipation of a step is 𝔉 λ_n times
//    the slip, node by node; below it, nothing slips. The Tresca → Coulomb fixed point takes
//    at most 10 iterations.
#include <gtest/gtest.h>

#include <cmath>

#include "support/problems.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

constexpr double kDelta = 1e-4;  // the prescribed approach [m]
constexpr double kHs = 0.5, kHm = 1.0;

physics::BoundaryCondition move(int body, const std::string& where, int comp, core::TimeTable t) {
  physics::BoundaryCondition bc;
  bc.body = body;
  bc.where = where;
  bc.displacement[comp] = std::move(t);
  return bc;
}

physics::BoundaryCondition roller(int body, const std::string& where, int comp) {
  auto bc = hold(where, {comp});
  bc.body = body;
  return bc;
}

/// Two blocks, the upper one of height kHs on the lower one of height kHm, touching at z = kHm.
/// `upper_is_slave` chooses which surface carries the multipliers.
physics::Problem pressed_blocks(int dim, std::array<int, 3> upper_cells,
                                std::array<int, 3> lower_cells, bool upper_is_slave,
                                double friction = 0, int steps = 1) {
  physics::Problem p;
  p.dimension = dim;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = 1.0;
  p.time.end = steps;
  p.physics.thermal_expansion = false;
  p.physics.thermoelastic_heating = false;
  const int v = dim - 1;
  const auto pt = [&](double x, double y, double z) {
    return dim == 3 ? mesh::Point{x, y, z} : mesh::Point{x, z, 0};
  };
  const std::string bottom = dim == 3 ? "zmin" : "ymin", top = dim == 3 ? "zmax" : "ymax";
  for (int b = 0; b < 2; ++b) {
    physics::Body body;
    const bool upper = b == 0;
    body.name = upper ? "upper" : "lower";
    body.material = steel();
    body.mesh = upper ? mesh::make_box(dim, pt(0, 0, kHm), pt(1, 1, kHm + kHs), upper_cells)
                      : mesh::make_box(dim, pt(0, 0, 0), pt(1, 1, kHm), lower_cells);
    body.initial_temperature = p.physics.reference_temperature;
    p.bodies.push_back(std::move(body));
  }
  p.boundaries.push_back(move(0, top, v, core::TimeTable(-kDelta)));
  p.boundaries.push_back(roller(1, bottom, v));
  for (int b = 0; b < 2; ++b) {
    if (friction == 0 || b == 1) p.boundaries.push_back(roller(b, "xmin", 0));
    if (dim == 3) p.boundaries.push_back(roller(b, "ymin", 1));
  }
  auto c = contact_pair(upper_is_slave ? 0 : 1, upper_is_slave ? bottom : top,
                        upper_is_slave ? 1 : 0, upper_is_slave ? top : bottom, friction);
  p.contacts = {c};
  p.solver.qp_tolerance = 1e-12;
  p.solver.coupling_tolerance = 1e-10;
  return p;
}

struct NullObserver : physics::Observer {};

class MortarPatch : public ::testing::TestWithParam<std::tuple<int, bool>> {};

TEST_P(MortarPatch, NonMatchingMeshesCarryTheUniaxialPressure) {
  const auto [dim, upper_is_slave] = GetParam();
  // 3D: 3×3 faces against 5×7 (Tribol's layout); 2D: 5 against 7 segments.
  const auto p = dim == 3 ? pressed_blocks(3, {3, 3, 2}, {5, 7, 3}, upper_is_slave)
                          : pressed_blocks(2, {5, 2, 1}, {7, 3, 1}, upper_is_slave);
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  NullObserver none;
  const auto status = sim.run(none);
  ASSERT_TRUE(status.completed) << status.message;

  const auto mat = steel();
  const double modulus = dim == 3 ? mat.young_modulus
                                  : mat.young_modulus / (1 - mat.poisson_ratio * mat.poisson_ratio);
  const double pressure = modulus * kDelta / (kHs + kHm);
  const auto lambda = sim.contact_multipliers();
  const auto& rows = sim.dual_solver()->rows();
  ASSERT_GT(rows.n_nodes(), 0);
  // 1e-8 relative: the QP stops at ‖g^P‖ ≤ 1e-12‖d‖; the conditioning of F (κ ~ 1e2 here)
  // and the factorisations' round-off (~1e-13) leave the multipliers far inside 1e-8.
  for (PetscInt k = 0; k < rows.n_nodes(); ++k) {
    EXPECT_NEAR(lambda[dim * k], pressure, 1e-8 * pressure) << "contact node " << k;
    for (int l = 1; l < dim; ++l) EXPECT_NEAR(lambda[dim * k + l], 0.0, 1e-8 * pressure);
  }
  // The force balance: Σ w_k λ_k = pressure × area, the area being 1 (1 m in 2D).
  EXPECT_NEAR(sim.history("contact_normal_force"), pressure, 1e-8 * pressure);
  // The displacement is linear in the height in both blocks: the strain −δ/(h_s + h_m).
  const int v = dim - 1;
  for (int b = 0; b < 2; ++b) {
    const auto u = sim.state(b).u.to_std();
    const auto& m = p.bodies[b].mesh;
    for (int a = 0; a < m.n_nodes(); ++a) {
      const double z = m.point(a)[v];
      const double expected = -kDelta * z / (kHs + kHm);
      EXPECT_NEAR(u[dim * a + v], expected, 1e-8 * kDelta) << "body " << b << " node " << a;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(SlaveAboveOrBelow, MortarPatch,
                         ::testing::Combine(::testing::Values(2, 3), ::testing::Bool()),
                         [](const auto& info) {
                           return std::to_string(std::get<0>(info.param)) + "d_" +
                                  (std::get<1>(info.param) ? "upper_slave" : "lower_slave");
                         });

/// Records, per step, the contact history and Σ_k 𝔉 λ_n,k ‖(B_τΔu)_k‖ from the multipliers.
struct SlidingRecorder : physics::Observer {
  double friction = 0;
  std::vector<double> normal, tangential, dissipation, coulomb_work, slip;
  std::vector<int> active, slipping;
  int max_coupling = 0;
  void step(const physics::Simulation& sim) override {
    if (sim.step() == 0) return;
    max_coupling = std::max(max_coupling, static_cast<int>(sim.history("coupling_iterations")));
    normal.push_back(sim.history("contact_normal_force"));
    tangential.push_back(sim.history("contact_tangential_force_sum"));  // Σ_k w_k‖λ_τ,k‖
    dissipation.push_back(sim.history("frictional_dissipation"));
    active.push_back(static_cast<int>(sim.history("active_nodes")));
    slipping.push_back(static_cast<int>(sim.history("slip_nodes")));
    const auto lambda = sim.contact_multipliers();
    const auto& inc = sim.contact_slip();
    const int dim = sim.dual_solver()->rows().dim;
    double work = 0, total_slip = 0;
    for (size_t k = 0; k < lambda.size() / dim; ++k) {
      const double s = std::hypot(inc[dim * k + 1], dim == 3 ? inc[dim * k + 2] : 0.0);
      work += friction * std::max(lambda[dim * k], 0.0) * s;
      total_slip += s;
    }
    coulomb_work.push_back(work);
    slip.push_back(total_slip);
  }
};

TEST(MortarSliding3d, CoulombPastTheStickLimitNoSlipBelowIt) {
  // 3×3 faces on 5×7, 𝔉 = 0.3; step 1 presses by δ, then the top moves along x by `shift` per
  // step. The stick limit of the top's motion is about 𝔉 times the normal compliance (a few
  // δ here): 1e-6 m per step stays far below it; 1e-4 m per step slides after the first step.
  const double friction = 0.3;
  for (const double shift : {1e-6, 1e-4}) {
    auto p = pressed_blocks(3, {3, 3, 2}, {5, 7, 3}, true, friction, 4);
    p.boundaries[0].displacement[2] = core::TimeTable({0, 1}, {0, -kDelta});
    physics::BoundaryCondition pull;
    pull.body = 0;
    pull.where = "zmax";
    pull.displacement[0] = core::TimeTable({0, 1, 4}, {0, 0, 3 * shift});
    p.boundaries.push_back(pull);
    physics::Simulation sim(p);
    sim.enable_mortar_contact();
    SlidingRecorder rec;
    rec.friction = friction;
    const auto status = sim.run(rec);
    ASSERT_TRUE(status.completed) << status.message;
    const size_t last = rec.normal.size() - 1;
    EXPECT_GT(rec.normal[last], 0);
    EXPECT_GT(rec.active[last], 0);
    EXPECT_LE(rec.max_coupling, 10);  // Tresca → Coulomb within the 10 iterations
    if (shift > 1e-5) {
      // Gross sliding: every active node on its Coulomb disc, so Σw‖λ_τ‖ = 𝔉Σwλ_n. 1e-6: the
      // fixed point stops at a relative change of 1e-10 of λ and the QP at 1e-12.
      EXPECT_EQ(rec.slipping[last], rec.active[last]);
      EXPECT_NEAR(rec.tangential[last] / rec.normal[last], friction, 1e-6 * friction);
      // The dissipation of a sliding step is 𝔉 λ_n times the slip, node by node: λ_τ is
      // opposite to the slip increment (to the QP tolerance, hence 1e-8 relative).
      for (size_t i = 1; i < rec.dissipation.size(); ++i) {
        const double step_work = std::abs(rec.dissipation[i] - rec.dissipation[i - 1]);
        EXPECT_NEAR(step_work, rec.coulomb_work[i], 1e-8 * rec.coulomb_work[i]) << "step " << i;
        EXPECT_GT(rec.coulomb_work[i], 0);
      }
      std::printf("sliding: F_t/F_n = %.9f (𝔉 = %.1f), dissipation %.6e J, %d/%d nodes slip\n",
                  rec.tangential[last] / rec.normal[last], friction, rec.dissipation[last],
                  rec.slipping[last], rec.active[last]);
    } else {
      // Stick: nothing slips; the slip increments are round-off of the shift (≤ 1e-9 of it).
      EXPECT_EQ(rec.slipping[last], 0);
      EXPECT_LT(rec.tangential[last], friction * rec.normal[last]);
      for (size_t i = 1; i < rec.slip.size(); ++i) EXPECT_LT(rec.slip[i], 1e-9 * shift) << i;
    }
  }
}

}  // namespace
}  // namespace tc::test
