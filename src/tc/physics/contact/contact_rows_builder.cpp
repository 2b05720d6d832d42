#include "tc/physics/contact/contact_rows_builder.hpp"

#include <algorithm>
#include <cmath>

#include "tc/core/error.hpp"

namespace tc::physics {

ContactRowsBuilder finite_rows(ContactRowsBuilder builder, const int& step) {
  // The contact phase: the rows of the mortar pair (or of a test's builder) in the configuration
  // of t^k. A NaN there would reach the QP as a NaN operator and be reported as a failure to
  // converge; named here instead.
  return [&step, builder = std::move(builder)](const core::Vector& us, const core::Vector& um) {
    // A NaN position makes the mortar search find no overlap, not a NaN: checked before.
    if (!us.all_finite() || !um.all_finite())
      throw NumericalError(
          "contact: the configuration of t^k (u of the contact pair) is not finite (NaN or Inf)",
          step + 1, 0, std::nan(""));
    auto rows = builder(us, um);
    PetscReal ns = 0, nm = 0;
    if (rows.n_rows() > 0) {
      TC_PETSC(MatNorm(rows.slave.get(), NORM_FROBENIUS, &ns));
      TC_PETSC(MatNorm(rows.master.get(), NORM_FROBENIUS, &nm));
    }
    const auto finite = [](const std::vector<double>& x) {
      return std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
    };
    if (!finite(rows.gap) || !finite(rows.weights) || !std::isfinite(ns) || !std::isfinite(nm))
      throw NumericalError(
          "contact: the mortar rows (B, gap, weights) in the configuration of t^k are not finite "
          "(NaN or Inf)",
          step + 1, 0, std::nan(""));
    return rows;
  };
}

}  // namespace tc::physics
