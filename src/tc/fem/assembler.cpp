// Global assembly (thesis 4.1, 4.3, 4.4): element kernels scattered into PETSc AIJ matrices
// whose nonzero pattern is known exactly from the node graph, so PETSc never reallocates.
#include "tc/fem/assembler.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "tc/core/error.hpp"
#include "tc/core/numeric/collective.hpp"
#include "tc/core/verify.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::fem {

namespace {

// PETSc's MatSetValues takes the element block row by row.
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Gauss–Legendre points and weights on [0, 1] with 4 points (exact to degree 7).
constexpr double kGauss4X[] = {0.06943184420297371, 0.33000947820757187, 0.66999052179242813,
                               0.93056815579702629};
constexpr double kGauss4W[] = {0.17392742256872693, 0.32607257743127307, 0.32607257743127307,
                               0.17392742256872693};

/// Rules of higher order than quadrature(t), for measuring errors of smooth exact solutions
/// without the superconvergence of the 2-point Gauss points polluting the observed H1 order:
/// 4^d tensor Gauss on Quad4/Hex8, and the same collapsed onto the simplex (Duffy) for
/// Tri3/Tet4, exact to degree 7 (Quad4, Hex8), 6 (Tri3), 5 (Tet4); a second-order type takes
/// its corner type's rule (the squared error of a quadratic field has degree 4).
std::vector<QuadraturePoint> error_rule(CellType t) {
  std::vector<QuadraturePoint> out;
  const int d = mesh::dimension(t);
  const int n3 = d == 3 ? 4 : 1;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < n3; ++k) {
        const double s = kGauss4X[i], r = kGauss4X[j], q = d == 3 ? kGauss4X[k] : 0.0;
        const double w = kGauss4W[i] * kGauss4W[j] * (d == 3 ? kGauss4W[k] : 1.0);
        QuadraturePoint p;
        switch (mesh::corner_type(t)) {
          case CellType::Quad4:  // [0,1]² → [−1,1]², Jacobian 4
            p = {{2 * s - 1, 2 * r - 1, 0}, 4 * w};
            break;
          case CellType::Hex8:
            p = {{2 * s - 1, 2 * r - 1, 2 * q - 1}, 8 * w};
            break;
          case CellType::Tri3:  // (s, r) → (s, r(1 − s)), Jacobian 1 − s
            p = {{s, r * (1 - s), 0}, w * (1 - s)};
            break;
          case CellType::Tet4:  // (s, r, q) → (s, r(1−s), q(1−s)(1−r)), Jacobian (1−s)²(1−r)
            p = {{s, r * (1 - s), q * (1 - s) * (1 - r)}, w * (1 - s) * (1 - s) * (1 - r)};
            break;
          default:
            TC_VERIFY(false, "a corner type is of first order");
        }
        out.push_back(p);
      }
  return out;
}

}  // namespace

NodeGraph node_graph(const mesh::Mesh& m) {
  std::vector<std::vector<int>> adj(m.n_nodes());
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto nodes = m.cell(c);
    for (const int a : nodes) adj[a].insert(adj[a].end(), nodes.begin(), nodes.end());
  }
  NodeGraph g;
  g.offsets.reserve(m.n_nodes() + 1);
  g.offsets.push_back(0);
  for (auto& row : adj) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    g.columns.insert(g.columns.end(), row.begin(), row.end());
    g.offsets.push_back(static_cast<int>(g.columns.size()));
    std::vector<int>().swap(row);  // free as we go: the graph of a large mesh is big
  }
  return g;
}

namespace {

/// Adds every cell's kernel into `out` (this rank's cells when spread) and assembles it.
void add_cell_values(const mesh::Mesh& m, int row_block, int col_block, const CellKernel& kernel,
                     const core::RowBlocks* spread, core::SparseMatrix& out) {
  const auto add_cells = [&] {
    std::vector<PetscInt> rows, cols;
    RowMajor ke;
    for (int c = 0; c < m.n_cells(); ++c) {
      const auto nodes = m.cell(c);
      rows.clear();
      cols.clear();
      for (const int a : nodes) {
        for (int k = 0; k < row_block; ++k) rows.push_back(row_block * a + k);
        for (int k = 0; k < col_block; ++k) cols.push_back(col_block * a + k);
      }
      if (spread &&
          std::none_of(rows.begin(), rows.end(), [&](PetscInt r) { return spread->owns(r); }))
        continue;  // another rank's cell
      ke = kernel(c, m.cell_type(c), cell_coords(m, c));
      TC_VERIFY(ke.rows() == static_cast<Eigen::Index>(rows.size()) &&
                    ke.cols() == static_cast<Eigen::Index>(cols.size()),
                "the cell kernel's matrix matches the cell's dofs");
      out.add_values(rows, cols, ke.data());
    }
  };
  // Spread, a kernel that throws on one rank's cells (a bad cell) must stop every rank, not
  // leave the others in the assembly's communication.
  if (spread)
    core::collective_check(spread->comm, "assembly", add_cells);
  else
    add_cells();
  out.assemble();
}

}  // namespace

core::SparseMatrix assemble(const mesh::Mesh& m, const NodeGraph& g, int row_block, int col_block,
                            const CellKernel& kernel, const core::RowBlocks* spread,
                            const core::RowBlocks* spread_cols) {
  if (spread && !spread_cols) spread_cols = spread;  // square
  TC_VERIFY(!spread ||
                (spread->n == row_block * m.n_nodes() && spread_cols->n == col_block * m.n_nodes()),
            "the rows spread over the ranks are the mesh's dofs");
  core::SparseMatrix out;
  if (spread) {  // this rank's rows: entries in its block of columns and outside it
    const PetscInt first = spread->first(), end = first + spread->here();
    const PetscInt c0 = spread_cols->first(), c1 = c0 + spread_cols->here();
    std::vector<PetscInt> diagonal, off_diagonal;
    for (PetscInt row = first; row < end; ++row) {
      const int a = static_cast<int>(row / row_block);
      PetscInt in = 0;
      for (int e = g.offsets[a]; e < g.offsets[a + 1]; ++e)
        for (int k = 0; k < col_block; ++k) {
          const PetscInt col = static_cast<PetscInt>(col_block) * g.columns[e] + k;
          in += col >= c0 && col < c1 ? 1 : 0;
        }
      diagonal.push_back(in);
      off_diagonal.push_back(col_block * g.degree(a) - in);
    }
    out = core::SparseMatrix::over_ranks(*spread, *spread_cols, diagonal, off_diagonal);
  } else {
    std::vector<PetscInt> nnz(static_cast<size_t>(row_block) * m.n_nodes());
    for (int a = 0; a < m.n_nodes(); ++a)
      for (int k = 0; k < row_block; ++k) nnz[row_block * a + k] = col_block * g.degree(a);
    out = core::SparseMatrix(row_block * m.n_nodes(), col_block * m.n_nodes(), nnz);
  }
  add_cell_values(m, row_block, col_block, kernel, spread, out);
  return out;
}

void reassemble(const mesh::Mesh& m, int row_block, int col_block, const CellKernel& kernel,
                core::SparseMatrix& out, const core::RowBlocks* spread) {
  TC_PETSC(MatZeroEntries(out.get()));
  add_cell_values(m, row_block, col_block, kernel, spread, out);
}

void reassemble_mechanics(const mesh::Mesh& m, const CellModuli& cells, BodyMatrices& b,
                          const core::RowBlocks* spread, const core::RowBlocks* spread_theta) {
  // K_u and K_uθ with the same λ_c, μ_c of each cell: β_c = (3λ_c + 2μ_c)α is the
  // temperature derivative of the thermal stress C(θ)ε_th (2.5), so the thermoelastic
  // heating K_uθᵀu̇ stays the transpose of the thermal force's operator.
  const int d = m.dim();
  const auto at = [](const std::vector<double>& v, int c) { return v[static_cast<size_t>(c)]; };
  reassemble(
      m, d, d,
      [&](int c, CellType t, const Coords& x) {
        return stiffness_u(t, x, at(cells.lambda, c), at(cells.mu, c));
      },
      b.stiffness_u, spread);
  reassemble(
      m, d, 1,
      [&](int c, CellType t, const Coords& x) { return coupling_u_theta(t, x, at(cells.beta, c)); },
      b.coupling_u_theta, spread && spread_theta ? spread : nullptr);
}

BodyMatrices assemble_body(const mesh::Mesh& m, const Material& mat, const core::RowBlocks* spread,
                           const core::RowBlocks* spread_theta) {
  // (4.3), (4.4): one pass per matrix; the graph is shared, so each pattern is exact.
  const auto g = node_graph(m);
  const int d = m.dim();
  const double lambda = mat.lame_lambda(), mu = mat.lame_mu();
  const double beta = mat.thermal_stress_modulus();
  BodyMatrices b;
  b.mass_u = assemble(
      m, g, d, d, [&](int, CellType t, const Coords& x) { return mass_u(t, x, mat.density); },
      spread);
  b.stiffness_u = assemble(
      m, g, d, d, [&](int, CellType t, const Coords& x) { return stiffness_u(t, x, lambda, mu); },
      spread);
  b.coupling_u_theta = assemble(
      m, g, d, 1, [&](int, CellType t, const Coords& x) { return coupling_u_theta(t, x, beta); },
      spread && spread_theta ? spread : nullptr, spread_theta);
  b.mass_theta = assemble(
      m, g, 1, 1,
      [&](int, CellType t, const Coords& x) { return mass_theta(t, x, mat.heat_capacity()); },
      spread_theta);
  b.stiffness_theta = assemble(
      m, g, 1, 1,
      [&](int, CellType t, const Coords& x) {
        return stiffness_theta(t, x, mat.thermal_conductivity);
      },
      spread_theta);
  return b;
}

core::SparseMatrix singular_mass_u(const mesh::Mesh& m, const Material& mat,
                                   const std::vector<char>& massless,
                                   const core::RowBlocks* spread) {
  const int d = m.dim();
  return assemble(
      m, node_graph(m), d, d,
      [&](int c, CellType t, const Coords& x) {
        Eigen::MatrixXd me = mass_u(t, x, mat.density);
        const auto nodes = m.cell(c);
        const auto n = static_cast<Eigen::Index>(nodes.size());
        // P_e (node level): identity on massive nodes; a massless node follows the massive nodes
        // of the cell nearest to it (ties within 1e-9 share equally: the node above on a Hex8
        // whose face lies on the boundary, the free vertices of a Tet4).
        Eigen::MatrixXd p = Eigen::MatrixXd::Zero(n, n);
        bool any = false;
        for (Eigen::Index a = 0; a < n; ++a) {
          if (!massless[static_cast<size_t>(nodes[a])]) {
            p(a, a) = 1.0;
            continue;
          }
          any = true;
          double nearest = INFINITY;
          for (Eigen::Index b = 0; b < n; ++b)
            if (!massless[static_cast<size_t>(nodes[b])])
              nearest = std::min(nearest, (x.row(a) - x.row(b)).norm());
          if (!std::isfinite(nearest))
            throw Error(
                fmt::format("modified mass: cell {} has every node on the contact boundary; "
                            "it needs a node off it (refine the mesh across the boundary)",
                            c));
          std::vector<Eigen::Index> near;
          for (Eigen::Index b = 0; b < n; ++b)
            if (!massless[static_cast<size_t>(nodes[b])] &&
                (x.row(a) - x.row(b)).norm() <= nearest * (1 + 1e-9))
              near.push_back(b);
          for (const auto b : near) p(a, b) = 1.0 / static_cast<double>(near.size());
        }
        if (!any) return me;
        Eigen::MatrixXd pd = Eigen::MatrixXd::Zero(d * n, d * n);  // P_e ⊗ I_d (interleaved dofs)
        for (Eigen::Index a = 0; a < n; ++a)
          for (Eigen::Index b = 0; b < n; ++b)
            for (int k = 0; k < d; ++k) pd(d * a + k, d * b + k) = p(a, b);
        return Eigen::MatrixXd(pd.transpose() * me * pd);
      },
      spread);
}

core::SparseMatrix boundary_mass(const mesh::Mesh& m, const std::vector<WeightedFacet>& facets,
                                 const core::RowBlocks* spread) {
  std::vector<std::vector<const WeightedFacet*>> by_cell(static_cast<size_t>(m.n_cells()));
  for (const auto& f : facets) by_cell.at(static_cast<size_t>(f.facet.cell)).push_back(&f);
  return assemble(
      m, node_graph(m), 1, 1,
      [&](int c, CellType, const Coords&) {
        const auto nodes = m.cell(c);
        const auto n = static_cast<Eigen::Index>(nodes.size());
        Eigen::MatrixXd me = Eigen::MatrixXd::Zero(n, n);  // zeros keep the node graph's pattern
        for (const auto* f : by_cell[static_cast<size_t>(c)]) {
          const auto fn = f->facet.node_span();
          const Eigen::MatrixXd hf =
              f->weight * facet_mass(f->facet.type, facet_coords(m, f->facet));
          std::vector<Eigen::Index> local;
          for (const int a : fn) {
            const auto it = std::find(nodes.begin(), nodes.end(), a);
            if (it == nodes.end())
              throw Error(fmt::format("film: facet node {} is not a node of its cell {}", a, c));
            local.push_back(it - nodes.begin());
          }
          for (size_t i = 0; i < local.size(); ++i)
            for (size_t j = 0; j < local.size(); ++j)
              me(local[i], local[j]) +=
                  hf(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
        }
        return me;
      },
      spread);
}

void lump_rows(core::SparseMatrix& m) {
  // PETSc's row sums into a vector laid out as m's rows (each rank's own when m is spread).
  core::Handle<::Vec, VecDestroy> sums;
  TC_PETSC(MatCreateVecs(m.get(), nullptr, sums.out()));
  TC_PETSC(MatGetRowSum(m.get(), sums.get()));
  TC_PETSC(MatZeroEntries(m.get()));
  TC_PETSC(MatDiagonalSet(m.get(), sums.get(), INSERT_VALUES));
}

namespace {}  // namespace

bool lumps_by_row_sums(CellType t) {
  return t != CellType::Tri6 && t != CellType::Quad8 && t != CellType::Tet10 &&
         t != CellType::Hex20;
}

bool lumps_by_row_sums(const mesh::Mesh& m) {
  for (int c = 0; c < m.n_cells(); ++c)
    if (!lumps_by_row_sums(m.cell_type(c))) return false;
  return true;
}

std::vector<double> lumped_volumes(const mesh::Mesh& m) {
  if (lumps_by_row_sums(m)) return volume_integrals(m);
  std::vector<double> out(m.n_nodes(), 0.0);
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto t = m.cell_type(c);
    const auto x = cell_coords(m, c);
    const auto nodes = m.cell(c);
    if (lumps_by_row_sums(t)) {
      const auto v = cell_load(t, x);
      for (size_t a = 0; a < nodes.size(); ++a) out[nodes[a]] += v[static_cast<Eigen::Index>(a)];
      continue;
    }
    // HRZ: the consistent diagonal, scaled to the cell's volume Σ_ab (M_e)_ab (M_e of ρc = 1).
    const auto me = mass_theta(t, x, 1.0);
    const double scale = me.sum() / me.trace();
    for (size_t a = 0; a < nodes.size(); ++a) {
      const auto i = static_cast<Eigen::Index>(a);
      out[nodes[a]] += scale * me(i, i);
    }
  }
  return out;
}

void lump_heat_capacity(core::SparseMatrix& mass_theta, const mesh::Mesh& m, double heat_capacity) {
  if (lumps_by_row_sums(m)) return lump_rows(mass_theta);
  const auto v = lumped_volumes(m);
  core::Handle<::Vec, VecDestroy> diagonal;
  TC_PETSC(MatCreateVecs(mass_theta.get(), nullptr, diagonal.out()));
  PetscInt first = 0, end = 0;  // this rank's rows (all of them when whole)
  TC_PETSC(VecGetOwnershipRange(diagonal.get(), &first, &end));
  for (PetscInt row = first; row < end; ++row)
    TC_PETSC(VecSetValue(diagonal.get(), row, heat_capacity * v[static_cast<size_t>(row)],
                         INSERT_VALUES));
  TC_PETSC(VecAssemblyBegin(diagonal.get()));
  TC_PETSC(VecAssemblyEnd(diagonal.get()));
  TC_PETSC(MatZeroEntries(mass_theta.get()));
  TC_PETSC(MatDiagonalSet(mass_theta.get(), diagonal.get(), INSERT_VALUES));
}

std::vector<double> volume_integrals(const mesh::Mesh& m, const Func& f) {
  std::vector<double> out(m.n_nodes(), 0.0);
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto v = cell_load(m.cell_type(c), cell_coords(m, c), f);
    const auto nodes = m.cell(c);
    for (size_t a = 0; a < nodes.size(); ++a) out[nodes[a]] += v[a];
  }
  return out;
}

std::vector<double> boundary_integrals(const mesh::Mesh& m, const std::string& boundary,
                                       const Func& f) {
  std::vector<double> out(m.n_nodes(), 0.0);
  for (const auto& facet : m.boundary(boundary)) {
    const auto v = facet_load(facet.type, facet_coords(m, facet), f);
    const auto nodes = facet.node_span();
    for (size_t a = 0; a < nodes.size(); ++a) out[nodes[a]] += v[a];
  }
  return out;
}

ErrorNorms error_norms(const mesh::Mesh& m, std::span<const double> field, int components,
                       const std::function<double(const mesh::Point&, int)>& exact,
                       const std::function<Eigen::Vector3d(const mesh::Point&, int)>& exact_grad) {
  const std::vector<QuadraturePoint> rules[] = {
      error_rule(CellType::Tri3),  error_rule(CellType::Quad4), error_rule(CellType::Tet4),
      error_rule(CellType::Hex8),  error_rule(CellType::Tri6),  error_rule(CellType::Quad8),
      error_rule(CellType::Quad9), error_rule(CellType::Tet10), error_rule(CellType::Hex20),
      error_rule(CellType::Hex27)};
  const int d = m.dim();
  double l2 = 0, h1 = 0;
  Eigen::VectorXd n;
  Eigen::MatrixXd dn, grad;
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto t = m.cell_type(c);
    const auto x = cell_coords(m, c);
    const auto nodes = m.cell(c);
    for (const auto& q : rules[static_cast<int>(t)]) {
      shape(t, q.xi, n, dn);
      const Eigen::MatrixXd jac = x.transpose() * dn;  // J_ij = ∂x_i/∂ξ_j
      grad.noalias() = dn * jac.inverse();
      const double jxw = jac.determinant() * q.weight;
      mesh::Point p{0, 0, 0};
      for (Eigen::Index a = 0; a < x.rows(); ++a)
        for (int k = 0; k < d; ++k) p[k] += n[a] * x(a, k);
      for (int comp = 0; comp < components; ++comp) {
        double uh = 0;
        Eigen::Vector3d gh = Eigen::Vector3d::Zero();
        for (size_t a = 0; a < nodes.size(); ++a) {
          const double ua = field[static_cast<size_t>(components) * nodes[a] + comp];
          uh += n[a] * ua;
          gh.head(d) += ua * grad.row(static_cast<Eigen::Index>(a)).transpose();
        }
        const double e = uh - exact(p, comp);
        Eigen::Vector3d ge = gh - exact_grad(p, comp);
        if (d == 2) ge[2] = 0;  // the exact gradient's z entry is meaningless in 2D
        l2 += e * e * jxw;
        h1 += ge.squaredNorm() * jxw;
      }
    }
  }
  return {std::sqrt(l2), std::sqrt(h1)};
}

}  // namespace tc::fem
