// The dual contact solve (6.9) on a problem with a closed form, independent of the mortar
// layer: two blocks with matching meshes, node-to-node rows weighted by the nodal areas.
// The slave (on top) is pressed down by a prescribed displacement −δ of its top face; both
// blocks stand on rollers (x = 0: u_x = 0, y = 0: u_y = 0), the master on its bottom face.
// Frictionless and quasistatic, the state is uniaxial: σ_zz = −E δ/(h_s + h_m) in both
// blocks, so every contact multiplier (a pressure) is E δ/(h_s + h_m).
#include <gtest/gtest.h>

#include <map>

#include "support/contact_rows.hpp"
#include "support/problems.hpp"
#include "support/roller_blocks.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/physics/dual_contact.hpp"

namespace tc::test {
namespace {

using physics::ConstrainedSolver;

physics::ContactRows node_to_node(int, const Block& slave, const Block& master) {
  return node_to_node_rows(slave.mesh, master.mesh);
}

/// c of (5.4) from the reference configuration (u^k = 0, at rest).
std::vector<double> reference_targets(const physics::DualContactSolver& solver,
                                      const core::Vector& us, const core::Vector& um) {
  const core::Vector zero_s(us.size()), zero_m(um.size());
  return solver.targets(zero_s, zero_m, zero_s, zero_m);
}

struct Result {
  std::vector<double> lambda;
  qp::QpResult qp;
};

Result solve(int dim, PetscInt explicit_limit) {
  const double hs = 0.5, hm = 1.0, delta = 1e-4;
  const auto up = [&](double z) { return dim == 3 ? mesh::Point{1, 1, z} : mesh::Point{1, z, 0}; };
  const auto down = [&](double z) {
    return dim == 3 ? mesh::Point{0, 0, z} : mesh::Point{0, z, 0};
  };
  const std::string bottom = dim == 3 ? "zmin" : "ymin", top = dim == 3 ? "zmax" : "ymax";
  auto slave = make_block(dim, down(hm), up(hm + hs), {4, dim == 3 ? 4 : 3, 3}, top, -delta, "");
  auto master = make_block(dim, down(0), up(hm), {4, dim == 3 ? 4 : 5, 5}, "", 0.0, bottom);
  auto rows = node_to_node(dim, slave, master);

  physics::DualContactSettings settings;
  settings.qp.rtol = 1e-12;
  settings.explicit_limit = explicit_limit;
  physics::DualContactSolver solver(*slave.solver, *master.solver, slave.u_prescribed.size(),
                                    master.u_prescribed.size(), settings);
  solver.set_rows(std::move(rows));
  const auto us = free_solution(slave), um = free_solution(master);
  const auto c = reference_targets(solver, us, um);
  const std::vector<double> frictionless(static_cast<size_t>(solver.rows().n_nodes()), 0.0);
  core::Vector lambda(solver.rows().n_rows()), u_s(us.size()), u_m(um.size());
  Result r;
  r.qp = solver.solve(us, um, c, frictionless, lambda, u_s, u_m);
  EXPECT_EQ(solver.kind(), explicit_limit > 0 ? physics::DualOperator::explicit_schur
                                              : physics::DualOperator::matrix_free);
  r.lambda = lambda.to_std();
  return r;
}

class ContactPatch : public ::testing::TestWithParam<std::tuple<int, PetscInt>> {};

TEST_P(ContactPatch, MatchingMeshesCarryTheUniaxialPressure) {
  const auto [dim, limit] = GetParam();
  const auto r = solve(dim, limit);
  ASSERT_TRUE(r.qp.converged()) << r.qp.message;
  const auto mat = steel();
  // Uniaxial stress: rollers leave the lateral strains free, so σ = E ε (3D); plane strain
  // adds ε_zz = 0, so σ = E/(1 − ν²) ε in 2D.
  const double modulus = dim == 3 ? mat.young_modulus
                                  : mat.young_modulus / (1 - mat.poisson_ratio * mat.poisson_ratio);
  const double pressure = modulus * 1e-4 / 1.5;
  const int d = dim;
  for (size_t k = 0; k < r.lambda.size() / d; ++k) {
    // Linear elements reproduce the uniform state exactly; the QP stops at ‖g^P‖ ≤ 1e-12‖d‖.
    EXPECT_NEAR(r.lambda[d * k], pressure, 1e-8 * pressure) << "node " << k;
    for (int l = 1; l < d; ++l) EXPECT_EQ(r.lambda[d * k + l], 0.0);  // frictionless
  }
}

INSTANTIATE_TEST_SUITE_P(Dual, ContactPatch,
                         ::testing::Combine(::testing::Values(2, 3),
                                            ::testing::Values(PetscInt{0}, PetscInt{1500})));

// ------------------------------------------------------------------- Coulomb friction, 3D

/// The slave's top face is moved by (s, 0, −δ) (fully prescribed), the master's bottom is
/// clamped; friction 𝔉 with the Tresca bound updated to γ = λ_n until λ stops changing
/// (the Tresca→Coulomb fixed point of 6.3). Returns λ, the slip B_τu − c_τ and the counts.
struct Friction {
  std::vector<double> lambda, slip;
  std::vector<double> weights;  // nodal areas of the contact nodes
  int fixed_point = 0;
  int qp_iterations = 0;
};

Friction slide(double shift, double friction) {
  const int dim = 3;
  const double delta = 1e-4;
  Block slave, master;
  {
    slave.mesh = mesh::make_box(dim, {0, 0, 1}, {1, 1, 1.5}, {4, 4, 2});
    master.mesh = mesh::make_box(dim, {0, 0, 0}, {1, 1, 1}, {4, 4, 4});
    for (Block* b : {&slave, &master}) {
      b->matrices = fem::assemble_body(b->mesh, steel());
      b->u_prescribed = core::Vector(dim * b->mesh.n_nodes());
    }
    auto hold = [&](Block& b, const std::string& face, std::array<double, 3> u) {
      auto v = b.u_prescribed.view();
      for (const int a : b.mesh.boundary_nodes(face))
        for (int k = 0; k < dim; ++k) {
          b.dirichlet.push_back(dim * a + k);
          v[dim * a + k] = u[k];
        }
    };
    hold(slave, "zmax", {shift, 0.0, -delta});
    hold(master, "zmin", {0.0, 0.0, 0.0});
    for (Block* b : {&slave, &master})
      b->solver = std::make_unique<ConstrainedSolver>(b->matrices.stiffness_u, b->dirichlet, "");
  }
  physics::DualContactSettings settings;
  settings.qp.rtol = 1e-12;
  physics::DualContactSolver solver(*slave.solver, *master.solver, slave.u_prescribed.size(),
                                    master.u_prescribed.size(), settings);
  solver.set_rows(node_to_node(dim, slave, master));
  const PetscInt nc = solver.rows().n_nodes();
  const auto us = free_solution(slave), um = free_solution(master);
  const auto c = reference_targets(solver, us, um);

  Friction out;
  core::Vector lambda(dim * nc), previous(dim * nc), u_s(us.size()), u_m(um.size());
  std::vector<double> bound(static_cast<size_t>(nc), 0.0);  // γ = 0: frictionless first
  for (out.fixed_point = 1; out.fixed_point <= 30; ++out.fixed_point) {
    previous.copy_from(lambda);
    const auto r = solver.solve(us, um, c, bound, lambda, u_s, u_m);
    EXPECT_TRUE(r.converged()) << r.message;
    out.qp_iterations += r.iterations;
    const auto l = lambda.to_std();
    for (PetscInt k = 0; k < nc; ++k) bound[k] = friction * l[dim * k];
    previous.axpy(-1.0, lambda);
    if (previous.norm() <= 1e-10 * lambda.norm()) break;
  }
  out.lambda = lambda.to_std();
  core::Vector bu(dim * nc);
  solver.rows().slave.mult(u_s, bu);
  solver.rows().master.mult_add(u_m, bu);
  out.slip = bu.to_std();
  for (PetscInt i = 0; i < dim * nc; ++i) out.slip[i] -= c[i];
  const auto w = fem::boundary_integrals(slave.mesh, "zmin");
  for (const int a : slave.mesh.boundary_nodes("zmin")) out.weights.push_back(w[a]);
  return out;
}

TEST(Friction3d, PastTheStickLimitTheForceRatioIsTheFrictionCoefficient) {
  const double friction = 0.3;
  const auto f = slide(1e-3, friction);  // 10× the normal approach: everything slides
  EXPECT_LE(f.fixed_point, 10);          // the acceptance bound of the issue
  double normal = 0, tangential_x = 0;
  for (size_t k = 0; k < f.weights.size(); ++k) {
    const double ln = f.lambda[3 * k], lt = std::hypot(f.lambda[3 * k + 1], f.lambda[3 * k + 2]);
    const double slip = std::hypot(f.slip[3 * k + 1], f.slip[3 * k + 2]);
    ASSERT_GT(slip, 0.0) << "node " << k << " sticks";
    // Slipping nodes sit on the Coulomb circle: ‖λ_τ‖ = 𝔉λ_n to the fixed point's 1e-10.
    EXPECT_NEAR(lt, friction * ln, 1e-8 * ln) << "node " << k;
    normal += f.weights[k] * ln;
    tangential_x += f.weights[k] * f.lambda[3 * k + 1];
  }
  // The force on the slave −B_τᵀλ_τ opposes the slip (+x): λ_τ,x > 0 along +x slip.
  EXPECT_NEAR(std::abs(tangential_x) / normal, friction, 1e-6);
}

TEST(Friction3d, BelowTheStickLimitNothingSlips) {
  // A tangential shift far below 𝔉 × (the normal approach) sticks everywhere.
  const auto f = slide(1e-6, 0.9);
  double max_slip = 0, max_normal_gap = 0;
  for (size_t k = 0; k < f.weights.size(); ++k) {
    max_slip = std::max(max_slip, std::hypot(f.slip[3 * k + 1], f.slip[3 * k + 2]));
    max_normal_gap = std::max(max_normal_gap, std::abs(f.slip[3 * k]));
    EXPECT_LT(std::hypot(f.lambda[3 * k + 1], f.lambda[3 * k + 2]), 0.9 * f.lambda[3 * k]);
  }
  // Stick: the weighted slip vanishes to the QP tolerance, far below the 1e-6 imposed shift
  // (times the nodal weights ~1/16).
  EXPECT_LT(max_slip, 1e-12);
  EXPECT_LT(max_normal_gap, 1e-12);  // and the faces stay closed
}

}  // namespace
}  // namespace tc::test
