#pragma once
// The scale of MPGP's stopping test ‖g^P‖ ≤ max(rtol ‖d‖, atol) (docs/choices.md, "Stopping
// and breakdown"): d on the components free to move, and the weights of the rows' groups.
#include <optional>
#include <vector>

#include "tc/qp/sets.hpp"

namespace tc::qp {

/// d with the components whose set is one point zeroed (FeasibleSet::zero_fixed).
[[nodiscard]] Vector free_part(const Vector& d, const FeasibleSet& set);

/// The stopping test's weights (QpOptions::row_groups): 1 on group 0, ‖d‖/max(‖d_G‖,
/// 1e-6‖d‖) but at least 1 on each other group G; none when every weight is 1. Collective.
[[nodiscard]] std::optional<Vector> group_weights(const Vector& d, const std::vector<int>& groups);

}  // namespace tc::qp
