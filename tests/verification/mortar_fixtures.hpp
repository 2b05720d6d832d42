#pragma once
// Blocks for the mortar tests, header-only: a slave block on top of a master block (the
// slave's bottom face against the master's top face), non-matching divisions, seeded in-plane
// jitter of the interface nodes, bending of the interface, and helpers to read the matrices.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "tc/contact/mortar_pair.hpp"
#include "tc/mesh/box.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::test {

using Rotation = std::array<std::array<double, 3>, 3>;
using contact::operator+;
using contact::operator-;
using contact::operator*;

/// The mesh with every point replaced by f(node, point); cells and boundaries are kept.
inline mesh::Mesh moved(const mesh::Mesh& m,
                        const std::function<mesh::Point(int, const mesh::Point&)>& f) {
  mesh::Mesh out(m.dim());
  for (int j = 0; j < m.n_nodes(); ++j) out.add_point(f(j, m.point(j)));
  for (int c = 0; c < m.n_cells(); ++c) out.add_cell(m.cell_type(c), m.cell(c));
  for (const auto& name : m.boundary_names())
    for (const auto& facet : m.boundary(name)) out.add_facet(name, facet);
  return out;
}

/// Moves the nodes of `boundary` that are not on its rim by a seeded uniform offset in
/// [−amplitude, amplitude] along the in-plane axes (x in 2D; x and y in 3D, or only y when
/// `only_y`). The interface stays planar; its outline is unchanged.
inline mesh::Mesh jitter(const mesh::Mesh& m, const std::string& boundary, double amplitude,
                         std::uint32_t seed, bool only_y = false) {
  const int d = m.dim();
  mesh::Point lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const auto nodes = m.boundary_nodes(boundary);
  for (const int j : nodes)
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], m.point(j)[i]);
      hi[i] = std::max(hi[i], m.point(j)[i]);
    }
  std::vector<char> on(m.n_nodes(), 0);
  for (const int j : nodes) on[j] = 1;
  std::mt19937 rng(seed);
  auto uniform = [&] { return amplitude * (2.0 * rng() / 4294967295.0 - 1.0); };
  return moved(m, [&](int j, const mesh::Point& p) {
    mesh::Point q = p;
    if (!on[j]) return q;
    for (int i = 0; i < d - 1; ++i) {
      const double shift = uniform();  // drawn for every axis: same stream with or without only_y
      const bool rim = std::abs(p[i] - lo[i]) < 1e-12 || std::abs(p[i] - hi[i]) < 1e-12;
      if (!rim && !(only_y && i == 0)) q[i] += shift;
    }
    return q;
  });
}

/// Moves whole grid lines: every in-plane coordinate value of a structured box (other than
/// the extreme ones) is shifted by a seeded uniform offset in [−amplitude, amplitude], the same
/// for all nodes that share it. Rectangles stay rectangles (affine facets) of random sizes.
inline mesh::Mesh jitter_lines(const mesh::Mesh& m, double amplitude, std::uint32_t seed) {
  const int d = m.dim();
  std::mt19937 rng(seed);
  std::vector<std::map<double, double>> shift(d - 1);  // axis: coordinate value → offset
  for (int i = 0; i < d - 1; ++i) {
    for (const auto& p : m.points()) shift[i][p[i]] = 0;
    const auto first = shift[i].begin()->first, last = shift[i].rbegin()->first;
    for (auto& [value, offset] : shift[i])
      if (value != first && value != last) offset = amplitude * (2.0 * rng() / 4294967295.0 - 1.0);
  }
  return moved(m, [&](int, const mesh::Point& p) {
    mesh::Point q = p;
    for (int i = 0; i < d - 1; ++i) q[i] += shift[i].at(p[i]);
    return q;
  });
}

/// Bends a mesh: the vertical coordinate (y in 2D, z in 3D) gains amplitude·sin(2x) [+ in 3D
/// with `doubly`: amplitude·cos(1.5y)]. Applied to both blocks, the interface becomes a curved
/// surface discretised differently on the two sides.
inline mesh::Mesh bend(const mesh::Mesh& m, double amplitude, bool doubly = false) {
  const int v = m.dim() - 1;
  return moved(m, [&](int, const mesh::Point& p) {
    mesh::Point q = p;
    q[v] += amplitude * std::sin(2 * p[0]);
    if (doubly) q[v] += amplitude * std::cos(1.5 * p[1]);
    return q;
  });
}

/// The slave block [lo, hi] × [0, 1] (2D) or [lo, hi]² × [0, 1] (3D) raised by `gap`, with
/// n cells per in-plane axis and one layer; the contact face is ymin / zmin.
inline mesh::Mesh slave_block(int dim, double lo, double hi, int n, double gap = 0, double lo_y = 0,
                              double hi_y = 0) {
  if (hi_y <= lo_y) lo_y = lo, hi_y = hi;
  return dim == 2 ? mesh::make_box(2, {lo, gap, 0}, {hi, 1 + gap, 0}, {n, 1, 1})
                  : mesh::make_box(3, {lo, lo_y, gap}, {hi, hi_y, 1 + gap}, {n, n, 1});
}
/// The master block below: [lo, hi] × [−1, 0] (2D) or [lo, hi]² × [−1, 0]; contact face ymax /
/// zmax.
inline mesh::Mesh master_block(int dim, double lo, double hi, int n, double lo_y = 0,
                               double hi_y = 0) {
  if (hi_y <= lo_y) lo_y = lo, hi_y = hi;
  return dim == 2 ? mesh::make_box(2, {lo, -1, 0}, {hi, 0, 0}, {n, 1, 1})
                  : mesh::make_box(3, {lo, lo_y, -1}, {hi, hi_y, 0}, {n, n, 1});
}
inline std::string bottom(int dim) {
  return dim == 2 ? "ymin" : "zmin";
}
inline std::string top(int dim) {
  return dim == 2 ? "ymax" : "zmax";
}

/// A copy of a 3D box whose boundary `from` is also available as `name` with every
/// `every`-th Quad4 split into two Tri3 (same orientation): every = 1 gives an all-triangle
/// surface, 2 a mixed Tri3/Quad4 one.
inline mesh::Mesh with_triangles(mesh::Mesh m, const std::string& from, const std::string& name,
                                 int every) {
  int i = 0;
  for (const auto& f : m.boundary(from)) {
    if (i++ % every != every - 1) {
      m.add_facet(name, f);
      continue;
    }
    const auto& q = f.nodes;
    m.add_facet(name, {mesh::FacetType::Tri3, {q[0], q[1], q[2], -1}, f.cell});
    m.add_facet(name, {mesh::FacetType::Tri3, {q[0], q[2], q[3], -1}, f.cell});
  }
  return m;
}

/// The entries of a sequential PETSc matrix.
inline std::map<std::pair<PetscInt, PetscInt>, double> entries(const core::SparseMatrix& a) {
  std::map<std::pair<PetscInt, PetscInt>, double> out;
  for (PetscInt r = 0; r < a.rows(); ++r) {
    PetscInt n = 0;
    const PetscInt* cols = nullptr;
    const double* vals = nullptr;
    TC_PETSC(MatGetRow(a.get(), r, &n, &cols, &vals));
    for (PetscInt i = 0; i < n; ++i) out[{r, cols[i]}] = vals[i];
    TC_PETSC(MatRestoreRow(a.get(), r, &n, &cols, &vals));
  }
  return out;
}

/// The rows of a mortar pair equal reference rows (gaps, weights and both B blocks) entry by
/// entry to `tol` absolute.
inline void expect_same_rows(const contact::ContactRows& rows, const contact::ContactRows& ref,
                             double tol) {
  for (size_t k = 0; k < ref.gap.size(); ++k) {
    EXPECT_NEAR(rows.gap[k], ref.gap[k], tol) << k;
    EXPECT_NEAR(rows.weights[k], ref.weights[k], tol) << k;
  }
  for (const auto which : {&contact::ContactRows::slave, &contact::ContactRows::master}) {
    const auto a = entries(rows.*which), b = entries(ref.*which);
    for (const auto& [ij, v] : b) EXPECT_NEAR(a.count(ij) ? a.at(ij) : 0.0, v, tol);
    for (const auto& [ij, v] : a) EXPECT_NEAR(b.count(ij) ? b.at(ij) : 0.0, v, tol);
  }
}

inline double sum_of(const core::SparseMatrix& a) {
  double s = 0;
  for (const auto& [ij, v] : entries(a)) s += v;
  return s;
}

/// y = A x for a sequential matrix and std::vectors.
inline std::vector<double> times(const core::SparseMatrix& a, const std::vector<double>& x) {
  core::Vector xv = core::Vector::from(x), yv(a.rows());
  a.mult(xv, yv);
  return yv.to_std();
}

/// Area of the slave surface: Σ over facets of ∫|x_ξ × x_η| by 8 × 8 Gauss (exact for planar
/// facets, accurate to ~1e-15 for the mildly warped ones of the tests); length in 2D.
inline double surface_area(const mesh::Mesh& m, const std::string& boundary) {
  static const double g[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                              -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                              0.7966664774136267,  0.9602898564975363};
  static const double w[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                              0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                              0.2223810344533745, 0.1012285362903763};
  double area = 0;
  for (const auto& f : m.boundary(boundary)) {
    // A second-order facet by its corners: exact for straight edges with mid-edge nodes at
    // their midpoints, as the tests' are.
    const auto corners = mesh::corner_type(f.type);
    const auto& x0 = m.point(f.nodes[0]);
    const auto& x1 = m.point(f.nodes[1]);
    if (corners == mesh::FacetType::Line2) {
      area += std::hypot(x1[0] - x0[0], x1[1] - x0[1]);
      continue;
    }
    const auto& x2 = m.point(f.nodes[2]);
    if (corners == mesh::FacetType::Tri3) {
      const contact::Vec3 c = contact::cross(x1 - x0, x2 - x0);
      area += 0.5 * contact::norm(c);
      continue;
    }
    const auto& x3 = m.point(f.nodes[3]);
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) {
        const double xi = g[i], eta = g[j];
        const contact::Vec3 dx = 0.25 * ((1 - eta) * (x1 - x0) + (1 + eta) * (x2 - x3));
        const contact::Vec3 dy = 0.25 * ((1 - xi) * (x3 - x0) + (1 + xi) * (x2 - x1));
        area += w[i] * w[j] * contact::norm(contact::cross(dx, dy));
      }
  }
  return area;
}

/// Checks Σ_ij D_ij = Σ_ij M_ij = Σ_k weight_k = overlap_area() = area, relative `tol`.
inline void expect_sums(const contact::MortarPair& p, double area, double tol) {
  double w = 0;
  for (const double x : p.weights()) w += x;
  if (std::getenv("TC_MORTAR_VERBOSE"))
    std::printf("sums: D %.2e M %.2e weights %.2e (relative)\n",
                std::abs(sum_of(p.d_matrix()) - area) / area,
                std::abs(sum_of(p.m_matrix()) - area) / area, std::abs(w - area) / area);
  EXPECT_NEAR(sum_of(p.d_matrix()), area, tol * area);
  EXPECT_NEAR(sum_of(p.m_matrix()), area, tol * area);
  EXPECT_NEAR(w, area, tol * area);
  EXPECT_NEAR(p.overlap_area(), area, tol * area);
}

/// max_k |(D⁻¹ M f_m)_k − f(x_k^s)| / max |f| for a linear f over the contact nodes, and
/// cond₂(D). D is solved densely on the contact nodes' columns; entries of D in the columns of
/// slave nodes that are not contact nodes (standard basis, a node whose weight fell below the
/// threshold) multiply known values and move to the right-hand side: D_cc f_c = M f_m − D_cn f_n.
struct Transfer {
  double error = 0, cond = 1;
  /// The solve with D loses up to cond(D) ulps; at least 1e-12 is asked for.
  [[nodiscard]] double tolerance() const { return std::max(1e-12, 1e-15 * cond); }
};
inline Transfer transfer(const contact::MortarPair& p, const mesh::Mesh& slave,
                         const mesh::Mesh& master,
                         const std::function<double(const mesh::Point&)>& f) {
  std::vector<double> fm(master.n_nodes());
  for (int j = 0; j < master.n_nodes(); ++j) fm[j] = f(master.point(j));
  auto rhs = times(p.m_matrix(), fm);
  const auto& nodes = p.contact_nodes();
  const Eigen::Index n = static_cast<Eigen::Index>(nodes.size());
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, n);
  for (const auto& [ij, v] : entries(p.d_matrix())) {
    const int col = p.contact_index(static_cast<int>(ij.second));
    if (col >= 0)
      d(ij.first, col) += v;
    else
      rhs[ij.first] -= v * f(slave.point(static_cast<int>(ij.second)));
  }
  const Eigen::VectorXd fs =
      d.partialPivLu().solve(Eigen::Map<const Eigen::VectorXd>(rhs.data(), n));
  double err = 0, scale = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double exact = f(slave.point(nodes[k]));
    err = std::max(err, std::abs(fs(k) - exact));
    scale = std::max(scale, std::abs(exact));
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(d);
  const Transfer t{err / scale, svd.singularValues()(0) / svd.singularValues()(n - 1)};
  if (std::getenv("TC_MORTAR_VERBOSE"))
    std::printf("transfer error %.2e, cond(D) %.2e\n", t.error, t.cond);
  return t;
}

/// max_k |g_k − δ weight_k| / (δ max_k weight_k).
inline double gap_error(const contact::MortarPair& p, double delta) {
  struct Report {
    double err = 0;
    ~Report() {
      if (std::getenv("TC_MORTAR_VERBOSE")) std::printf("gap error %.2e\n", err);
    }
  };
  double err = 0, wmax = 0;
  for (size_t k = 0; k < p.gap().size(); ++k) {
    err = std::max(err, std::abs(p.gap()[k] - delta * p.weights()[k]));
    wmax = std::max(wmax, p.weights()[k]);
  }
  return Report{err / (delta * wmax)}.err;
}

inline Rotation rotation(const contact::Vec3& axis_in, double angle) {
  const contact::Vec3 a = contact::normalized(axis_in);
  const double c = std::cos(angle), s = std::sin(angle);
  Rotation r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = (1 - c) * a[i] * a[j] + (i == j ? c : 0.0);
  r[0][1] -= s * a[2];
  r[0][2] += s * a[1];
  r[1][0] += s * a[2];
  r[1][2] -= s * a[0];
  r[2][0] -= s * a[1];
  r[2][1] += s * a[0];
  return r;
}

inline contact::Vec3 rotate(const Rotation& r, const contact::Vec3& v) {
  contact::Vec3 out{};
  for (int i = 0; i < 3; ++i) out[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2];
  return out;
}

}  // namespace tc::test
