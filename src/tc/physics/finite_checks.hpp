#pragma once
// NaN and Inf caught where they arise, each named with the phase that produced it
// (docs/robustness.md): the assembly and the initial state, the contact rows of a step, and
// the vectors of the steps.
#include <functional>
#include <memory>
#include <vector>

#include "tc/contact/contact_rows.hpp"
#include "tc/core/petsc.hpp"
#include "tc/physics/body_field.hpp"
#include "tc/physics/body_system.hpp"

namespace tc::physics {

/// The contact rows of a step (B_s, B_m, gap, nodal weights) from the displacements of the
/// slave and master at t^k: the configuration in which the constraints are linearised.
using ContactRowsBuilder =
    std::function<contact::ContactRows(const core::Vector& u_slave, const core::Vector& u_master)>;

/// Throws NumericalError naming the phase of `what` (heat step, mechanical step, contact QP)
/// when v has a NaN or an Inf.
void require_finite(const core::Vector& v, const char* what, int step, int iteration);

/// Throws NumericalError when a body's matrices or initial state are not finite.
void check_setup_finite(const std::vector<std::unique_ptr<BodySystem>>& systems,
                        const std::vector<BodyState>& states);

/// `builder` with its configuration and its rows checked for NaN/Inf; `step` is the number of
/// completed steps (read at each call, for the message).
[[nodiscard]] ContactRowsBuilder finite_rows(ContactRowsBuilder builder, const int& step);

}  // namespace tc::physics
