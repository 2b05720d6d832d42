// Dual (and standard) mortar on second-order contact surfaces: Line3 in 2D, Tri6, Quad8, Quad9
// in 3D, quadratic against quadratic and quadratic against linear, on non-matching meshes
// whose grid lines are moved at random (faces stay affine, mid-edge nodes at the midpoints).
// Closed forms:
//  - the weights ∫ψ_k of one covered face: Line3 (1/6, 1/6, 2/3) L; Quad9 (1/36, 1/9, 4/9) A;
//    on the transformed basis (α = 1/5, integration.hpp) Tri6 (2/15, 1/5) A and Quad8
//    (1/20, 1/5) A at the (vertices, mid-edge nodes), all positive; D = diag(d̃)T⁻ᵀ, so a
//    mid-edge row of Tri6 and Quad8 holds 5/3 d̃ at its node and −1/3 d̃ at its two vertices;
//  - Σ D = Σ M = Σ weights = the overlapped area;
//  - D⁻¹M transfers a linear field exactly, and a quadratic one when both sides are quadratic
//    (both spaces then hold it: P2 ⊂ Tri6, Quad8, Quad9, Line3);
//  - the weighted gap of surfaces offset by δ is δ × weight at every contact node;
//  - every slave node, vertex and mid-edge, is a contact node.
// And the contact patch test of mortar_patch_test.cpp on these surfaces through the dual solve
// (physics::DualContactSolver): a uniform pressure is transmitted at every slave node. The
// same closed forms at other shares α of the transformation (MortarOptions::vertex_share), and
// which pressures each multiplier space holds (MultiplierSpace, below).
// Tolerances: the rules are exact for these integrands (integration.hpp's mortar_rule), so only
// round-off remains: sums of O(10³–10⁴) terms of a few ulps stay below 1e-13 relative; 1e-12
// fails on any lost or doubled clip polygon (≥ 1e-4 of the area here).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>

#include "mortar_fixtures.hpp"
#include "support/problems.hpp"
#include "support/roller_blocks.hpp"
#include "tc/core/error.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/mesh/reference_cell.hpp"
#include "tc/mesh/second_order.hpp"

namespace tc::test {
namespace {

using contact::MortarOptions;
using contact::MortarPair;
using contact::MultiplierBasis;
using mesh::CellType;

/// A first-order box as cells of `element` on its corners (Kuhn simplices, mid-edge nodes at
/// the midpoints of the straight edges).
mesh::Mesh as_element(const mesh::Mesh& box, CellType element) {
  const CellType corners = mesh::corner_type(element);
  mesh::Mesh m = corners == CellType::Tri3 || corners == CellType::Tet4
                     ? mesh::split_into_simplices(box)
                     : box;
  return mesh::order(element) == 2 ? mesh::to_second_order(m, element) : m;
}

double linear(const mesh::Point& x) {
  return 0.3 + 1.7 * x[0] - 0.9 * x[1] + 0.4 * x[2];
}
/// On the flat interfaces here (y = const in 2D, z = const in 3D) a quadratic of the plane.
double quadratic(const mesh::Point& x) {
  return 0.3 + 1.7 * x[0] - 0.9 * x[1] + 0.8 * x[0] * x[0] - 1.1 * x[0] * x[1] + 0.6 * x[1] * x[1];
}

struct Surfaces {
  int dim;
  CellType slave, master;
};

std::string label(const Surfaces& s) {
  return std::to_string(s.dim) + "d_" + mesh::name(s.slave) + "_on_" + mesh::name(s.master);
}

class QuadraticMortar : public ::testing::TestWithParam<std::tuple<Surfaces, MultiplierBasis>> {
 protected:
  Surfaces surfaces() const { return std::get<0>(GetParam()); }
  MortarOptions options() const { return {std::get<1>(GetParam()), 0.0}; }
  bool both_quadratic() const {
    return mesh::order(surfaces().slave) == 2 && mesh::order(surfaces().master) == 2;
  }
  /// Slave [0, 1]^(d−1) (7 cells per axis in 2D, 4 in 3D) raised by `gap` over the master
  /// [−0.2, 1.25]^(d−1) (5 or 3 cells), grid lines moved by up to 0.03 and 0.05.
  std::pair<mesh::Mesh, mesh::Mesh> blocks(double gap = 0) const {
    const auto [dim, s, m] = surfaces();
    const int ns = dim == 2 ? 7 : 4, nm = dim == 2 ? 5 : 3;
    return {as_element(jitter_lines(slave_block(dim, 0, 1, ns, gap), 0.03, 21), s),
            as_element(jitter_lines(master_block(dim, -0.2, 1.25, nm), 0.05, 22), m)};
  }
};

TEST_P(QuadraticMortar, SumsAreTheAreaAndEverySlaveNodeCarriesAMultiplier) {
  const auto [slave, master] = blocks();
  const int dim = surfaces().dim;
  const MortarPair pair(slave, bottom(dim), master, top(dim), options());
  expect_sums(pair, surface_area(slave, bottom(dim)), 1e-12);
  EXPECT_EQ(pair.contact_nodes().size(), slave.boundary_nodes(bottom(dim)).size());
  for (const double w : pair.weights()) EXPECT_GT(w, 0.0);
}

TEST_P(QuadraticMortar, TransfersLinearFieldsAndQuadraticOnesWhereBothSpacesHoldThem) {
  const auto [slave, master] = blocks();
  const int dim = surfaces().dim;
  const MortarPair pair(slave, bottom(dim), master, top(dim), options());
  const auto t = transfer(pair, slave, master, linear);
  EXPECT_LT(t.error, t.tolerance()) << "linear, cond(D) = " << t.cond;
  if (both_quadratic()) {
    const auto q = transfer(pair, slave, master, quadratic);
    EXPECT_LT(q.error, q.tolerance()) << "quadratic, cond(D) = " << q.cond;
  }
}

TEST_P(QuadraticMortar, OffsetGapIsDeltaTimesTheWeight) {
  const double delta = 0.01;
  const auto [slave, master] = blocks(delta);
  const int dim = surfaces().dim;
  const MortarPair pair(slave, bottom(dim), master, top(dim), options());
  // g_k = n_k·∫ψ_k(x^m − x^s) = δ∫ψ_k exactly (flat faces, exact rules): round-off of δ w.
  EXPECT_LT(gap_error(pair, delta), 1e-12);
}

const Surfaces kSurfaces[] = {
    {2, CellType::Quad8, CellType::Quad8}, {2, CellType::Quad9, CellType::Tri6},
    {2, CellType::Quad8, CellType::Quad4}, {2, CellType::Quad4, CellType::Quad9},
    {3, CellType::Hex20, CellType::Hex20}, {3, CellType::Hex27, CellType::Hex27},
    {3, CellType::Tet10, CellType::Tet10}, {3, CellType::Tet10, CellType::Hex20},
    {3, CellType::Hex20, CellType::Hex8},  {3, CellType::Hex27, CellType::Tet4},
    {3, CellType::Tet10, CellType::Hex8},  {3, CellType::Hex8, CellType::Hex27}};

INSTANTIATE_TEST_SUITE_P(Pairs, QuadraticMortar,
                         ::testing::Combine(::testing::ValuesIn(kSurfaces),
                                            ::testing::Values(MultiplierBasis::dual,
                                                              MultiplierBasis::standard)),
                         [](const auto& info) {
                           return label(std::get<0>(info.param)) + "_" +
                                  contact::name(std::get<1>(info.param));
                         });

// ---------------------------------------------------------------------------------------------
// One slave face, wholly covered by a master face: its nodes' weights and D's rows.

struct OneFace {
  int dim;
  CellType cell;
  std::vector<double> vertex_edge_centre;  // ∫ψ_k / area at a vertex, a mid-edge node, the centre
  bool transformed;
  double alpha = contact::kVertexShare;  // MortarOptions::vertex_share
  const char* tag = "";                  // the test name's suffix
};

class QuadraticWeights : public ::testing::TestWithParam<OneFace> {};

TEST_P(QuadraticWeights, AreTheClosedFormsOfTheTransformedBasis) {
  const auto& c = GetParam();
  // The slave [0.2, 0.8]^(d−1): one cell; the master one cell of [0, 1]^(d−1) below it.
  const auto slave = as_element(slave_block(c.dim, 0.2, 0.8, 1), c.cell);
  const auto master = master_block(c.dim, 0, 1, 1);
  const double area = c.dim == 2 ? 0.6 : 0.36;
  MortarOptions options;
  options.vertex_share = c.alpha;
  const MortarPair pair(slave, bottom(c.dim), master, top(c.dim), options);
  // Each node's weight is its role's share of every face it is on (a Kuhn-split square gives
  // two triangles of half its area).
  const auto facets = slave.boundary(bottom(c.dim));
  const double face_area = area / static_cast<double>(facets.size());
  std::map<int, double> expected;
  for (const auto& f : facets) {
    const int corners = mesh::n_nodes(mesh::corner_type(f.type));
    const int n_edges = f.type == mesh::FacetType::Line3 ? 1 : corners;
    for (int a = 0; a < mesh::n_nodes(f.type); ++a) {
      const int role = a < corners ? 0 : a < corners + n_edges ? 1 : 2;
      expected[f.nodes[a]] += c.vertex_edge_centre[static_cast<size_t>(role)] * face_area;
    }
  }
  ASSERT_EQ(pair.contact_nodes().size(), expected.size());
  double total = 0;
  for (const auto& [node, w] : expected) {
    const int k = pair.contact_index(node);
    ASSERT_GE(k, 0) << "node " << node;
    // Integrals of size ≤ 0.36 summed over ≤ 2 faces: 1e-15 absolute is a few ulps.
    EXPECT_NEAR(pair.weights()[static_cast<size_t>(k)], w, 1e-15) << "node " << node;
    EXPECT_GT(pair.weights()[static_cast<size_t>(k)], 0.0);
    total += pair.weights()[static_cast<size_t>(k)];
  }
  EXPECT_NEAR(total, area, 1e-14);
  // D's rows: diagonal but for the mid-edge rows of transformed faces, d̃/(1 − 2α) at the node
  // and −α d̃/(1 − 2α) at each of its vertices (T⁻ᵀ; 5/3 and −1/3 with α = 1/5), each row
  // summing to its weight.
  const auto d = entries(pair.d_matrix());
  std::map<PetscInt, std::vector<std::pair<int, double>>> rows;
  for (const auto& [ij, v] : d) rows[ij.first].push_back({static_cast<int>(ij.second), v});
  for (const auto& [k, row] : rows) {
    const int node = pair.contact_nodes()[static_cast<size_t>(k)];
    const double w = pair.weights()[static_cast<size_t>(k)];
    double sum = 0;
    for (const auto& [j, v] : row) {
      sum += v;
      if (j == node) continue;
      EXPECT_TRUE(c.transformed) << "an off-diagonal entry of D in row " << k;
      EXPECT_NEAR(v, -c.alpha * w / (1 - 2 * c.alpha), 1e-14) << "row " << k << " column " << j;
    }
    EXPECT_NEAR(sum, w, 1e-14);
    if (row.size() > 1) {
      EXPECT_EQ(row.size(), 3u);
      EXPECT_NEAR(d.at({k, node}), w / (1 - 2 * c.alpha), 1e-14);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Faces, QuadraticWeights,
    ::testing::Values(OneFace{2, CellType::Quad8, {1.0 / 6, 2.0 / 3, 0}, false},
                      OneFace{3, CellType::Hex27, {1.0 / 36, 1.0 / 9, 4.0 / 9}, false},
                      OneFace{3, CellType::Hex20, {1.0 / 20, 1.0 / 5, 0}, true},
                      OneFace{3, CellType::Tet10, {2.0 / 15, 1.0 / 5, 0}, true},
                      // Other shares: Quad8 (2α/3 − 1/12, (1 − 2α)/3), Tri6 (2α/3, (1 − 2α)/3).
                      OneFace{3, CellType::Hex20, {1.0 / 36, 2.0 / 9, 0}, true, 1.0 / 6, "_1_6"},
                      OneFace{3, CellType::Hex20, {1.0 / 8, 1.0 / 8, 0}, true, 5.0 / 16, "_5_16"},
                      OneFace{3, CellType::Tet10, {1.0 / 18, 5.0 / 18, 0}, true, 1.0 / 12, "_1_12"},
                      OneFace{3, CellType::Tet10, {1.0 / 6, 1.0 / 6, 0}, true, 0.25, "_1_4"}),
    [](const auto& info) { return std::string(mesh::name(info.param.cell)) + info.param.tag; });

// ---------------------------------------------------------------------------------------------
// Other shares α of the transformation (MortarOptions::vertex_share) on the non-matching
// surfaces of QuadraticMortar: the same closed forms hold for every α of the open interval
// that keeps the weights positive, since Σφ̃ = 1 and span φ̃ = span φ for any α < ½.

struct Share {
  Surfaces surfaces;
  double alpha;
  const char* tag;
};

class VertexShare : public ::testing::TestWithParam<Share> {
 protected:
  MortarOptions options() const {
    MortarOptions o;
    o.vertex_share = GetParam().alpha;
    return o;
  }
  std::pair<mesh::Mesh, mesh::Mesh> blocks(double gap = 0) const {
    const auto [dim, s, m] = GetParam().surfaces;
    return {as_element(jitter_lines(slave_block(dim, 0, 1, 4, gap), 0.03, 21), s),
            as_element(jitter_lines(master_block(dim, -0.2, 1.25, 3), 0.05, 22), m)};
  }
};

TEST_P(VertexShare, KeepsTheSumsTheTransferAndTheGap) {
  const auto [slave, master] = blocks();
  const MortarPair pair(slave, bottom(3), master, top(3), options());
  expect_sums(pair, surface_area(slave, bottom(3)), 1e-12);
  EXPECT_EQ(pair.contact_nodes().size(), slave.boundary_nodes(bottom(3)).size());
  for (const double w : pair.weights()) EXPECT_GT(w, 0.0);
  const auto t = transfer(pair, slave, master, linear);
  EXPECT_LT(t.error, t.tolerance()) << "linear, cond(D) = " << t.cond;
  if (mesh::order(GetParam().surfaces.master) == 2) {
    const auto q = transfer(pair, slave, master, quadratic);
    EXPECT_LT(q.error, q.tolerance()) << "quadratic, cond(D) = " << q.cond;
  }
  std::printf("[ measure  ] %s α = %.4f: cond(D) = %.3e\n", label(GetParam().surfaces).c_str(),
              GetParam().alpha, t.cond);
  const double delta = 0.01;
  const auto [raised, below] = blocks(delta);
  const MortarPair offset(raised, bottom(3), below, top(3), options());
  EXPECT_LT(gap_error(offset, delta), 1e-12);
}

const Share kShares[] = {{{3, CellType::Tet10, CellType::Tet10}, 1.0 / 12, "1_12"},
                         {{3, CellType::Tet10, CellType::Tet10}, 0.2, "1_5"},
                         {{3, CellType::Tet10, CellType::Tet10}, 0.25, "1_4"},
                         {{3, CellType::Tet10, CellType::Tet10}, 0.4, "2_5"},
                         {{3, CellType::Tet10, CellType::Hex20}, 0.45, "9_20"},
                         {{3, CellType::Tet10, CellType::Hex8}, 0.25, "1_4"},
                         {{3, CellType::Hex20, CellType::Hex20}, 1.0 / 6, "1_6"},
                         {{3, CellType::Hex20, CellType::Hex20}, 0.2, "1_5"},
                         {{3, CellType::Hex20, CellType::Hex20}, 5.0 / 16, "5_16"},
                         {{3, CellType::Hex20, CellType::Hex20}, 0.4, "2_5"},
                         {{3, CellType::Hex20, CellType::Tet10}, 0.45, "9_20"},
                         {{3, CellType::Hex20, CellType::Hex8}, 5.0 / 16, "5_16"}};

INSTANTIATE_TEST_SUITE_P(Pairs, VertexShare, ::testing::ValuesIn(kShares), [](const auto& info) {
  return label(info.param.surfaces) + "_alpha_" + info.param.tag;
});

// ---------------------------------------------------------------------------------------------
// Which pressures the multiplier space M_h = span ψ holds (its a priori order: an L2 error
// O(h^{k+1}) of λ_h needs P_k ⊂ M_h). Slave and master cover the same square (line), so D is
// square and invertible: λ = D⁻ᵀ f̂_s with f̂_j = ∫p φ_j^s is the one λ_h ∈ M_h with the moments
// of p, and λ_h = p iff p ∈ M_h; then Mᵀλ = ∫λ_h φ^m equals f̂^m = ∫p φ^m, otherwise not.
// Constants are held by every space (Σψ = 1). A linear p is held by Line3 (the weighted mean
// ∫xφ_v/∫φ_v of a vertex function is the vertex on either side) and Quad9 (its tensor
// product), not by Line2, Quad4, Tri3 (ψ_v's mean is the point ⅓ (2/4 for Tri3) into each cell)
// and not by Tri6 or Quad8 with any α: the mean of a mid-edge function (2/5, 2/5, 1/5 in a
// Tri6's barycentrics) depends on the cell.

/// Σ over the facets of ∫ g φ_a dS by facet quadrature (exact here: affine facets, g of
/// degree ≤ 1), per node.
std::map<int, double> moments(const mesh::Mesh& m, const std::string& boundary,
                              const std::function<double(const mesh::Point&)>& g) {
  std::map<int, double> out;
  for (const auto& f : m.boundary(boundary)) {
    const auto at = [&](const contact::Vec2& xi, double w) {
      const auto s = contact::facet_shape(f.type, xi);
      mesh::Point x{0, 0, 0};
      contact::Vec3 d1{0, 0, 0}, d2{0, 0, 0};
      for (int b = 0; b < s.n; ++b)
        for (int c = 0; c < 3; ++c) {
          x[c] += s.phi[b] * m.point(f.nodes[b])[c];
          d1[c] += s.dphi[b][0] * m.point(f.nodes[b])[c];
          d2[c] += s.dphi[b][1] * m.point(f.nodes[b])[c];
        }
      const double ds = m.dim() == 2 ? contact::norm(d1) : contact::norm(contact::cross(d1, d2));
      for (int a = 0; a < s.n; ++a) out[f.nodes[a]] += w * ds * g(x) * s.phi[a];
    };
    const auto corners = mesh::corner_type(f.type);
    if (m.dim() == 2)
      for (const auto& p : contact::gauss_line(5)) at({p.s, 0}, p.w);
    else if (corners == mesh::FacetType::Tri3)
      for (const auto& p : contact::gauss_triangle(5)) at({p.r, p.s}, 0.5 * p.w);
    else
      for (const auto& p : contact::gauss_line(5))
        for (const auto& q : contact::gauss_line(5)) at({2 * p.s - 1, 2 * q.s - 1}, 4 * p.w * q.w);
  }
  return out;
}

/// max_c |(Mᵀ D⁻ᵀ f̂_s)_c − f̂_c^m| / max |f̂^m| (the header's comment).
double reproduction_error(const MortarPair& pair, const mesh::Mesh& slave, const mesh::Mesh& master,
                          const std::function<double(const mesh::Point&)>& p) {
  const int dim = slave.dim();
  const auto fs = moments(slave, bottom(dim), p), fm = moments(master, top(dim), p);
  const auto& nodes = pair.contact_nodes();
  const auto n = static_cast<Eigen::Index>(nodes.size());
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, n);
  for (const auto& [kj, v] : entries(pair.d_matrix()))
    d(kj.first, pair.contact_index(static_cast<int>(kj.second))) += v;
  Eigen::VectorXd rhs(n);
  for (Eigen::Index k = 0; k < n; ++k) rhs(k) = fs.at(nodes[static_cast<size_t>(k)]);
  const Eigen::VectorXd lambda = d.transpose().partialPivLu().solve(rhs);
  std::map<int, double> mt;
  for (const auto& [kc, v] : entries(pair.m_matrix()))
    mt[static_cast<int>(kc.second)] += v * lambda(kc.first);
  double err = 0, scale = 0;
  for (const auto& [c, f] : fm) {
    err = std::max(err, std::abs(mt[c] - f));
    scale = std::max(scale, std::abs(f));
  }
  return err / scale;
}

struct Space {
  int dim;
  CellType slave, master;
  double alpha;
  bool linear;  // P1 ⊂ M_h
  const char* tag;
};

class MultiplierSpace : public ::testing::TestWithParam<Space> {};

TEST_P(MultiplierSpace, HoldsConstantsAndLinearPressuresWhereTheTheorySays) {
  const auto& c = GetParam();
  const int ns = c.dim == 2 ? 7 : 4, nm = c.dim == 2 ? 5 : 3;
  const auto slave = as_element(jitter_lines(slave_block(c.dim, 0, 1, ns), 0.03, 21), c.slave);
  const auto master = as_element(jitter_lines(master_block(c.dim, 0, 1, nm), 0.05, 22), c.master);
  MortarOptions options;
  options.vertex_share = c.alpha;
  const MortarPair pair(slave, bottom(c.dim), master, top(c.dim), options);
  ASSERT_EQ(pair.contact_nodes().size(), slave.boundary_nodes(bottom(c.dim)).size());
  const double constant =
      reproduction_error(pair, slave, master, [](const mesh::Point&) { return 1.0; });
  const double lin = reproduction_error(pair, slave, master, linear);
  std::printf("[ measure  ] multipliers on %s (α = %.4f): constant %.1e, linear %.1e\n",
              mesh::name(c.slave), c.alpha, constant, lin);
  // Round-off: a dense solve with cond(D) ≤ 10² of O(10²) moments; a space that misses P1
  // misses it by O(h²) of the moments here (≥ 1e-4 relative, measured).
  EXPECT_LT(constant, 1e-12);
  if (c.linear)
    EXPECT_LT(lin, 1e-12);
  else
    EXPECT_GT(lin, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(
    Spaces, MultiplierSpace,
    ::testing::Values(Space{2, CellType::Quad4, CellType::Quad8, 0.2, false, "Line2"},
                      Space{2, CellType::Quad8, CellType::Quad4, 0.2, true, "Line3"},
                      Space{3, CellType::Hex8, CellType::Hex27, 0.2, false, "Quad4"},
                      Space{3, CellType::Tet4, CellType::Hex20, 0.2, false, "Tri3"},
                      Space{3, CellType::Hex27, CellType::Hex8, 0.2, true, "Quad9"},
                      Space{3, CellType::Tet10, CellType::Hex8, 1.0 / 12, false, "Tri6_1_12"},
                      Space{3, CellType::Tet10, CellType::Hex8, 0.2, false, "Tri6_1_5"},
                      Space{3, CellType::Tet10, CellType::Hex8, 0.25, false, "Tri6_1_4"},
                      Space{3, CellType::Tet10, CellType::Hex8, 1.0 / 20, false, "Tri6_1_20"},
                      Space{3, CellType::Tet10, CellType::Hex8, 1.0 / 8, false, "Tri6_1_8"},
                      Space{3, CellType::Tet10, CellType::Hex8, 0.4, false, "Tri6_2_5"},
                      Space{3, CellType::Hex20, CellType::Tet4, 1.0 / 6, false, "Quad8_1_6"},
                      Space{3, CellType::Hex20, CellType::Tet4, 0.25, false, "Quad8_1_4"},
                      Space{3, CellType::Hex20, CellType::Tet4, 0.4, false, "Quad8_2_5"},
                      Space{3, CellType::Hex20, CellType::Tet4, 0.2, false, "Quad8_1_5"},
                      Space{3, CellType::Hex20, CellType::Tet4, 5.0 / 16, false, "Quad8_5_16"}),
    [](const auto& info) { return std::string(info.param.tag); });

TEST(VertexShareRange, OutsideThePositiveWeightsIsRefused) {
  // Quad8 needs α > ⅛ (∫φ̃_v = 2α/3 − 1/12), Tri6 α > 0, both α < ½ (∫φ̃_e = (1 − 2α)/3).
  const auto master = master_block(3, 0, 1, 2);
  const auto hex20 = as_element(slave_block(3, 0, 1, 2), CellType::Hex20);
  const auto tet10 = as_element(slave_block(3, 0, 1, 2), CellType::Tet10);
  const auto hex27 = as_element(slave_block(3, 0, 1, 2), CellType::Hex27);
  const auto with = [](double alpha) {
    MortarOptions o;
    o.vertex_share = alpha;
    return o;
  };
  EXPECT_THROW(MortarPair(hex20, "zmin", master, "zmax", with(0.12)), Error);
  EXPECT_NO_THROW(MortarPair(hex20, "zmin", master, "zmax", with(0.13)));
  EXPECT_THROW(MortarPair(tet10, "zmin", master, "zmax", with(0.5)), Error);
  EXPECT_THROW(MortarPair(tet10, "zmin", master, "zmax", with(0.0)), Error);
  EXPECT_NO_THROW(MortarPair(tet10, "zmin", master, "zmax", with(0.01)));
  // Quad9 faces are not transformed: α is not used.
  EXPECT_NO_THROW(MortarPair(hex27, "zmin", master, "zmax", with(0.01)));
}

TEST(QuadraticMortarFaces, ASlaveSurfaceMixingQuad9AndQuad8IsRefused) {
  // A test of the refusal only: the first Quad9 face also listed as the Quad8 on its first
  // eight nodes.
  auto slave = as_element(slave_block(3, 0, 1, 2), CellType::Hex27);
  const auto faces = slave.boundary("zmin");
  for (const auto& f : faces) slave.add_facet("mixed", f);
  mesh::Facet quad8 = faces.front();
  quad8.type = mesh::FacetType::Quad8;
  quad8.nodes[8] = -1;
  slave.add_facet("mixed", quad8);
  const auto master = master_block(3, 0, 1, 2);
  EXPECT_THROW(MortarPair(slave, "mixed", master, "zmax"), MeshError);
  EXPECT_NO_THROW(MortarPair(slave, "zmin", master, "zmax"));
}

// ---------------------------------------------------------------------------------------------
// The contact patch test (mortar_patch_test.cpp) on second-order surfaces: two blocks on
// rollers, the upper pressed down by δ at its top, the lower held at its bottom; frictionless
// and quasistatic, the state is uniaxial, σ = −M δ/(h₁ + h₂) (M = E in 3D, E/(1 − ν²) in plane
// strain), which every element here reproduces exactly. The multipliers λ_k = p at every slave
// node: B_sᵀλ = ∫(Σλ_kψ_k)φ_j is then ∫pφ_j, the consistent load, since Σψ_k = 1.

struct PatchCase {
  int dim;
  CellType upper, lower;
  MultiplierBasis basis;
  double alpha = contact::kVertexShare;  // MortarOptions::vertex_share
  const char* tag = "";
};

class QuadraticPatch : public ::testing::TestWithParam<PatchCase> {};

TEST_P(QuadraticPatch, NonMatchingSurfacesCarryTheUniaxialPressureAtEverySlaveNode) {
  const auto [dim, upper_cell, lower_cell, basis, alpha, tag] = GetParam();
  const double delta = 1e-4;
  const auto point = [dim](double x, double z) {
    return dim == 3 ? mesh::Point{x, x, z} : mesh::Point{x, z, 0};
  };
  // 3 × 3 against 4 × 5 in 3D, 5 against 7 in 2D: no node of one surface on the other's.
  const std::array<int, 3> upper_cells = dim == 3 ? std::array{3, 3, 1} : std::array{5, 2, 1};
  const std::array<int, 3> lower_cells = dim == 3 ? std::array{4, 5, 2} : std::array{7, 3, 1};
  Block upper =
      make_block(dim, point(0, 1), point(1, 1.5), upper_cells, top(dim), -delta, "", upper_cell);
  Block lower =
      make_block(dim, point(0, 0), point(1, 1), lower_cells, bottom(dim), 0.0, "", lower_cell);
  MortarOptions options{basis, 0.0};
  options.vertex_share = alpha;
  const MortarPair pair(upper.mesh, bottom(dim), lower.mesh, top(dim), options);
  ASSERT_EQ(pair.contact_nodes().size(), upper.mesh.boundary_nodes(bottom(dim)).size());

  physics::DualContactSettings settings;
  settings.qp.rtol = 1e-12;
  physics::DualContactSolver solver(*upper.solver, *lower.solver, upper.u_prescribed.size(),
                                    lower.u_prescribed.size(), settings);
  solver.set_rows(pair.rows());
  const auto us = free_solution(upper), um = free_solution(lower);
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
  // As in mortar_patch_test.cpp: the QP's ‖g^P‖ ≤ 1e-12‖d‖ amplified by cond(F), 1e-8.
  double worst = 0;
  for (size_t k = 0; k < pair.contact_nodes().size(); ++k) {
    worst = std::max(worst, std::abs(l[dim * k] - pressure) / pressure);
    EXPECT_NEAR(l[dim * k], pressure, 1e-8 * pressure) << "contact node " << k;
    for (int t = 1; t < dim; ++t) EXPECT_EQ(l[dim * k + t], 0.0);
  }
  std::printf(
      "[ measure  ] quadratic patch %s on %s (%s, α = %.4f): max |λ_k − p|/p = %.2e, %d QP "
      "iterations, %zu contact nodes\n",
      mesh::name(upper_cell), mesh::name(lower_cell), contact::name(basis), alpha, worst,
      r.iterations, pair.contact_nodes().size());
  // The bodies touch without penetrating: B_n u = c_n at every node (all active).
  core::Vector bu(solver.rows().n_rows());
  solver.rows().slave.mult(u_s, bu);
  solver.rows().master.mult_add(u_m, bu);
  const auto b = bu.to_std();
  for (size_t k = 0; k < pair.contact_nodes().size(); ++k)
    EXPECT_NEAR(b[dim * k], c[dim * k], 1e-8 * delta * pair.weights()[k]);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, QuadraticPatch,
    ::testing::Values(PatchCase{2, CellType::Quad8, CellType::Quad8, MultiplierBasis::dual},
                      PatchCase{2, CellType::Quad9, CellType::Quad4, MultiplierBasis::dual},
                      PatchCase{2, CellType::Quad4, CellType::Tri6, MultiplierBasis::dual},
                      PatchCase{2, CellType::Tri6, CellType::Quad9, MultiplierBasis::standard},
                      PatchCase{3, CellType::Hex20, CellType::Hex20, MultiplierBasis::dual},
                      PatchCase{3, CellType::Hex27, CellType::Hex8, MultiplierBasis::dual},
                      PatchCase{3, CellType::Tet10, CellType::Hex20, MultiplierBasis::dual},
                      PatchCase{3, CellType::Hex8, CellType::Tet10, MultiplierBasis::dual},
                      PatchCase{3, CellType::Hex20, CellType::Hex27, MultiplierBasis::standard},
                      PatchCase{3, CellType::Tet10, CellType::Hex20, MultiplierBasis::dual,
                                1.0 / 12, "_alpha_1_12"},
                      PatchCase{3, CellType::Tet10, CellType::Hex20, MultiplierBasis::dual, 0.25,
                                "_alpha_1_4"},
                      PatchCase{3, CellType::Hex20, CellType::Hex20, MultiplierBasis::dual, 1.0 / 6,
                                "_alpha_1_6"},
                      PatchCase{3, CellType::Hex20, CellType::Hex20, MultiplierBasis::dual,
                                5.0 / 16, "_alpha_5_16"}),
    [](const auto& info) {
      return std::to_string(info.param.dim) + "d_" + mesh::name(info.param.upper) + "_on_" +
             mesh::name(info.param.lower) + "_" + contact::name(info.param.basis) + info.param.tag;
    });

}  // namespace
}  // namespace tc::test
