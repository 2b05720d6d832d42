// The contact patch test (verification.md) on non-matching meshes, through the mortar rows and
// the dual solve (physics::DualContactSolver, 6.9): two blocks on rollers, the upper one pressed
// down by δ at its top, the lower one held at its bottom; frictionless and quasistatic, the
// state is uniaxial, σ = −M δ/(h_1 + h_2) with M = E (3D) or E/(1 − ν²) (2D plane strain), so
// every contact multiplier equals that pressure. Segment-based mortar integration passes it to
// the QP's tolerance (Tribol's tribol_mortar_lm_patch_test asserts 1e-10 on displacements), with
// either basis and whichever block is the slave.
#include <gtest/gtest.h>

#include <map>
#include <memory>

#include "mortar_fixtures.hpp"
#include "support/problems.hpp"
#include "support/roller_blocks.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/fem/assembler.hpp"

namespace tc::test {
namespace {

using contact::MultiplierBasis;
using physics::ConstrainedSolver;

struct Case {
  int dim;
  MultiplierBasis basis;
  bool upper_is_slave;
};

class MortarPatch : public ::testing::TestWithParam<Case> {};

TEST_P(MortarPatch, NonMatchingMeshesCarryTheUniaxialPressure) {
  const auto [dim, basis, upper_is_slave] = GetParam();
  const double delta = 1e-4;
  const auto point = [dim](double x, double z) {
    return dim == 3 ? mesh::Point{x, x, z} : mesh::Point{x, z, 0};
  };
  const std::string bottom = dim == 3 ? "zmin" : "ymin", top = dim == 3 ? "zmax" : "ymax";
  // 3 × 3 against 5 × 7 in 3D, 5 against 7 in 2D (verification.md).
  const std::array<int, 3> upper_cells = dim == 3 ? std::array{3, 3, 2} : std::array{5, 2, 1};
  const std::array<int, 3> lower_cells = dim == 3 ? std::array{5, 7, 3} : std::array{7, 3, 1};
  Block upper = make_block(dim, point(0, 1), point(1, 1.5), upper_cells, top, -delta, "");
  Block lower = make_block(dim, point(0, 0), point(1, 1), lower_cells, bottom, 0.0, "");
  Block& slave = upper_is_slave ? upper : lower;
  Block& master = upper_is_slave ? lower : upper;
  const contact::MortarPair pair(slave.mesh, upper_is_slave ? bottom : top, master.mesh,
                                 upper_is_slave ? top : bottom, {basis, 0.0});
  const int n_slave_face_nodes =
      static_cast<int>(slave.mesh.boundary_nodes(upper_is_slave ? bottom : top).size());
  ASSERT_EQ(static_cast<int>(pair.contact_nodes().size()), n_slave_face_nodes);

  physics::DualContactSettings settings;
  settings.qp.rtol = 1e-12;
  physics::DualContactSolver solver(*slave.solver, *master.solver, slave.u_prescribed.size(),
                                    master.u_prescribed.size(), settings);
  solver.set_rows(pair.rows());
  const auto us = free_solution(slave), um = free_solution(master);
  const core::Vector zs(us.size()), zm(um.size());
  const auto c = solver.targets(zs, zm, zs, zm);
  const std::vector<double> frictionless(pair.contact_nodes().size(), 0.0);
  core::Vector lambda(solver.rows().n_rows()), u_s(us.size()), u_m(um.size());
  const auto r = solver.solve(us, um, c, frictionless, lambda, u_s, u_m);
  ASSERT_TRUE(r.converged()) << r.message;

  const auto mat = steel();
  const double modulus = dim == 3 ? mat.young_modulus
                                  : mat.young_modulus / (1 - mat.poisson_ratio * mat.poisson_ratio);
  const double pressure = modulus * delta / 1.5;
  const auto l = lambda.to_std();
  // The QP stops at ‖g^P‖ ≤ 1e-12‖d‖; linear elements and exact mortar integrals reproduce
  // the uniform state, so what remains is the QP's tolerance amplified by cond(F): 1e-8.
  double worst = 0;
  for (size_t k = 0; k < pair.contact_nodes().size(); ++k) {
    worst = std::max(worst, std::abs(l[dim * k] - pressure) / pressure);
    EXPECT_NEAR(l[dim * k], pressure, 1e-8 * pressure) << "contact node " << k;
    for (int t = 1; t < dim; ++t) EXPECT_EQ(l[dim * k + t], 0.0);
  }
  if (std::getenv("TC_MORTAR_VERBOSE"))
    std::printf("pressure: max relative error %.2e, %d QP iterations\n", worst, r.iterations);
  // The bodies touch without penetrating: B_n u = c_n at every node (all active).
  core::Vector bu(solver.rows().n_rows());
  solver.rows().slave.mult(u_s, bu);
  solver.rows().master.mult_add(u_m, bu);
  const auto b = bu.to_std();
  for (size_t k = 0; k < pair.contact_nodes().size(); ++k)
    EXPECT_NEAR(b[dim * k], c[dim * k], 1e-8 * delta * pair.weights()[k]);
}

INSTANTIATE_TEST_SUITE_P(Cases, MortarPatch,
                         ::testing::Values(Case{2, MultiplierBasis::dual, true},
                                           Case{2, MultiplierBasis::dual, false},
                                           Case{2, MultiplierBasis::standard, true},
                                           Case{3, MultiplierBasis::dual, true},
                                           Case{3, MultiplierBasis::dual, false},
                                           Case{3, MultiplierBasis::standard, true}),
                         [](const auto& info) {
                           return std::to_string(info.param.dim) + "d_" +
                                  contact::name(info.param.basis) +
                                  (info.param.upper_is_slave ? "_upper_slave" : "_lower_slave");
                         });

}  // namespace
}  // namespace tc::test
