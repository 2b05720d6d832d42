// The second-order reference cells (mesh/reference_cell.hpp), their quadrature rules and
// kernels (fem/element.hpp) and the second-order box (mesh/box.hpp), against closed forms:
//  - shape functions: N_a(ξ_b) = δ_ab, Σ N_a = 1, and every complete quadratic polynomial
//    reproduced (P2 ⊂ span{N_a} for Lagrange and serendipity alike); gradients against
//    central differences;
//  - local faces: their nodes lie where the face's own shape functions put them, and their
//    normals point out of the cell;
//  - quadrature: monomials integrated exactly up to the rule's degree;
//  - kernels: ∫ρ over a cell and the kinetic energy of a rigid rotation, exact.
// Tolerances: everything is exact in exact arithmetic, with O(1) values and at most ~10³
// operations, so 1e-12 bounds rounding; the central differences (step 1e-5) have truncation
// error ~h² · |N'''| ≲ 1e-9, hence 1e-8 there. A wrong node order, sign or weight misses by
// O(0.1) or more.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "tc/fem/assembler.hpp"
#include "tc/fem/element.hpp"
#include "tc/mesh/box.hpp"
#include "tc/mesh/reference_cell.hpp"

using namespace tc;
using mesh::CellType;
using mesh::FacetType;

namespace {

constexpr CellType kSecondOrder[] = {CellType::Tri6,  CellType::Quad8, CellType::Quad9,
                                     CellType::Tet10, CellType::Hex20, CellType::Hex27};

/// A point inside every reference cell (the simplex and [−1, 1]^d alike).
mesh::Point inner_point(int dim) {
  return {0.21, 0.17, dim == 3 ? 0.13 : 0.0};
}

double quadratic(const mesh::Point& x) {
  return 0.3 + 1.1 * x[0] - 0.7 * x[1] + 0.4 * x[2] + 0.9 * x[0] * x[0] - 1.3 * x[0] * x[1] +
         0.5 * x[1] * x[1] + 0.8 * x[1] * x[2] - 0.6 * x[2] * x[2] + 0.2 * x[0] * x[2];
}

}  // namespace

TEST(ReferenceCell, ShapeFunctionsAreNodalAndReproduceQuadratics) {
  for (const auto t : kSecondOrder) {
    const int nn = mesh::n_nodes(t), d = mesh::dimension(t);
    std::vector<double> n(nn), dn(3 * nn);
    for (int b = 0; b < nn; ++b) {
      mesh::shape_functions(t, mesh::reference_node(t, b), n.data(), dn.data());
      for (int a = 0; a < nn; ++a)
        EXPECT_NEAR(n[a], a == b ? 1.0 : 0.0, 1e-12) << mesh::name(t) << " N_" << a << " at " << b;
    }
    const auto xi = inner_point(d);
    mesh::shape_functions(t, xi, n.data(), dn.data());
    double sum = 0, interpolated = 0;
    for (int a = 0; a < nn; ++a) {
      sum += n[a];
      interpolated += n[a] * quadratic(mesh::reference_node(t, a));
    }
    EXPECT_NEAR(sum, 1.0, 1e-12) << mesh::name(t);
    EXPECT_NEAR(interpolated, quadratic(xi), 1e-12) << mesh::name(t);
    // Gradients against central differences of the values.
    const double h = 1e-5;
    std::vector<double> np(nn), nm(nn), scratch(3 * nn);
    for (int k = 0; k < d; ++k) {
      auto xp = xi, xm = xi;
      xp[k] += h;
      xm[k] -= h;
      mesh::shape_functions(t, xp, np.data(), scratch.data());
      mesh::shape_functions(t, xm, nm.data(), scratch.data());
      for (int a = 0; a < nn; ++a)
        EXPECT_NEAR(dn[3 * a + k], (np[a] - nm[a]) / (2 * h), 1e-8)
            << mesh::name(t) << " dN_" << a << "/dξ_" << k;
    }
  }
}

TEST(ReferenceCell, FacetShapeFunctionsAreNodal) {
  for (const auto t : {FacetType::Line3, FacetType::Tri6, FacetType::Quad8, FacetType::Quad9}) {
    const int nn = mesh::n_nodes(t);
    std::vector<double> n(nn), dn(3 * nn);
    for (int b = 0; b < nn; ++b) {
      mesh::shape_functions(t, mesh::reference_node(t, b), n.data(), dn.data());
      for (int a = 0; a < nn; ++a) EXPECT_NEAR(n[a], a == b ? 1.0 : 0.0, 1e-12) << mesh::name(t);
    }
  }
}

TEST(ReferenceCell, LocalFacesAreConsistentAndOutward) {
  for (const auto t : kSecondOrder) {
    const int d = mesh::dimension(t);
    mesh::Point centre{0, 0, 0};
    for (int a = 0; a < mesh::n_nodes(t); ++a)
      for (int k = 0; k < 3; ++k) centre[k] += mesh::reference_node(t, a)[k] / mesh::n_nodes(t);
    ASSERT_EQ(mesh::local_faces(t).size(), mesh::local_faces(mesh::corner_type(t)).size());
    for (const auto& f : mesh::local_faces(t)) {
      const int nf = mesh::n_nodes(f.type);
      EXPECT_EQ(mesh::order(f.type), 2) << mesh::name(t);
      // Node k of the face is where the face's map x(η) = Σ_j N_j(η) x_j puts its reference
      // node k: this holds only if the mid-edge (and centre) nodes are the right ones.
      std::vector<double> n(nf), dn(3 * nf);
      for (int k = 0; k < nf; ++k) {
        mesh::shape_functions(f.type, mesh::reference_node(f.type, k), n.data(), dn.data());
        // The corners' map: the face's first-order shape functions on its corners.
        const auto lin = mesh::corner_type(f.type);
        const int nc = mesh::n_nodes(lin);
        std::vector<double> nl(nc), dnl(3 * nc);
        mesh::shape_functions(lin, mesh::reference_node(f.type, k), nl.data(), dnl.data());
        mesh::Point expected{0, 0, 0};
        for (int j = 0; j < nc; ++j)
          for (int c = 0; c < 3; ++c) expected[c] += nl[j] * mesh::reference_node(t, f.v[j])[c];
        const auto got = mesh::reference_node(t, f.v[k]);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(got[c], expected[c], 1e-12) << mesh::name(t) << " face node " << k;
      }
      // Outward: the corners' normal (2D: the edge turned clockwise) points away from the centre.
      const auto p0 = mesh::reference_node(t, f.v[0]), p1 = mesh::reference_node(t, f.v[1]);
      double normal[3];
      if (d == 2) {
        normal[0] = p1[1] - p0[1];
        normal[1] = -(p1[0] - p0[0]);
        normal[2] = 0;
      } else {
        const auto p2 = mesh::reference_node(t, f.v[2]);
        const double u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        const double v[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        normal[0] = u[1] * v[2] - u[2] * v[1];
        normal[1] = u[2] * v[0] - u[0] * v[2];
        normal[2] = u[0] * v[1] - u[1] * v[0];
      }
      double out = 0;
      for (int c = 0; c < 3; ++c) out += normal[c] * (p0[c] - centre[c]);
      EXPECT_GT(out, 0.0) << mesh::name(t);
    }
  }
}

namespace {

double factorial(int n) {
  return n <= 1 ? 1.0 : n * factorial(n - 1);
}

/// ∫ ξ^i η^j ζ^k over the reference cell of t: the unit simplex (i! j! k! / (i + j + k + d)!)
/// or [−1, 1]^d (Π 2/(p + 1) for even p, 0 for odd).
double exact_monomial(CellType t, int i, int j, int k) {
  const int d = mesh::dimension(t);
  const auto c = mesh::corner_type(t);
  if (c == CellType::Tri3 || c == CellType::Tet4)
    return factorial(i) * factorial(j) * factorial(k) / factorial(i + j + k + d);
  const auto one = [](int p) { return p % 2 ? 0.0 : 2.0 / (p + 1); };
  return one(i) * one(j) * (d == 3 ? one(k) : 1.0);
}

}  // namespace

TEST(Quadrature, SecondOrderRulesAreExactToTheirDegree) {
  for (const auto t : kSecondOrder) {
    const int d = mesh::dimension(t);
    const auto c = mesh::corner_type(t);
    const bool simplex = c == CellType::Tri3 || c == CellType::Tet4;
    // Simplices: total degree 4 (Tri6's rule) or 5 (Tet10's); tensor cells: degree 5 per
    // direction (3-point Gauss).
    const int degree = t == CellType::Tet10 ? 5 : simplex ? 4 : 5;
    for (int i = 0; i <= degree; ++i)
      for (int j = 0; j <= degree; ++j)
        for (int k = 0; k <= (d == 3 ? degree : 0); ++k) {
          if (simplex && i + j + k > degree) continue;
          double sum = 0;
          for (const auto& q : fem::quadrature(t))
            sum += q.weight * std::pow(q.xi[0], i) * std::pow(q.xi[1], j) *
                   (d == 3 ? std::pow(q.xi[2], k) : 1.0);
          EXPECT_NEAR(sum, exact_monomial(t, i, j, k), 1e-14)
              << mesh::name(t) << " x^" << i << " y^" << j << " z^" << k;
        }
  }
}

TEST(Kernels, MassOfASecondOrderCellIsExact) {
  // A parallelogram (prism) cell: affine, so ∫ρ = ρ|K| and the kinetic energy of the rigid
  // rotation v = ω × x is ½ρω²∫(x² + y²), both integrands of degree ≤ 2 in x and exact.
  for (const auto t : kSecondOrder) {
    const int d = mesh::dimension(t);
    auto m = mesh::make_box(d, {0, 0, 0}, {2, 1, 0.5}, {1, 1, 1}, t);
    // Shear the box x ← x + 0.3 y + 0.2 z (affine; volume kept).
    std::array<std::array<double, 3>, 3> shear{{{1, 0.3, 0.2}, {0, 1, 0}, {0, 0, 1}}};
    m.transform(shear, {0.1, -0.2, d == 3 ? 0.3 : 0.0});
    const double volume = d == 2 ? 2.0 : 1.0, rho = 7800;
    double mass = 0, area = 0, kinetic = 0;
    for (int c = 0; c < m.n_cells(); ++c) {
      EXPECT_EQ(m.cell_type(c), t);
      const auto x = fem::cell_coords(m, c);
      const Eigen::MatrixXd mu = fem::mass_u(t, x, rho);
      Eigen::VectorXd v(mu.rows());  // ω = e_z: v = (−y, x, 0)
      for (Eigen::Index a = 0; a < x.rows(); ++a) {
        v[d * a] = -x(a, 1);
        v[d * a + 1] = x(a, 0);
        if (d == 3) v[d * a + 2] = 0;
      }
      kinetic += 0.5 * v.dot(mu * v);
      mass += mu.sum() / d;
      area += mesh::cell_measure(m, c);
    }
    // ∫(x'² + y'²) independently: 3-point Gauss (exact to degree 5) on the unsheared box
    // [0, 2] × [0, 1] (× [0, 0.5]), the shear having unit Jacobian.
    const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    double inertia = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < (d == 3 ? 3 : 1); ++k) {
          const double x = 1 + g[i], y = 0.5 * (1 + g[j]), z = d == 3 ? 0.25 * (1 + g[k]) : 0;
          const double xs = x + 0.3 * y + 0.2 * z + 0.1, ys = y - 0.2;
          inertia += w[i] * w[j] * (d == 3 ? w[k] * 0.25 : 1.0) * 0.5 * (xs * xs + ys * ys);
        }
    EXPECT_NEAR(mass, rho * volume, 1e-12 * rho * volume) << mesh::name(t);
    EXPECT_NEAR(area, volume, 1e-12) << mesh::name(t);
    EXPECT_NEAR(kinetic, 0.5 * rho * inertia, 1e-12 * rho * inertia) << mesh::name(t);
  }
}

TEST(Kernels, LumpedHeatCapacityIsPositiveAndKeepsTheVolume) {
  // fem::lumped_volumes on a sheared 2×2(×2) box of each second-order cell: every node's share
  // is positive (row sums ∫N_a are ≤ 0 at Tri6, Quad8, Tet10 and Hex20 corners, so those cells
  // take HRZ's scaled diagonal), and the shares add up to the volume (each cell keeps its own):
  // exact in exact arithmetic, ~10² additions of O(1) numbers, so 1e-12. Where row sums are
  // positive (Quad9, Hex27) they are volume_integrals bit for bit, so runs keep their histories.
  for (const auto t : kSecondOrder) {
    const int d = mesh::dimension(t);
    auto m = mesh::make_box(d, {0, 0, 0}, {2, 1, 0.5}, {2, 2, 2}, t);
    std::array<std::array<double, 3>, 3> shear{{{1, 0.3, 0.2}, {0, 1, 0}, {0, 0, 1}}};
    m.transform(shear, {0, 0, 0});
    const double volume = d == 2 ? 2.0 : 1.0;
    const auto v = fem::lumped_volumes(m);
    double sum = 0;
    for (const double x : v) {
      EXPECT_GT(x, 0) << mesh::name(t);
      sum += x;
    }
    EXPECT_NEAR(sum, volume, 1e-12) << mesh::name(t);
    const bool row_sums = t == CellType::Quad9 || t == CellType::Hex27;
    const auto integrals = fem::volume_integrals(m);
    double lowest = 1;
    for (const double x : integrals) lowest = std::min(lowest, x);
    if (row_sums) {
      EXPECT_EQ(v, integrals) << mesh::name(t);
    } else {
      EXPECT_LE(lowest, 0) << mesh::name(t);  // why HRZ: row sums would not do
    }
  }
}
