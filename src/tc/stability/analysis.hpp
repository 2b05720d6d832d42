#pragma once
// `thermocontact stability`: the linear stability of a case's steady sliding (docs/theory.md,
// "Linear stability"). The case's first `state_step` steps are run (its pressed, sliding
// state), the problem is linearised about that state (linearisation.hpp), and SLEPc gives the
// leading growth rates and modes at each speed and the critical speed (eigen.hpp). The analysis
// is quasistatic (the case's `time.scheme` must be), on one rank, of one contact pair whose
// master is a rigid tool. The results are plain data; io writes them (the app's
// stability_command.cpp).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tc/model/problem.hpp"
#include "tc/stability/eigen.hpp"

namespace tc::stability {

/// A mode's fields on the slave body's mesh (prescribed dofs 0): θ per node, u interleaved.
struct ModeFields {
  std::vector<double> theta_re, theta_im, u_re, u_im;
};

struct SpeedResult {
  double speed = 0;  // [m/s]
  EigenResult rates;
  double seconds = 0;  // the eigenproblem's wall time
};

struct StabilityResult {
  int body = 0;            // the slave body (its mesh carries the modes)
  double state_speed = 0;  // the case's sliding speed after the state [m/s]
  double state_time = 0;   // t of the state [s]
  int active_nodes = 0, open_nodes = 0, unknowns = 0;
  std::vector<SpeedResult> speeds;
  std::optional<Eigenpair> critical;         // re: V_c [m/s]
  std::optional<double> growth_at_critical;  // the leading Re b at V_c (≈ 0: a check) [1/s]
  int critical_iterations = 0;
  double state_seconds = 0, linearise_seconds = 0, critical_seconds = 0;
};

/// Runs the analysis of `p` (its [stability] settings; defaults when absent). `progress` is
/// called with one line per stage. Throws Error (exit 1) when the state has no sliding or no
/// pressed node, and what the run throws.
[[nodiscard]] StabilityResult analyse(const physics::Problem& p,
                                      const std::function<void(const std::string&)>& progress = {},
                                      Linearisation* keep = nullptr);

/// The fields of an eigenvector x of `lin` on its body's mesh.
[[nodiscard]] ModeFields mode_fields(const Linearisation& lin, const Eigenpair& e, int dim,
                                     PetscInt n_nodes);

}  // namespace tc::stability
