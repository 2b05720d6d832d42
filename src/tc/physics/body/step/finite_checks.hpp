#pragma once
// NaN and Inf caught where they arise, each named with the phase that produced it
// (docs/robustness.md): the assembly and the initial state, and the vectors of the steps (the
// contact rows of a step: finite_rows, physics/contact/contact_rows_builder.hpp).
#include <memory>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/physics/body/body_field.hpp"
#include "tc/physics/body/body_system.hpp"

namespace tc::physics {

/// Throws NumericalError naming the phase of `what` (heat step, mechanical step, contact QP)
/// when v has a NaN or an Inf.
void require_finite(const core::Vector& v, const char* what, int step, int iteration);

/// Throws NumericalError when a body's matrices or initial state are not finite.
void check_setup_finite(const std::vector<std::unique_ptr<BodySystem>>& systems,
                        const std::vector<BodyState>& states);

}  // namespace tc::physics
