// Mortar discretisation in 2D (Line2 segments) on non-matching, randomly jittered and curved
// interfaces, with the standard and the dual multiplier basis:
//  - the rows equal the node-to-node rows of tests/support/contact_rows.hpp on matching meshes
//    (the sign convention of the dual solver);
//  - Σ D = Σ M = the overlapped length; D⁻¹M transfers a linear field exactly; the weighted gap
//    of two flat surfaces offset by δ is δ × weight; partial overlaps; rigid-motion invariance;
//    inactive slave faces and the search radius.
// Tolerances: the quadrature is exact for every integrand here (integration.hpp), so only
// round-off remains: sums of O(100) terms of size h, each with a relative error of a few ulps,
// stay below 1e-14 relative; 1e-12 leaves a margin of 100 and still fails on any lost or
// doubled piece of overlap (≥ 1e-3 of the length in these meshes).
#include <gtest/gtest.h>

#include <type_traits>

#include "mortar_fixtures.hpp"
#include "support/contact_rows.hpp"
#include "tc/core/error.hpp"

namespace tc::test {
namespace {

using contact::MortarOptions;
using contact::MortarPair;
using contact::MultiplierBasis;

class Mortar2d : public ::testing::TestWithParam<MultiplierBasis> {
 protected:
  MortarOptions options() const { return {GetParam(), 0.0}; }
};

double linear(const mesh::Point& x) {
  return 0.3 + 1.7 * x[0] - 0.9 * x[1];
}

TEST(Mortar2dRows, MatchingMeshesGiveTheNodeToNodeRowsWithTheDualBasis) {
  const auto slave = slave_block(2, 0, 1, 6, 0.01);
  const auto master = master_block(2, 0, 1, 6);
  const MortarPair pair(slave, "ymin", master, "ymax");
  const auto rows = pair.rows();
  const auto ref = node_to_node_rows(slave, master);
  ASSERT_EQ(rows.n_nodes(), ref.n_nodes());
  ASSERT_EQ(rows.dim, 2);
  // Round-off of integrals of size h/2 = 0.083: 1e-15 absolute is a few ulps.
  expect_same_rows(rows, ref, 1e-15);
}

TEST_P(Mortar2d, SumsAreTheLengthOnJitteredAndCurvedInterfaces) {
  for (const bool curved : {false, true}) {
    // The master reaches beyond the slave on both sides: the whole slave is overlapped.
    auto slave = jitter(slave_block(2, 0, 1, 13), "ymin", 0.03, 7);
    auto master = jitter(master_block(2, -0.2, 1.3, 9), "ymax", 0.05, 8);
    if (curved) slave = bend(slave, 0.2), master = bend(master, 0.2);
    const MortarPair pair(slave, "ymin", master, "ymax", options());
    SCOPED_TRACE(curved ? "curved" : "planar");
    expect_sums(pair, surface_area(slave, "ymin"), 1e-12);
    EXPECT_EQ(pair.contact_nodes().size(), 14u);
  }
}

TEST_P(Mortar2d, LinearFieldIsTransferredExactly) {
  const auto slave = jitter(slave_block(2, 0, 1, 11), "ymin", 0.03, 1);
  const auto master = jitter(master_block(2, -0.1, 1.2, 7), "ymax", 0.05, 2);
  const MortarPair pair(slave, "ymin", master, "ymax", options());
  {
    const auto t = transfer(pair, slave, master, linear);
    EXPECT_LT(t.error, t.tolerance());
  }
}

TEST_P(Mortar2d, OffsetSurfacesHaveTheGapTimesTheWeight) {
  const double delta = 0.037;
  const auto slave = jitter(slave_block(2, 0, 1, 11, delta), "ymin", 0.03, 3);
  const auto master = jitter(master_block(2, -0.1, 1.2, 7), "ymax", 0.05, 4);
  const MortarPair pair(slave, "ymin", master, "ymax", options());
  ASSERT_EQ(pair.contact_nodes().size(), 12u);
  EXPECT_LT(gap_error(pair, delta), 1e-12);
  for (const auto& n : pair.normals()) EXPECT_NEAR(n[1], -1.0, 1e-15);
  // Closed by a displacement: the same pair evaluated with the slave lowered by δ has g = 0.
  std::vector<double> u(2 * slave.n_nodes(), 0.0);
  for (int j = 0; j < slave.n_nodes(); ++j) u[2 * j + 1] = -delta;
  MortarPair moved_pair(slave, "ymin", master, "ymax", options());
  moved_pair.update(u);
  for (const double g : moved_pair.gap()) EXPECT_NEAR(g, 0.0, 1e-15);
}

TEST_P(Mortar2d, PartialOverlapMasterOffsetAndSlaveLarger) {
  struct Case {
    double master_lo, master_hi, overlap;
  };
  // master shifted right (covers [0.37, 1]); master inside the slave (covers [0.23, 0.71]).
  for (const Case c : {Case{0.37, 1.6, 0.63}, Case{0.23, 0.71, 0.48}}) {
    SCOPED_TRACE(c.master_lo);
    const double delta = 0.02;
    const auto slave = jitter(slave_block(2, 0, 1, 9, delta), "ymin", 0.02, 5);
    const auto master = jitter(master_block(2, c.master_lo, c.master_hi, 5), "ymax", 0.03, 6);
    const MortarPair pair(slave, "ymin", master, "ymax", options());
    expect_sums(pair, c.overlap, 1e-12);
    EXPECT_LT(pair.contact_nodes().size(), 10u);
    EXPECT_LT(gap_error(pair, delta), 1e-12);
    const auto slave0 = jitter(slave_block(2, 0, 1, 9), "ymin", 0.02, 5);
    const MortarPair flat(slave0, "ymin", master, "ymax", options());
    {
      const auto t = transfer(flat, slave0, master, linear);
      EXPECT_LT(t.error, t.tolerance());
    }
  }
}

TEST_P(Mortar2d, RigidMotionChangesOnlyTheFrame) {
  const auto slave = bend(jitter(slave_block(2, 0, 1, 10, 0.03), "ymin", 0.03, 9), 0.2);
  const auto master = bend(jitter(master_block(2, -0.3, 1.1, 7), "ymax", 0.05, 10), 0.2);
  const MortarPair pair(slave, "ymin", master, "ymax", options());
  auto slave_r = slave, master_r = master;
  const Rotation r = rotation({0, 0, 1}, 0.7);
  slave_r.transform(r, {0.3, -1.2, 0});
  master_r.transform(r, {0.3, -1.2, 0});
  const MortarPair turned(slave_r, "ymin", master_r, "ymax", options());
  ASSERT_EQ(turned.contact_nodes(), pair.contact_nodes());
  // Entries of size ≤ h = 0.1 computed from coordinates of size ~1 that were rotated (a few
  // ulps of 1): 1e-14 absolute.
  const auto d0 = entries(pair.d_matrix()), d1 = entries(turned.d_matrix());
  const auto m0 = entries(pair.m_matrix()), m1 = entries(turned.m_matrix());
  ASSERT_EQ(d0.size(), d1.size());
  ASSERT_EQ(m0.size(), m1.size());
  for (const auto& [ij, v] : d0) EXPECT_NEAR(d1.at(ij), v, 1e-14);
  for (const auto& [ij, v] : m0) EXPECT_NEAR(m1.count(ij) ? m1.at(ij) : 0.0, v, 1e-14);
  for (size_t k = 0; k < pair.gap().size(); ++k) {
    EXPECT_NEAR(turned.gap()[k], pair.gap()[k], 1e-14);
    EXPECT_NEAR(turned.weights()[k], pair.weights()[k], 1e-14);
    const auto n = rotate(r, pair.normals()[k]);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(turned.normals()[k][i], n[i], 1e-14);
  }
}

TEST_P(Mortar2d, InactiveFacesAndTheSearchRadius) {
  const auto slave = slave_block(2, 0, 1, 8);
  const auto far = master_block(2, 3, 4, 5);  // beside the slave: nothing in reach
  const MortarPair none(slave, "ymin", far, "ymax", options());
  EXPECT_TRUE(none.contact_nodes().empty());
  EXPECT_EQ(none.rows().n_rows(), 0);
  EXPECT_EQ(none.d_matrix().rows(), 0);
  // A master 0.1 below the slave: skipped with a radius of 0.05, found with 0.15.
  const auto lifted = slave_block(2, 0, 1, 8, 0.1);
  const auto master = master_block(2, 0, 1, 5);
  const MortarPair skipped(lifted, "ymin", master, "ymax", {GetParam(), 0.05});
  EXPECT_TRUE(skipped.contact_nodes().empty());
  const MortarPair found(lifted, "ymin", master, "ymax", {GetParam(), 0.15});
  EXPECT_EQ(found.contact_nodes().size(), 9u);
  EXPECT_LT(gap_error(found, 0.1), 1e-12);
  // A master facing away (its bottom face) is never paired.
  const MortarPair away(lifted, "ymin", master, "ymin", {GetParam(), 2.0});
  EXPECT_TRUE(away.contact_nodes().empty());
}

TEST(Mortar2dErrors, MissingBoundaryOrWrongSizesAreReported) {
  const auto slave = slave_block(2, 0, 1, 4);
  const auto master = master_block(2, 0, 1, 3);
  EXPECT_THROW(MortarPair(slave, "bottom", master, "ymax"), MeshError);
  EXPECT_THROW(MortarPair(slave, "ymin", master, "zmax"), MeshError);
  EXPECT_THROW(MortarPair(slave, "ymin", slave_block(3, 0, 1, 2), "zmin"), MeshError);
  MortarPair pair(slave, "ymin", master, "ymax");
  const std::vector<double> wrong(3, 0.0);
  EXPECT_THROW(pair.update(wrong), Error);
  EXPECT_THROW((void)pair.tangents(1), Error);
  EXPECT_THROW(MortarPair(slave, "ymin", master, "ymax", {MultiplierBasis::dual, -1.0}), Error);
  // Movable, so that a simulation can hold pairs in a container and replace them.
  static_assert(std::is_move_assignable_v<MortarPair> && std::is_move_constructible_v<MortarPair>);
  MortarPair other(slave, "ymin", master_block(2, 0.5, 1, 2), "ymax");
  other = std::move(pair);
  EXPECT_EQ(other.contact_nodes().size(), 5u);
}

INSTANTIATE_TEST_SUITE_P(Bases, Mortar2d,
                         ::testing::Values(MultiplierBasis::standard, MultiplierBasis::dual),
                         [](const auto& info) { return std::string(contact::name(info.param)); });

}  // namespace
}  // namespace tc::test
