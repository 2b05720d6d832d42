#include "tc/io/auto_subdomains.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "tc/core/petsc.hpp"

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

double decomposed_memory(int dim, double u_dofs) {
  const double parts = std::max(2.0, std::ceil(u_dofs / kDofsPerSubdomain));
  return parts * direct_memory(dim, u_dofs / parts);
}

std::vector<int> auto_subdomains(int dim, const std::vector<double>& u_dofs, double budget,
                                 int factor_ranks) {
  std::vector<int> out(u_dofs.size(), 1);
  std::vector<double> need(u_dofs.size());
  for (size_t i = 0; i < u_dofs.size(); ++i) need[i] = direct_memory(dim, u_dofs[i], factor_ranks);
  std::vector<size_t> largest(u_dofs.size());
  std::iota(largest.begin(), largest.end(), size_t{0});
  std::stable_sort(largest.begin(), largest.end(),
                   [&](size_t a, size_t b) { return u_dofs[a] > u_dofs[b]; });
  for (const size_t i : largest) {
    if (budget <= 0 || std::accumulate(need.begin(), need.end(), 0.0) <= budget) break;
    out[i] = static_cast<int>(std::max(2.0, std::ceil(u_dofs[i] / kDofsPerSubdomain)));
    need[i] = decomposed_memory(dim, u_dofs[i]);
  }
  return out;
}

double auto_budget(int dim, const std::vector<double>& direct_u_dofs, int factor_ranks) {
  double fixed = 0;
  for (const double dofs : direct_u_dofs) fixed += direct_memory(dim, dofs, factor_ranks);
  const double budget = kMemoryShare * memory_per_rank() - fixed;
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
