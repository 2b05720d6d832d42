// The dual contact solve (6.9) on a problem with a closed form, independent of the mortar
// layer: two blocks with matching meshes, node-to-node rows weighted by the nodal areas.
// The slave (on top) is pressed down by a prescribed displacement −δ of its top face; both
// blocks stand on rollers (x = 0: u_x = 0, y = 0: u_y = 0), the master on its bottom face.
// Frictionless and quasistatic, the state is uniaxial: σ_zz = −E δ/(h_s + h_m) in both
// blocks, so every contact multiplier (a pressure) is E δ/(h_s + h_m).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "support/contact_rows.hpp"
#include "support/problems.hpp"
#include "support/roller_blocks.hpp"
#include "support/vectors.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/fem/assembler.hpp"

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

/// The patch's QP with F explicit while it has at most `explicit_limit` rows, or at most
/// `covered_limit` rows that the compliance covers.
Result solve(int dim, PetscInt explicit_limit, PetscInt covered_limit = 0) {
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
  settings.covered_limit = covered_limit;
  physics::DualContactSolver solver(*slave.solver, *master.solver, slave.u_prescribed.size(),
                                    master.u_prescribed.size(), settings);
  solver.set_rows(std::move(rows));
  const auto us = free_solution(slave), um = free_solution(master);
  const auto c = reference_targets(solver, us, um);
  const std::vector<double> frictionless(static_cast<size_t>(solver.rows().n_nodes()), 0.0);
  core::Vector lambda(solver.rows().n_rows()), u_s(us.size()), u_m(um.size());
  Result r;
  r.qp = solver.solve(us, um, c, frictionless, lambda, u_s, u_m);
  const PetscInt m = solver.rows().n_rows();
  EXPECT_EQ(solver.kind(), explicit_limit > 0 && (m <= explicit_limit || m <= covered_limit)
                               ? physics::DualOperator::explicit_schur
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

TEST(ExplicitF, BeyondTheExplicitLimitTheCoveredRowsStayExplicitWithTheSameMultipliers) {
  // Issue 22's cliff: past explicit_limit every QP iteration cost two body solves. Rows the
  // compliance covers keep F explicit (covered_limit); the minimiser is the same, so λ agrees
  // with the matrix-free one to the QP tolerance (1e-12 relative on ‖g^P‖, times the
  // condition of F on this patch: 1e-9 relative is far above it).
  for (const int dim : {2, 3}) {
    const auto free = solve(dim, 1, 0), covered = solve(dim, 1, 8000);
    ASSERT_TRUE(free.qp.converged() && covered.qp.converged());
    double scale = 0;
    for (const double l : free.lambda) scale = std::max(scale, std::abs(l));
    for (size_t i = 0; i < free.lambda.size(); ++i)
      EXPECT_NEAR(covered.lambda[i], free.lambda[i], 1e-9 * scale) << dim << "D, row " << i;
  }
}

// ------------------------------------------- explicit F from the compliance on touched dofs

/// How far a's explicit F is from its definition (apply_f: two solves per column, F e_j =
/// Σ B_i A_i⁻¹ B_iᵀ e_j) and from b's explicit F, entry by entry; scale = the largest |F_ij|.
struct FDifferences {
  double scale = 0, to_apply = 0, to_other = 0;
};

FDifferences explicit_differences(const physics::DualContactSolver& a,
                                  const physics::DualContactSolver& b) {
  const PetscInt m = a.n_rows();
  core::Vector e(m), column(m);
  FDifferences d;
  for (PetscInt j = 0; j < m; ++j) {
    e.zero();
    e.view()[j] = 1.0;
    a.apply_f(e, column);
    const auto exact = column.to_std();
    for (PetscInt i = 0; i < m; ++i) {
      PetscScalar fa = 0, fb = 0;
      TC_PETSC(MatGetValue(a.explicit_matrix(), i, j, &fa));
      TC_PETSC(MatGetValue(b.explicit_matrix(), i, j, &fb));
      d.scale = std::max(d.scale, std::abs(exact[i]));
      d.to_apply = std::max(d.to_apply, std::abs(fa - exact[i]));
      d.to_other = std::max(d.to_other, std::abs(fa - fb));
    }
  }
  return d;
}

TEST(ExplicitF, FromTheComplianceEqualsTheSolvesToRoundOff) {
  // The slave block has its top face's vertical dofs prescribed: rows that reach them must
  // see zero compliance there, as the solves do.
  auto slave = make_block(3, {0, 0, 1}, {1, 1, 1.5}, {3, 3, 2}, "zmax", 0.0, "");
  auto master = make_block(3, {0, 0, 0}, {1, 1, 1}, {3, 3, 3}, "", 0.0, "zmin");
  const PetscInt n_s = slave.u_prescribed.size(), n_m = master.u_prescribed.size();
  physics::DualContactSettings with, without;
  without.compliance_limit = 0;
  with.scale = without.scale = false;  // explicit_matrix() is then F itself
  physics::DualContactSolver a(*slave.solver, *master.solver, n_s, n_m, with);
  physics::DualContactSolver b(*slave.solver, *master.solver, n_s, n_m, without);
  // Three sets of rows: the second overlaps the first and reaches new dofs, the third is the
  // first again (no new dof: no solve).
  const std::tuple<int, PetscInt, PetscInt> cases[] = {{6, 0, 7}, {8, 11, 5}, {6, 0, 7}};
  std::vector<int> solves;
  for (const auto& [nodes, first, stride] : cases) {
    a.set_rows(scattered_rows(n_s, n_m, nodes, first, stride));
    b.set_rows(scattered_rows(n_s, n_m, nodes, first, stride));
    ASSERT_NE(a.explicit_matrix(), nullptr);
    solves.push_back(a.setup_solves());
    const PetscInt m = 3 * nodes;
    EXPECT_EQ(b.setup_solves(), 2 * m);
    ASSERT_EQ(a.n_rows(), m);
    const auto d = explicit_differences(a, b);
    // Both are the same sums of products of the direct solver's solutions, in another order:
    // they agree to the round-off of a few hundred operations on O(scale) numbers.
    EXPECT_LE(d.to_apply, 1e-12 * d.scale);
    EXPECT_LE(d.to_other, 1e-12 * d.scale);
  }
  // Solves spent on columns: all dofs of the first rows, the new ones of the second, none on
  // the third. The first set touches 18 slave dofs and ≤ 54 master dofs.
  EXPECT_GT(solves[0], 18);
  EXPECT_GT(solves[1], 0);
  EXPECT_LT(solves[1], solves[0] + 24 + 72);
  EXPECT_EQ(solves[2], 0);
}

TEST(ExplicitF, OnTheRowsNodeStructureEqualsTheRowsThemselves) {
  // Mortar rows are B = V(C ⊗ I): F is then formed as V (Σ Ĉ_i S_i Ĉ_iᵀ) Vᵀ on a dim-th of
  // B's entries. Against the same B without its structure (directions cleared: F from B's
  // rows) and against the definition (apply_f, two solves), in 2D and 3D, one pair and two
  // stacked pairs (the second's nodes after the first's). Both are sums of the same products
  // in another order: 1e-12 of F's largest entry; a rotation by V_kᵀ instead of V_k, a block
  // of the wrong node or a lost sign is O(1).
  for (const int dim : {2, 3}) {
    const auto lo = [&](double z) {
      return dim == 3 ? mesh::Point{0, 0, z} : mesh::Point{0, z, 0};
    };
    const auto hi = [&](double z) {
      return dim == 3 ? mesh::Point{1, 1, z} : mesh::Point{1, z, 0};
    };
    const std::string top = dim == 3 ? "zmax" : "ymax", bottom = dim == 3 ? "zmin" : "ymin";
    auto slave = make_block(dim, lo(1), hi(1.5), {3, 3, 2}, top, 0.0, "");
    auto master = make_block(dim, lo(0), hi(1), {3, 3, 3}, "", 0.0, bottom);
    const PetscInt n_s = slave.u_prescribed.size(), n_m = master.u_prescribed.size();
    for (const int pairs : {1, 2}) {
      physics::DualContactSettings plain;
      plain.scale = false;  // explicit_matrix() is then F itself
      physics::DualContactSolver a(*slave.solver, *master.solver, n_s, n_m, plain);
      physics::DualContactSolver b(*slave.solver, *master.solver, n_s, n_m, plain);
      std::vector<physics::ContactRows> structured, unstructured;
      for (int p = 0; p < pairs; ++p) {
        structured.push_back(node_structured_rows(dim, n_s / dim, n_m / dim, 7, 2 + 5 * p, 3));
        ASSERT_TRUE(structured.back().node_structured());
        unstructured.push_back(node_structured_rows(dim, n_s / dim, n_m / dim, 7, 2 + 5 * p, 3));
        unstructured.back().directions.clear();
      }
      const std::vector<physics::PairBodies> bodies(static_cast<size_t>(pairs));
      a.set_rows(std::move(structured), bodies);
      b.set_rows(std::move(unstructured), bodies);
      ASSERT_NE(a.explicit_matrix(), nullptr);
      ASSERT_NE(b.explicit_matrix(), nullptr);
      const auto d = explicit_differences(a, b);
      ASSERT_GT(d.scale, 0.0);
      EXPECT_LE(d.to_other, 1e-12 * d.scale) << dim << "D, " << pairs << " pair(s)";
      EXPECT_LE(d.to_apply, 1e-12 * d.scale) << dim << "D, " << pairs << " pair(s)";
    }
  }
}

TEST(ExplicitF, ScaledInPlaceGivesTheSameConstraintValues) {
  // With the QP scaled, Σ F Σ takes F's place and B u − Fλ is formed as B u − Σ⁻¹(Σ F Σ)Σ⁻¹λ:
  // the same values as from F itself and from the matrix-free F (two solves per body), to the
  // round-off of the products (1e-12 of the largest term; a σ applied once or twice, or on
  // the wrong side, changes them by O(1) relative).
  auto slave = make_block(3, {0, 0, 1}, {1, 1, 1.5}, {3, 3, 2}, "zmax", 0.0, "");
  auto master = make_block(3, {0, 0, 0}, {1, 1, 1}, {3, 3, 3}, "", 0.0, "zmin");
  const PetscInt n_s = slave.u_prescribed.size(), n_m = master.u_prescribed.size();
  physics::DualContactSettings scaled, plain, free;
  plain.scale = false;
  free.explicit_limit = 0;  // matrix-free
  physics::DualContactSolver a(*slave.solver, *master.solver, n_s, n_m, scaled);
  physics::DualContactSolver b(*slave.solver, *master.solver, n_s, n_m, plain);
  physics::DualContactSolver c(*slave.solver, *master.solver, n_s, n_m, free);
  constexpr int nodes = 8;
  for (auto* d : {&a, &b, &c}) d->set_rows(scattered_rows(n_s, n_m, nodes, 11, 5));
  ASSERT_EQ(c.kind(), physics::DualOperator::matrix_free);
  ASSERT_EQ(a.kind(), physics::DualOperator::explicit_schur);
  const auto us = some_vector(n_s, 0.2), um = some_vector(n_m, 0.9);
  const auto lambda = some_vector(3 * nodes, 1.3);
  core::Vector va, vb, vc;
  a.constraint_values(us, um, lambda, va);
  b.constraint_values(us, um, lambda, vb);
  c.constraint_values(us, um, lambda, vc);
  const double scale = vb.max_abs();
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(max_abs_diff(va, vb), 1e-12 * scale);
  EXPECT_LT(max_abs_diff(va, vc), 1e-12 * scale);
}

TEST(ExplicitF, FormedByThreadsIsTheSerialFToTheBit) {
  // F's bands of 32 rows are dealt to threads: 150 nodes (450 rows, 15 bands, the last short)
  // by 1, 2 and 3 threads (more threads than the CPUs here is fine). Each entry is one sum
  // whatever thread computes it, so F must be equal entry for entry; a band written to the
  // wrong rows or a buffer shared between threads would show.
  auto slave = make_block(3, {0, 0, 1}, {1, 1, 1.5}, {3, 3, 2}, "zmax", 0.0, "");
  auto master = make_block(3, {0, 0, 0}, {1, 1, 1}, {3, 3, 3}, "", 0.0, "zmin");
  const PetscInt n_s = slave.u_prescribed.size(), n_m = master.u_prescribed.size();
  constexpr int nodes = 150;
  std::vector<std::vector<double>> f;
  for (const int threads : {1, 2, 3}) {
    physics::DualContactSettings s;
    s.form_threads = threads;
    physics::DualContactSolver d(*slave.solver, *master.solver, n_s, n_m, s);
    d.set_rows(scattered_rows(n_s, n_m, nodes, 3, 5));
    ASSERT_NE(d.explicit_matrix(), nullptr);
    const PetscScalar* v = nullptr;
    TC_PETSC(MatDenseGetArrayRead(d.explicit_matrix(), &v));
    f.emplace_back(v, v + 9 * nodes * nodes);
    TC_PETSC(MatDenseRestoreArrayRead(d.explicit_matrix(), &v));
  }
  ASSERT_GT(*std::max_element(f[0].begin(), f[0].end()), 0.0);
  for (size_t k = 0; k < f[0].size(); ++k) {
    ASSERT_EQ(f[1][k], f[0][k]) << "2 threads, entry " << k;
    ASSERT_EQ(f[2][k], f[0][k]) << "3 threads, entry " << k;
  }
}

TEST(ExplicitF, FormedAgainOnRowsSeenBeforeIsTheFirstFToTheBit) {
  // F is formed every step into the last step's storage, from S read tile by tile on the
  // T-positions U the rows reach. Rows R1, R2 (as many rows, partly on other dofs: F's storage
  // kept, S grown, U ⊊ T and not its first positions), R1 again, R2 again: each F entry is the
  // same sum of the same entries of S (S's old block does not move when it grows) in the same
  // order, so a repeat must be the first F to the bit, and every F must be F's definition
  // (apply_f, two solves, to 1e-12 of F's largest entry, the round-off of a few hundred
  // operations). A stale entry, a tile read from the wrong rows or columns of S, or a W
  // buffer of the last step's size would show. 1 and 3 threads.
  auto slave = make_block(3, {0, 0, 1}, {1, 1, 1.5}, {3, 3, 2}, "zmax", 0.0, "");
  auto master = make_block(3, {0, 0, 0}, {1, 1, 1}, {3, 3, 3}, "", 0.0, "zmin");
  const PetscInt n_s = slave.u_prescribed.size(), n_m = master.u_prescribed.size();
  for (const int threads : {1, 3}) {
    physics::DualContactSettings plain;
    plain.scale = false;  // explicit_matrix() is then F itself
    plain.form_threads = threads;
    physics::DualContactSolver a(*slave.solver, *master.solver, n_s, n_m, plain);
    const auto entries = [&] {
      const PetscScalar* v = nullptr;
      TC_PETSC(MatDenseGetArrayRead(a.explicit_matrix(), &v));
      std::vector<double> f(v, v + a.n_rows() * a.n_rows());
      TC_PETSC(MatDenseRestoreArrayRead(a.explicit_matrix(), &v));
      return f;
    };
    const std::pair<PetscInt, PetscInt> sets[] = {{2, 3}, {5, 7}, {2, 3}, {5, 7}};
    std::map<PetscInt, std::vector<double>> first;  // by the set's first node
    ::Mat storage = nullptr;
    for (const auto& [start, stride] : sets) {
      a.set_rows(node_structured_rows(3, n_s / 3, n_m / 3, 40, start, stride));
      ASSERT_NE(a.explicit_matrix(), nullptr);
      if (storage) {
        EXPECT_EQ(a.explicit_matrix(), storage);  // the same m: kept
      }
      storage = a.explicit_matrix();
      const auto d = explicit_differences(a, a);
      ASSERT_GT(d.scale, 0.0);
      EXPECT_LE(d.to_apply, 1e-12 * d.scale) << threads << " thread(s), rows from " << start;
      const auto f = entries();
      const auto [at, fresh] = first.try_emplace(start, f);
      EXPECT_EQ(a.setup_solves() > 0, fresh);  // only new rows reach new dofs
      for (size_t k = 0; k < f.size(); ++k)
        ASSERT_EQ(f[k], at->second[k]) << threads << " thread(s), rows from " << start;
    }
  }
}

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

Friction slide(double shift, double friction, bool scale = true) {
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
  settings.scale = scale;
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

TEST(Friction3d, ScalingTheDualVariablesKeepsTheSolution) {
  // Σ changes the metric of MPGP, not the QP: the same λ from both, in stick (0.9) and in
  // slip (0.3), to what the stopping tests allow (‖g^P‖ ≤ 1e-12‖d‖ in either norm, the
  // fixed point to 1e-10 relative, with the conditioning of F on top).
  for (const auto& [shift, friction] : {std::pair{1e-6, 0.9}, std::pair{1e-3, 0.3}}) {
    const auto a = slide(shift, friction, true), b = slide(shift, friction, false);
    ASSERT_EQ(a.lambda.size(), b.lambda.size());
    double scale = 0, diff = 0;
    for (size_t i = 0; i < a.lambda.size(); ++i) {
      scale = std::max(scale, std::abs(b.lambda[i]));
      diff = std::max(diff, std::abs(a.lambda[i] - b.lambda[i]));
    }
    EXPECT_LE(diff, 1e-8 * scale) << "shift " << shift;
  }
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
