// Mortar discretisation in 3D (Tri3 and Quad4 faces, mixed) on non-matching, randomly
// jittered and curved interfaces, with the standard and the dual multiplier basis:
//  - the rows equal the node-to-node rows on matching meshes (the dual solver's convention);
//  - Σ D = Σ M = the overlapped area (planar, cylindrical and doubly curved);
//  - D⁻¹M transfers a linear field exactly on planar interfaces (rectangles of random sizes,
//    triangles, mixed, general quadrilaterals);
//  - offset gap = δ × weight; each master face cut by many slave faces and the reverse; partial
//    overlaps; rigid-motion invariance; inactive faces and the search radius.
// Tolerances: where the quadrature is exact (integration.hpp) only round-off remains: sums of
// O(10³) quadrature terms with relative errors of a few ulps stay below 1e-14; 1e-12 leaves a
// margin of 100 and fails on any lost or doubled clip polygon (≥ 1e-4 of the area here).
#include <gtest/gtest.h>

#include "mortar_fixtures.hpp"
#include "support/contact_rows.hpp"
#include "tc/core/error.hpp"

namespace tc::test {
namespace {

using contact::MortarOptions;
using contact::MortarPair;
using contact::MultiplierBasis;

class Mortar3d : public ::testing::TestWithParam<MultiplierBasis> {
 protected:
  MortarOptions options() const { return {GetParam(), 0.0}; }
};

double linear(const mesh::Point& x) {
  return 0.3 + 1.7 * x[0] - 0.9 * x[1] + 0.4 * x[2];
}

void expect_exact_transfer(const MortarPair& p, const mesh::Mesh& s, const mesh::Mesh& m) {
  const auto t = transfer(p, s, m, linear);
  EXPECT_LT(t.error, t.tolerance()) << "cond(D) = " << t.cond;
}

TEST(Mortar3dRows, MatchingMeshesGiveTheNodeToNodeRowsWithTheDualBasis) {
  const auto slave = slave_block(3, 0, 1, 4, 0.01);
  const auto master = master_block(3, 0, 1, 4);
  const MortarPair pair(slave, "zmin", master, "zmax");
  const auto rows = pair.rows();
  const auto ref = node_to_node_rows(slave, master);
  ASSERT_EQ(rows.n_nodes(), ref.n_nodes());
  ASSERT_EQ(rows.nodes, pair.contact_nodes());
  // Integrals of size h²/4 ≈ 0.016: 1e-15 absolute is a few ulps.
  expect_same_rows(rows, ref, 1e-15);
}

TEST_P(Mortar3d, SumsAreTheAreaOnJitteredPlanarAndCurvedInterfaces) {
  // The master reaches beyond the slave on every side, so the whole slave is overlapped.
  const auto s0 = slave_block(3, 0, 1, 9), m0 = master_block(3, -0.2, 1.25, 7);
  {
    SCOPED_TRACE("planar, general quadrilaterals");
    const auto s = jitter(s0, "zmin", 0.03, 11), m = jitter(m0, "zmax", 0.05, 12);
    expect_sums(MortarPair(s, "zmin", m, "zmax", options()), surface_area(s, "zmin"), 1e-12);
  }
  {
    SCOPED_TRACE("cylindrical (planar faces: jitter along the axis only)");
    const auto s = bend(jitter(s0, "zmin", 0.03, 13, true), 0.15);
    const auto m = bend(jitter(m0, "zmax", 0.05, 14, true), 0.15);
    expect_sums(MortarPair(s, "zmin", m, "zmax", options()), surface_area(s, "zmin"), 1e-12);
  }
  {
    SCOPED_TRACE("mixed Tri3/Quad4 master, all-Tri3 slave");
    const auto s = with_triangles(jitter(s0, "zmin", 0.03, 15), "zmin", "tri", 1);
    const auto m = with_triangles(jitter(m0, "zmax", 0.05, 16), "zmax", "mixed", 2);
    expect_sums(MortarPair(s, "tri", m, "mixed", options()), surface_area(s, "tri"), 1e-12);
  }
  {
    // Warped quadrilaterals: the surface element is integrated with the area ratio of
    // geometry.hpp, a rational function that the rule integrates accurately but not exactly.
    // With curvature amplitude 0.05 over faces of 0.11 the measured error is ~1e-9; 1e-7
    // still fails on any lost clip polygon (≥ 1e-4).
    SCOPED_TRACE("doubly curved, warped quadrilaterals");
    const auto s = bend(jitter(s0, "zmin", 0.03, 17), 0.05, true);
    const auto m = bend(jitter(m0, "zmax", 0.05, 18), 0.05, true);
    const MortarPair p(s, "zmin", m, "zmax", options());
    EXPECT_NEAR(sum_of(p.d_matrix()), sum_of(p.m_matrix()), 1e-12 * p.overlap_area());
    expect_sums(p, surface_area(s, "zmin"), 1e-7);
  }
}

TEST_P(Mortar3d, LinearFieldIsTransferredExactly) {
  const auto s0 = slave_block(3, 0, 1, 9), m0 = master_block(3, -0.1, 1.15, 6);
  {
    SCOPED_TRACE("rectangles of random sizes");
    const auto s = jitter_lines(s0, 0.03, 21), m = jitter_lines(m0, 0.05, 22);
    expect_exact_transfer(MortarPair(s, "zmin", m, "zmax", options()), s, m);
  }
  {
    SCOPED_TRACE("jittered triangles against a mixed Tri3/rectangle master");
    const auto s = with_triangles(jitter(s0, "zmin", 0.03, 23), "zmin", "tri", 1);
    const auto m = with_triangles(jitter_lines(m0, 0.05, 24), "zmax", "mixed", 2);
    expect_exact_transfer(MortarPair(s, "tri", m, "mixed", options()), s, m);
  }
  {
    // General quadrilaterals: φ∘(inverse bilinear map) is not a polynomial, so D and M are
    // only as accurate as the quadrature; but both sides interpolate a linear f exactly
    // (isoparametric) and, on a planar interface, meet at the same quadrature points, so
    // Σ_j M_kj f_j = Σ_q w_q ψ_k f(x_q) = Σ_j D_kj f(x_j^s) holds to round-off anyway.
    SCOPED_TRACE("general quadrilaterals");
    const auto s = jitter(s0, "zmin", 0.03, 25), m = jitter(m0, "zmax", 0.05, 26);
    expect_exact_transfer(MortarPair(s, "zmin", m, "zmax", options()), s, m);
  }
}

TEST_P(Mortar3d, OffsetSurfacesHaveTheGapTimesTheWeight) {
  const double delta = 0.041;
  const auto s = jitter(slave_block(3, 0, 1, 9, delta), "zmin", 0.03, 31);
  const auto m =
      with_triangles(jitter(master_block(3, -0.1, 1.15, 6), "zmax", 0.05, 32), "zmax", "mixed", 2);
  const MortarPair pair(s, "zmin", m, "mixed", options());
  ASSERT_EQ(pair.contact_nodes().size(), 100u);
  EXPECT_LT(gap_error(pair, delta), 1e-12);
  for (size_t k = 0; k < pair.normals().size(); ++k) {
    EXPECT_NEAR(pair.normals()[k][2], -1.0, 1e-15);
    const auto& t0 = pair.tangents(0)[k];
    const auto& t1 = pair.tangents(1)[k];
    EXPECT_NEAR(contact::dot(t0, pair.normals()[k]), 0.0, 1e-15);
    EXPECT_NEAR(contact::dot(t1, pair.normals()[k]), 0.0, 1e-15);
    EXPECT_NEAR(contact::dot(t0, t1), 0.0, 1e-15);
    EXPECT_NEAR(contact::norm(t1), 1.0, 1e-15);
  }
}

TEST_P(Mortar3d, EachMasterFaceCutByManySlaveFacesAndTheReverse) {
  const double delta = 0.013;
  struct Case {
    int n_slave, n_master;
  };
  for (const Case c : {Case{12, 2}, Case{2, 12}}) {
    SCOPED_TRACE(std::to_string(c.n_slave) + " slave faces per axis, " +
                 std::to_string(c.n_master) + " master");
    const auto s = jitter_lines(slave_block(3, 0, 1, c.n_slave, delta), 0.2 / c.n_slave, 41);
    const auto m = jitter_lines(master_block(3, -0.05, 1.1, c.n_master), 0.2 / c.n_master, 42);
    const MortarPair pair(s, "zmin", m, "zmax", options());
    expect_sums(pair, 1.0, 1e-12);
    EXPECT_LT(gap_error(pair, delta), 1e-12);
    const auto s0 = jitter_lines(slave_block(3, 0, 1, c.n_slave), 0.2 / c.n_slave, 41);
    expect_exact_transfer(MortarPair(s0, "zmin", m, "zmax", options()), s0, m);
    // Each slave face overlaps (at least) one master face, and with 12 × 12 master faces on
    // 2 × 2 slave faces every slave face is cut into ≥ 36 segments.
    EXPECT_GE(pair.segments().size(), 144u);
  }
}

TEST_P(Mortar3d, PartialOverlapMasterOffsetAndSlaveLarger) {
  struct Case {
    double x0, x1, y0, y1, overlap;
  };
  // Master offset (covers [0.3, 1] × [0, 0.75]); master inside the slave ([0.2, 0.8]²).
  for (const Case c : {Case{0.3, 1.4, -0.2, 0.75, 0.7 * 0.75}, Case{0.2, 0.8, 0.2, 0.8, 0.36}}) {
    SCOPED_TRACE(c.x0);
    const double delta = 0.02;
    const auto s = jitter_lines(slave_block(3, 0, 1, 8, delta), 0.03, 51);
    const auto m = jitter_lines(master_block(3, c.x0, c.x1, 5, c.y0, c.y1), 0.03, 52);
    const MortarPair pair(s, "zmin", m, "zmax", options());
    expect_sums(pair, c.overlap, 1e-12);
    EXPECT_LT(pair.contact_nodes().size(), 81u);
    EXPECT_LT(gap_error(pair, delta), 1e-12);
    const auto s0 = jitter_lines(slave_block(3, 0, 1, 8), 0.03, 51);
    expect_exact_transfer(MortarPair(s0, "zmin", m, "zmax", options()), s0, m);
  }
}

TEST_P(Mortar3d, SliversOfOverlapAtTheEdgeOfTheMaster) {
  // The master's edge falls a fraction ε of a face short of a slave grid line, so a column of
  // slave faces is covered on a sliver of relative width ε: the dual basis of those faces is
  // computed from nearly singular local mass matrices (Popp et al. 2012's partial overlap).
  const double h = 1.0 / 8, delta = 0.02;
  for (const double eps : {1e-3, 1e-6, 1e-9, 1e-11}) {
    SCOPED_TRACE(eps);
    const double x0 = 5 * h - eps * h;
    const auto s = slave_block(3, 0, 1, 8, delta);
    const auto m = master_block(3, x0, 1.3, 5, -0.1, 1.1);
    const MortarPair pair(s, "zmin", m, "zmax", options());
    expect_sums(pair, 1 - x0, 1e-12);
    EXPECT_LT(gap_error(pair, delta), 1e-12);
    const auto s0 = slave_block(3, 0, 1, 8);
    expect_exact_transfer(MortarPair(s0, "zmin", m, "zmax", options()), s0, m);
    // A higher weight threshold drops the nodes that only a sliver touches: D stays well
    // conditioned (≤ 100 instead of up to 1e10) and the transfer exact on the others.
    const MortarPair strict(s0, "zmin", m, "zmax", {GetParam(), 0.0, 1e-4});
    const auto t = transfer(strict, s0, m, linear);
    EXPECT_LT(t.cond, 100.0);
    EXPECT_LT(t.error, 1e-12);
    EXPECT_EQ(strict.contact_nodes().size(), 4u * 9u);  // the columns x = 5h … 1
  }
}

TEST_P(Mortar3d, RigidMotionChangesOnlyTheFrame) {
  const auto s = bend(jitter(slave_block(3, 0, 1, 7, 0.03), "zmin", 0.03, 61, true), 0.15);
  const auto m = bend(jitter(master_block(3, -0.2, 1.2, 5), "zmax", 0.05, 62, true), 0.15);
  const MortarPair pair(s, "zmin", m, "zmax", options());
  auto s_r = s, m_r = m;
  const Rotation r = rotation({1, 2, 3}, 0.7);
  s_r.transform(r, {0.3, -1.2, 2.5});
  m_r.transform(r, {0.3, -1.2, 2.5});
  const MortarPair turned(s_r, "zmin", m_r, "zmax", options());
  ASSERT_EQ(turned.contact_nodes(), pair.contact_nodes());
  // Entries ≤ h² ≈ 0.02 from coordinates of size ~3 after the motion: 1e-14 absolute.
  const auto d0 = entries(pair.d_matrix()), d1 = entries(turned.d_matrix());
  const auto m0 = entries(pair.m_matrix()), m1 = entries(turned.m_matrix());
  for (const auto& [ij, v] : d0) EXPECT_NEAR(d1.count(ij) ? d1.at(ij) : 0.0, v, 1e-14);
  for (const auto& [ij, v] : m0) EXPECT_NEAR(m1.count(ij) ? m1.at(ij) : 0.0, v, 1e-14);
  for (const auto& [ij, v] : m1) EXPECT_NEAR(m0.count(ij) ? m0.at(ij) : 0.0, v, 1e-14);
  for (size_t k = 0; k < pair.gap().size(); ++k) {
    EXPECT_NEAR(turned.gap()[k], pair.gap()[k], 1e-14);
    EXPECT_NEAR(turned.weights()[k], pair.weights()[k], 1e-14);
    const auto n = rotate(r, pair.normals()[k]);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(turned.normals()[k][i], n[i], 1e-14);
  }
}

TEST_P(Mortar3d, InactiveFacesAndTheSearchRadius) {
  const auto slave = slave_block(3, 0, 1, 4);
  const MortarPair none(slave, "zmin", master_block(3, 3, 4, 3), "zmax", options());
  EXPECT_TRUE(none.contact_nodes().empty());
  EXPECT_EQ(none.rows().n_rows(), 0);
  // Half of the slave sees the master: the other half's faces are inactive, not an error.
  const MortarPair half(slave, "zmin", master_block(3, 0.5, 1.5, 3, 0, 1), "zmax", options());
  EXPECT_EQ(half.contact_nodes().size(), 15u);
  EXPECT_NEAR(half.overlap_area(), 0.5, 1e-14);
  const auto lifted = slave_block(3, 0, 1, 4, 0.1);
  const auto master = master_block(3, 0, 1, 3);
  EXPECT_TRUE(
      MortarPair(lifted, "zmin", master, "zmax", {GetParam(), 0.05}).contact_nodes().empty());
  const MortarPair found(lifted, "zmin", master, "zmax", {GetParam(), 0.15});
  EXPECT_EQ(found.contact_nodes().size(), 25u);
  EXPECT_LT(gap_error(found, 0.1), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Bases, Mortar3d,
                         ::testing::Values(MultiplierBasis::standard, MultiplierBasis::dual),
                         [](const auto& info) { return std::string(contact::name(info.param)); });

}  // namespace
}  // namespace tc::test
