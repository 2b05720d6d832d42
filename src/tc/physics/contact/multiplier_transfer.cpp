#include "tc/physics/contact/multiplier_transfer.hpp"

#include <algorithm>
#include <map>

namespace tc::physics {

void MultiplierTransfer::warm_start(const contact::ContactRows& rows,
                                    const contact::MortarPair* mortar, core::Vector& lambda) {
  const int dim = rows.dim;
  const std::vector<double> previous = lambda.get() ? lambda.to_std() : std::vector<double>{};
  lambda = core::Vector(rows.n_rows());
  auto lv = lambda.view();
  // The mortar pair's tangents of a node may turn from one step to the next (measured on
  // example 06: 0.19 rad per step on average, up to π/2, the basis of the tangent plane being
  // arbitrary): λ_τ is carried over as the traction vector Σ_l λ_τ,l t_l, in the new basis.
  const bool turn = mortar && dim == 3 && !tangents_[0].empty();
  if (!rows.nodes.empty() && !nodes_.empty()) {
    std::map<int, size_t> where;
    for (size_t k = 0; k < nodes_.size(); ++k) where[nodes_[k]] = k;
    for (size_t k = 0; k < rows.nodes.size(); ++k)
      if (const auto it = where.find(rows.nodes[k]); it != where.end()) {
        const size_t j = it->second;
        for (int i = 0; i < dim; ++i) lv[dim * k + i] = previous[dim * j + i];
        if (!turn || k >= mortar->tangents(0).size()) continue;
        std::array<double, 3> traction{0, 0, 0};
        for (int l = 0; l < 2; ++l)
          for (int x = 0; x < 3; ++x) traction[x] += previous[dim * j + 1 + l] * tangents_[l][j][x];
        for (int l = 0; l < 2; ++l) {
          const auto& t = mortar->tangents(l)[k];
          lv[dim * k + 1 + l] = traction[0] * t[0] + traction[1] * t[1] + traction[2] * t[2];
        }
      }
  } else if (static_cast<PetscInt>(previous.size()) == rows.n_rows()) {
    for (PetscInt i = 0; i < rows.n_rows(); ++i) lv[i] = previous[i];
  }
  nodes_ = rows.nodes;
  if (mortar && dim == 3)
    for (int l = 0; l < 2; ++l) tangents_[l] = mortar->tangents(l);
}

void MultiplierTransfer::save(Checkpoint::Pair& c) const {
  c.lambda_nodes = nodes_;
  for (const auto& tl : tangents_)
    for (const auto& t : tl) c.lambda_tangents.insert(c.lambda_tangents.end(), t.begin(), t.end());
}

void MultiplierTransfer::restore(const Checkpoint::Pair& c) {
  nodes_ = c.lambda_nodes;
  const size_t per_basis = c.lambda_tangents.size() / 6;  // nodes with two tangents of 3
  for (int l = 0; l < 2; ++l) {
    tangents_[l].resize(per_basis);
    for (size_t k = 0; k < per_basis; ++k)
      for (int x = 0; x < 3; ++x)
        tangents_[l][k][x] = c.lambda_tangents[3 * (l * per_basis + k) + x];
  }
}

}  // namespace tc::physics
