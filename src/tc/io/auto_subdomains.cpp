#include "tc/io/auto_subdomains.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

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

}  // namespace tc::io
