#include "tc/io/case/auto_subdomains.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "tc/core/heap.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/mesh/box.hpp"
#include "tc/mesh/mesh.hpp"

namespace tc::io {

double direct_memory(int dim, double u_dofs, int factor_ranks) {
  if (dim == 2)  // 181 k dofs: 0.53 GB, 722 k: 2.22 GB; nested dissection fills as n log n
    return 2.93e3 * u_dofs * std::log2(std::max(u_dofs, 2.0)) / std::log2(181202.0);
  // 3D: the factor, 1.1 GB at 108 k dofs (bench/assembly), grows as dofs^1.31; the rest (the
  // matrices, the vectors) as the dofs: 27.8 k dofs 0.38 GB, 108 k 1.74 GB measured. Over
  // ranks, each holds its share of the factor and of the body's matrices: M_u and K_u (81
  // entries of 12 bytes a row each), K_uθ (27 a row), M_θ, K_θ and A_θ (27 a row of a third
  // as many rows): 2.6 kB of the 5.9 kB per dof; the rest whole.
  const double ranks = std::max(factor_ranks, 1);
  return (5.9e3 - 2.6e3 * (1.0 - 1.0 / ranks)) * u_dofs +
         1.1e9 * std::pow(u_dofs / 107811.0, 1.31) / ranks;
}

Pattern operator_pattern(const mesh::Mesh& mesh, int block) {
  // The nodes sharing a cell with each node, then each node's dofs' upper rows.
  const int n = mesh.n_nodes();
  std::vector<std::vector<int>> near(static_cast<size_t>(n));
  for (int c = 0; c < mesh.n_cells(); ++c) {
    const auto cell = mesh.cell(c);
    for (const int a : cell)
      for (const int b : cell)
        if (b >= a) near[static_cast<size_t>(a)].push_back(b);
  }
  Pattern p;
  p.start.reserve(static_cast<size_t>(n) * block + 1);
  p.start.push_back(0);
  for (int a = 0; a < n; ++a) {
    auto& row = near[static_cast<size_t>(a)];
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    for (int k = 0; k < block; ++k) {
      for (const int b : row)
        for (int l = b == a ? k : 0; l < block; ++l) p.column.push_back(block * b + l);
      p.start.push_back(static_cast<int>(p.column.size()));
    }
    std::vector<int>().swap(row);
  }
  return p;
}

namespace {

// Bytes of an AIJ matrix with `entries` nonzeros over `rows` rows: a double and an index per
// entry, and PETSc's four arrays of one index per row (i, ilen, imax, diag).
double aij_bytes(double entries, double rows) {
  return 12.0 * entries + 16.0 * rows;
}

// The same for a matrix on another's index arrays (core::share_pattern): its values, and the
// row lengths PETSc keeps per row.
double shared_aij_bytes(double entries, double rows) {
  return 8.0 * entries + 16.0 * rows;
}

// What the direct path holds for a body of n nodes whose node pattern (its upper triangle) has
// `upper` entries, besides its factors: K_u (dim² blocks), M_u without its zeros between
// components (dim entries a node pair: core::drop_zeros; on K_u's indices with the stabilised
// contact scheme, 8 bytes instead of 12 on dim² instead of dim entries: this counts less),
// K_uθ (dim rows a node), K_θ and M_θ on its indices, A_θ, and some thirty vectors of the
// body's fields (body_field.hpp).
double matrices_bytes(int dim, double n, double upper) {
  const double full = 2.0 * upper - n;  // the node pattern's entries, both triangles
  return aij_bytes(dim * dim * full, dim * n) + aij_bytes(dim * full, dim * n) +
         aij_bytes(dim * full, dim * n) + 2.0 * aij_bytes(full, n) + shared_aij_bytes(full, n) +
         8.0 * 16.0 * (dim + 1.0) * n;
}

struct Analysed {
  linalg::FactorAnalysis mech, heat;
  double matrices = 0;   // matrices_bytes
  double transient = 0;  // the mechanical factorisation's copy of A_u's triangle and its work
};

Analysed analyse(const mesh::Mesh& mesh, int dim) {
  Analysed out;
  const double n = mesh.n_nodes();
  {
    const auto nodes = operator_pattern(mesh, 1);
    out.heat = linalg::analyse_cholesky(nodes.start, nodes.column);
    out.matrices = matrices_bytes(dim, n, static_cast<double>(nodes.column.size()));
  }
  const auto dofs = operator_pattern(mesh, dim);
  out.mech = linalg::analyse_cholesky(dofs.start, dofs.column);
  // Held at once besides what stays, while A_u is factorised: linalg::CholmodFactor's copy of
  // its triangle (a double and an index per entry, an index per column) and CHOLMOD's update
  // block. (The dynamic scheme's initial acceleration runs CG on M_u itself, its supports
  // masked: a few vectors, no copy of M_u.)
  const double triangle = static_cast<double>(dofs.column.size());
  out.transient = 12.0 * triangle + 4.0 * dim * n + out.mech.work_bytes;
  return out;
}

double solve_seconds(const linalg::FactorAnalysis& f) {
  return 2.0 * f.bytes / kSolveBytesPerSecond;  // a forward and a backward pass over L
}

}  // namespace

BodyCosts body_costs(const mesh::Mesh& mesh, int dim, int factor_ranks, double compliance_columns) {
  BodyCosts c;
  const double n = mesh.n_nodes();
  c.u_dofs = dim * n;
  c.parts = static_cast<int>(std::max(2.0, std::ceil(c.u_dofs / kDofsPerSubdomain)));
  // A subdomain as a box of n / parts nodes, as even in every direction as the body allows.
  const int side = std::max(2, static_cast<int>(std::lround(std::pow(n / c.parts, 1.0 / dim))));
  const std::array<int, 3> cells{side - 1, side - 1, dim == 3 ? side - 1 : 1};
  const auto sub = analyse(mesh::make_box(dim, {0, 0, 0}, {1, 1, 1}, cells), dim);
  const double rhs = kSolvesPerStep + compliance_columns;
  c.feti_step_seconds = rhs * kFetiIterations * c.parts * solve_seconds(sub.mech);
  c.feti_setup_seconds = c.parts * (sub.mech.flops + sub.heat.flops) / kFactorFlopsPerSecond;
  if (factor_ranks == 1 && c.u_dofs <= kMaxAnalysedDofs) {
    const auto a = analyse(mesh, dim);
    // The pattern and CHOLMOD's work of the analysis would stay resident all run otherwise,
    // under the factors to come (0.6 GiB at 10⁶ dofs).
    core::release_free_heap();
    c.analysed = true;
    c.mech = a.mech;
    c.heat = a.heat;
    c.direct_bytes = a.matrices + kFactorOverhead * (a.mech.bytes + a.heat.bytes) + a.transient;
    c.factor_seconds = (a.mech.flops + a.heat.flops) / kFactorFlopsPerSecond;
    c.direct_step_seconds = kSolvesPerStep * (solve_seconds(a.mech) + solve_seconds(a.heat));
    // FETI keeps the body's whole matrices too (BodySystem) and the subdomains' factors.
    c.feti_bytes =
        a.matrices + c.parts * (sub.matrices + kFactorOverhead * (sub.mech.bytes + sub.heat.bytes));
  } else {
    // Beyond the analysis (or over ranks, where MUMPS factorises): the fit, and the flops of
    // nested dissection on a 3D body's n dofs, n², as linalg::CholeskySolver counts them.
    c.direct_bytes = direct_memory(dim, c.u_dofs, factor_ranks);
    c.factor_seconds = c.u_dofs * c.u_dofs / kFactorFlopsPerSecond;
    c.direct_step_seconds =
        kSolvesPerStep * 2.0 * (c.direct_bytes - 5.9e3 * c.u_dofs) / kSolveBytesPerSecond;
    c.feti_bytes = c.parts * direct_memory(dim, c.u_dofs / c.parts);
  }
  return c;
}

SubdomainChoice choose_subdomains(const std::vector<BodyCosts>& bodies, double budget, int steps) {
  SubdomainChoice out;
  const size_t n = bodies.size();
  out.subdomains.assign(n, 1);
  out.reasons.assign(n, "");
  std::vector<double> need(n);
  for (size_t i = 0; i < n; ++i) need[i] = bodies[i].direct_bytes;
  const auto run = [steps](double once, double per_step) { return once + steps * per_step; };
  const auto direct_run = [&](const BodyCosts& b) {
    return run(b.factor_seconds, b.direct_step_seconds);
  };
  const auto feti_run = [&](const BodyCosts& b) {
    return run(b.feti_setup_seconds, b.feti_step_seconds);
  };
  std::vector<size_t> largest(n);
  std::iota(largest.begin(), largest.end(), size_t{0});
  std::stable_sort(largest.begin(), largest.end(),
                   [&](size_t a, size_t b) { return bodies[a].u_dofs > bodies[b].u_dofs; });
  std::vector<char> too_large(n, 0);
  for (const size_t i : largest) {
    if (budget <= 0 || std::accumulate(need.begin(), need.end(), 0.0) <= budget) break;
    too_large[i] = 1;
    need[i] = bodies[i].feti_bytes;
  }
  // Where both fit, FETI only if faster over the run.
  for (size_t i = 0; i < n; ++i) {
    const auto& b = bodies[i];
    const bool faster = feti_run(b) < direct_run(b);
    if (!too_large[i] && faster && budget > 0) {
      const double sum = std::accumulate(need.begin(), need.end(), 0.0);
      if (sum - need[i] + b.feti_bytes <= budget) too_large[i] = 2, need[i] = b.feti_bytes;
    }
    if (too_large[i]) out.subdomains[i] = b.parts;
    const auto why = too_large[i] == 1   ? "the direct path does not fit"
                     : too_large[i] == 2 ? "FETI is faster"
                     : budget <= 0       ? "the machine's memory is unknown"
                     : faster            ? "FETI would be faster but does not fit"
                                         : "the direct path fits and is faster";
    out.reasons[i] = fmt::format(
        "direct {:.1f} GiB, factorisation {:.0f} s, {:.2g} s a step; FETI ({} subdomains) "
        "{:.1f} GiB, {:.2g} s a step; {} steps: {}{}",
        b.direct_bytes / kGiB, b.factor_seconds, b.direct_step_seconds, b.parts,
        b.feti_bytes / kGiB, b.feti_step_seconds, steps, why,
        b.analysed ? " (CHOLMOD's analysis of its pattern)" : " (fitted, not analysed)");
  }
  return out;
}

double auto_budget(double fixed) {
  const double budget = kMemoryShare * memory_per_rank() - kBaseBytes - fixed;
  return memory_per_rank() > 0 ? std::max(budget, 1.0) : 0.0;
}

double box_memory(int dim, const std::array<int, 3>& cells) {
  double nodes = 1, n_cells = 1;
  for (int k = 0; k < dim; ++k) nodes *= cells[k] + 1.0, n_cells *= cells[k];
  const double per_row = dim == 3 ? 27 : 9;           // nodes coupled to a node
  const double blocks = 2.0 * dim * dim + dim + 2.0;  // scalar blocks of the five matrices
  const double corners = dim == 3 ? 8 : 4;
  return nodes * (per_row * blocks * 12.0 + per_row * 4.0 + 24.0) + n_cells * (corners + 2) * 4.0;
}

double physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? static_cast<double>(pages) * static_cast<double>(size) : 0.0;
}

double memory_per_rank() {
  return physical_memory() / static_cast<double>(std::max(core::PetscSession::node_size(), 1));
}

std::string shared_by_ranks() {
  const int n = core::PetscSession::node_size();
  return n > 1 ? fmt::format(" shared by {} ranks", n) : std::string();
}

}  // namespace tc::io
