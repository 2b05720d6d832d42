#pragma once
// Meshes for the fem tests, header-only: simplex splits of structured boxes (conforming,
// positively oriented, boundaries carried over), seeded perturbation of interior nodes, and a
// direct solve with every boundary dof prescribed (symmetric elimination).
#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/mesh/box.hpp"
#include "tc/mesh/mesh.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::test {

namespace detail {

inline bool contains(std::span<const int> nodes, int n) {
  return std::find(nodes.begin(), nodes.end(), n) != nodes.end();
}

/// Signed volume of the tetrahedron (p0, p1, p2, p3) times 6.
inline double tet_volume6(const mesh::Point& p0, const mesh::Point& p1, const mesh::Point& p2,
                          const mesh::Point& p3) {
  const double a[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
  const double b[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
  const double c[3] = {p3[0] - p0[0], p3[1] - p0[1], p3[2] - p0[2]};
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

}  // namespace detail

/// Splits every Quad4 (a, b, c, d) of a 2D mesh along a–c into (a, b, c) and (a, c, d): both
/// counter-clockwise like the quad, and conforming since the cut is interior to each quad.
/// Triangle 2q + {0, 1} comes from quad q; boundary edges keep their nodes, their `cell` is
/// the triangle holding both nodes.
inline mesh::Mesh split_quads(const mesh::Mesh& m) {
  mesh::Mesh out(2);
  for (const auto& p : m.points()) out.add_point(p);
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto q = m.cell(c);
    const int t0[3] = {q[0], q[1], q[2]}, t1[3] = {q[0], q[2], q[3]};
    out.add_cell(mesh::CellType::Tri3, t0);
    out.add_cell(mesh::CellType::Tri3, t1);
  }
  for (const auto& name : m.boundary_names())
    for (auto f : m.boundary(name)) {
      const int t = 2 * f.cell;
      f.cell =
          (detail::contains(out.cell(t), f.nodes[0]) && detail::contains(out.cell(t), f.nodes[1]))
              ? t
              : t + 1;
      out.add_facet(name, f);
    }
  return out;
}

/// Splits every Hex8 of a structured 3D box into the 6 Kuhn tetrahedra along its diagonal
/// 0–6, one per path 000 → 111 along the unit steps in permuted axis order. The split is the
/// same in every cell, so the diagonals of shared faces agree (conforming). Node order is
/// fixed on the reference cube so that every tet has positive volume; tet 6h + {0..5} comes
/// from hex h. Each boundary Quad4 becomes two Tri3 with the quad's (outward) orientation.
inline mesh::Mesh split_hexes(const mesh::Mesh& m) {
  // VTK Hex8 index of the reference corner (ix, iy, iz).
  const auto corner = [](int ix, int iy, int iz) {
    constexpr int kBottom[4] = {0, 1, 3, 2};  // ix + 2 iy → counter-clockwise bottom face
    return kBottom[ix + 2 * iy] + 4 * iz;
  };
  std::vector<std::array<int, 4>> local;  // the 6 tets in local hex node indices
  std::array<int, 3> axes{0, 1, 2};
  do {
    std::array<int, 3> at{0, 0, 0};
    std::array<int, 4> tet{};
    std::array<mesh::Point, 4> ref{};
    tet[0] = corner(0, 0, 0);
    for (int s = 0; s < 3; ++s) {
      at[axes[s]] = 1;
      tet[s + 1] = corner(at[0], at[1], at[2]);
      ref[s + 1] = {double(at[0]), double(at[1]), double(at[2])};
    }
    if (detail::tet_volume6(ref[0], ref[1], ref[2], ref[3]) < 0) std::swap(tet[1], tet[2]);
    local.push_back(tet);
  } while (std::next_permutation(axes.begin(), axes.end()));

  mesh::Mesh out(3);
  for (const auto& p : m.points()) out.add_point(p);
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto h = m.cell(c);
    for (const auto& t : local) {
      const int nodes[4] = {h[t[0]], h[t[1]], h[t[2]], h[t[3]]};
      out.add_cell(mesh::CellType::Tet4, nodes);
    }
  }
  for (const auto& name : m.boundary_names())
    for (const auto& f : m.boundary(name)) {
      // The tets of the owner with three nodes on this face; their nodes taken in the quad's
      // cyclic order keep its orientation.
      for (int t = 6 * f.cell; t < 6 * f.cell + 6; ++t) {
        mesh::Facet tri;
        tri.type = mesh::FacetType::Tri3;
        tri.cell = t;
        int k = 0;
        for (int a = 0; a < 4; ++a)
          if (detail::contains(out.cell(t), f.nodes[a]) && k < 3) tri.nodes[k++] = f.nodes[a];
        if (k == 3) out.add_facet(name, tri);
      }
    }
  return out;
}

/// Sorted nodes lying on any named boundary.
inline std::vector<int> all_boundary_nodes(const mesh::Mesh& m) {
  std::set<int> s;
  for (const auto& name : m.boundary_names())
    for (const int n : m.boundary_nodes(name)) s.insert(n);
  return {s.begin(), s.end()};
}

/// Moves every interior node (on no boundary) by a seeded uniform random offset in
/// [−amplitude, amplitude] per coordinate (x, y in 2D). Portable: only mt19937's raw output is
/// used, so the mesh is the same with every standard library.
inline mesh::Mesh perturb(const mesh::Mesh& m, double amplitude, std::uint32_t seed = 42) {
  const auto boundary = all_boundary_nodes(m);
  std::mt19937 gen(seed);
  const auto uniform = [&] { return 2.0 * (gen() / 4294967296.0) - 1.0; };
  mesh::Mesh out(m.dim());
  for (int i = 0; i < m.n_nodes(); ++i) {
    mesh::Point p = m.point(i);
    const bool interior = !std::binary_search(boundary.begin(), boundary.end(), i);
    for (int k = 0; k < m.dim(); ++k) {
      const double shift = amplitude * uniform();  // drawn always: same stream for every node
      if (interior) p[k] += shift;
    }
    out.add_point(p);
  }
  for (int c = 0; c < m.n_cells(); ++c) out.add_cell(m.cell_type(c), m.cell(c));
  for (const auto& name : m.boundary_names())
    for (const auto& f : m.boundary(name)) out.add_facet(name, f);
  return out;
}

/// Solves K x = f with x[i] = g[i] on the `fixed` dofs, eliminating them symmetrically
/// (f ← f − K g, then rows and columns of K zeroed with 1 on the diagonal), by Cholesky.
inline std::vector<double> solve_dirichlet(const core::SparseMatrix& k, std::vector<double> f,
                                           const std::vector<PetscInt>& fixed,
                                           const std::vector<double>& g) {
  const PetscInt n = k.rows();
  std::vector<double> g_full(static_cast<size_t>(n), 0.0);
  for (size_t i = 0; i < fixed.size(); ++i) g_full[fixed[i]] = g[i];
  core::Vector gv = core::Vector::from(g_full), kg(n);
  k.mult(gv, kg);
  const auto kg_std = kg.to_std();
  for (PetscInt i = 0; i < n; ++i) f[i] -= kg_std[i];
  for (size_t i = 0; i < fixed.size(); ++i) f[fixed[i]] = g[i];
  core::SparseMatrix a = k.copy();
  a.zero_rows_columns(fixed, 1.0);
  const linalg::CholeskySolver solver(a);
  core::Vector b = core::Vector::from(f), x(n);
  solver.solve(b, x);
  return x.to_std();
}

/// Box mesh of the given type on [0,1]^d with n cells per axis (simplices by splitting; the
/// second-order types by make_box).
inline mesh::Mesh unit_box(mesh::CellType t, int n) {
  const int d = mesh::dimension(t);
  if (mesh::order(t) == 2) return mesh::make_box(d, {0, 0, 0}, {1, 1, 1}, {n, n, n}, t);
  auto m = mesh::make_box(d, {0, 0, 0}, {1, 1, 1}, {n, n, n});
  if (t == mesh::CellType::Tri3) return split_quads(m);
  if (t == mesh::CellType::Tet4) return split_hexes(m);
  return m;
}

}  // namespace tc::test
