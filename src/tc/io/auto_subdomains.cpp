#include "tc/io/auto_subdomains.hpp"

#include <algorithm>
#include <cmath>

namespace tc::io {

double direct_memory(int dim, double u_dofs) {
  if (dim == 2)  // 181 k dofs: 0.83 GB, 722 k: 3.36 GB; nested dissection fills as n log n
    return 4.6e3 * u_dofs * std::log2(std::max(u_dofs, 2.0)) / std::log2(181202.0);
  // 3D: 27.8 k dofs 0.57 GB, 108 k 2.94 GB, of which 1.1 GB the factor; the rest grows as the
  // dofs, the factor as dofs^1.31 (bench/assembly: 10 k … 556 k dofs).
  return 1.65e4 * u_dofs + 1.1e9 * std::pow(u_dofs / 107811.0, 1.31);
}

int auto_subdomains(int dim, double u_dofs, double budget) {
  if (budget <= 0 || direct_memory(dim, u_dofs) <= budget) return 1;
  return std::max(2, static_cast<int>(std::ceil(u_dofs / kDofsPerSubdomain)));
}

}  // namespace tc::io
