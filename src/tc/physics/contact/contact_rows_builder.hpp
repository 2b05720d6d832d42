#pragma once
// Where a step's contact rows come from: the mortar pair in the configuration of t^k (or a
// test's builder), checked for NaN and Inf before the QP sees them (docs/robustness.md).
#include <functional>

#include "tc/contact/contact_rows.hpp"
#include "tc/core/numeric/petsc.hpp"

namespace tc::physics {

/// The contact rows of a step (B_s, B_m, gap, nodal weights) from the displacements of the
/// slave and master at t^k: the configuration in which the constraints are linearised.
using ContactRowsBuilder =
    std::function<contact::ContactRows(const core::Vector& u_slave, const core::Vector& u_master)>;

/// `builder` with its configuration and its rows checked for NaN/Inf; `step` is the number of
/// completed steps (read at each call, for the message).
[[nodiscard]] ContactRowsBuilder finite_rows(ContactRowsBuilder builder, const int& step);

}  // namespace tc::physics
