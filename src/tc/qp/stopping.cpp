#include "tc/qp/stopping.hpp"

#include <algorithm>
#include <cmath>

#include "tc/core/numeric/petsc_blocks.hpp"
#include "tc/core/verify.hpp"

namespace tc::qp {

Vector free_part(const Vector& d, const FeasibleSet& set) {
  Vector out = d.clone();
  set.zero_fixed(out);
  return out;
}

std::optional<Vector> group_weights(const Vector& d, const std::vector<int>& groups) {
  if (groups.empty()) return std::nullopt;
  const auto rd = d.read();
  const auto dv = rd.span();
  TC_VERIFY(groups.size() == dv.size(), "a group for each of this rank's rows");
  int n = 0;
  for (const int g : groups) n = std::max(n, g + 1);
  TC_MPI(MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_INT, MPI_MAX, d.comm()));
  std::vector<double> squares(static_cast<size_t>(n), 0.0);
  for (size_t i = 0; i < dv.size(); ++i) squares[static_cast<size_t>(groups[i])] += dv[i] * dv[i];
  TC_MPI(MPI_Allreduce(MPI_IN_PLACE, squares.data(), n, MPI_DOUBLE, MPI_SUM, d.comm()));
  double all = 0;
  for (const double q : squares) all += q;
  const double norm = std::sqrt(all);
  std::vector<double> weight(static_cast<size_t>(n), 1.0);
  for (size_t g = 1; g < weight.size(); ++g)
    if (squares[g] > 0)
      weight[g] = std::max(1.0, norm / std::max(std::sqrt(squares[g]), 1e-6 * norm));
  if (std::all_of(weight.begin(), weight.end(), [](double w) { return w == 1.0; }))
    return std::nullopt;
  Vector w = d.duplicate();
  auto wv = w.view();
  for (size_t i = 0; i < dv.size(); ++i) wv[i] = weight[static_cast<size_t>(groups[i])];
  return w;
}

}  // namespace tc::qp
