#pragma once
// The contact multipliers from one step to the next: step k+1's QP starts from λ^k moved onto
// its rows (warm start).
#include <array>
#include <vector>

#include "tc/contact/contact_rows.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/record/checkpoint.hpp"

namespace tc::physics {

/// What the multipliers of the last step refer to: their slave mesh nodes and, with a 3D
/// mortar pair, the tangents their λ_τ are components in.
class MultiplierTransfer {
 public:
  /// Moves λ of the last step (`lambda` on entry, on the last step's rows) onto `rows`, node
  /// by node: by slave mesh node when the rows name them (the contact nodes of a mortar pair
  /// change as bodies slide), else by position while the count holds; zero elsewhere.
  /// `mortar`: the pair whose tangents the rows use (null for a test's rows).
  void warm_start(const contact::ContactRows& rows, const contact::MortarPair* mortar,
                  core::Vector& lambda);

  /// The pair's lambda_nodes and lambda_tangents in the checkpoint, and back.
  void save(Checkpoint::Pair& c) const;
  void restore(const Checkpoint::Pair& c);
  /// The contact nodes the last warm start left λ on.
  [[nodiscard]] size_t n_nodes() const { return nodes_.size(); }

 private:
  std::vector<int> nodes_;                          // slave mesh node of each contact node
  std::vector<std::array<double, 3>> tangents_[2];  // the tangents λ_τ refers to (3D mortar)
};

}  // namespace tc::physics
