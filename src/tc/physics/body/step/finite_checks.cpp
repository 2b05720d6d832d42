#include "tc/physics/body/step/finite_checks.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string_view>

#include "tc/core/error.hpp"

namespace tc::physics {

namespace {

/// The phase that produced a quantity, for the message (docs/robustness.md).
const char* phase_of(std::string_view what) {
  if (what == "temperature") return "heat step (5.6)";
  if (what == "displacement") return "mechanical step (5.3)";
  if (what.starts_with("u =") || what == "contact multiplier") return "contact QP (6.9)";
  return "bookkeeping";
}

}  // namespace

void require_finite(const core::Vector& v, const char* what, int step, int iteration) {
  if (!v.all_finite())
    throw NumericalError(fmt::format("{}: {} is not finite (NaN or Inf)", phase_of(what), what),
                         step, iteration, std::nan(""));
}

void check_setup_finite(const std::vector<std::unique_ptr<BodySystem>>& systems,
                        const std::vector<BodyState>& states) {
  // NaN/Inf out of the assembly (material values at the ends of double's range) or the initial
  // state: refused before the first step, where they would otherwise surface as a failed solve.
  auto finite = [](const core::SparseMatrix& m) {
    PetscReal norm = 0;
    TC_PETSC(MatNorm(m.get(), NORM_FROBENIUS, &norm));
    return std::isfinite(norm);
  };
  for (size_t b = 0; b < systems.size(); ++b) {
    const auto& m = systems[b]->matrices();
    const auto& name = systems[b]->body().name;
    for (const auto& [matrix, what] : {std::pair{&m.mass_u, "M_u"},
                                       {&m.stiffness_u, "K_u"},
                                       {&m.coupling_u_theta, "K_uθ"},
                                       {&m.mass_theta, "M_θ"},
                                       {&m.stiffness_theta, "K_θ"}})
      if (!finite(*matrix))
        throw NumericalError(
            fmt::format("assembly: {} of body '{}' is not finite (NaN or Inf)", what, name), 0, 0,
            std::nan(""));
    const auto& st = states[b];
    for (const auto& [v, what] :
         {std::pair{&st.u, "u"}, {&st.v, "u̇"}, {&st.a, "ü"}, {&st.theta, "θ"}})
      if (!v->all_finite())
        throw NumericalError(
            fmt::format("initial state: {} of body '{}' is not finite (NaN or Inf)", what, name), 0,
            0, std::nan(""));
  }
}

}  // namespace tc::physics
