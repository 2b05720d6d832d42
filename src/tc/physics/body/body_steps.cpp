#include "tc/physics/body/body_steps.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "tc/core/error.hpp"
#include "tc/physics/body/boundary_heat_newton.hpp"
#include "tc/physics/body/finite_checks.hpp"
#include "tc/physics/body/time_scheme.hpp"

namespace tc::physics {

void BodySteps::heat_rhs(int b) {
  const auto& sys = *bodies_.systems[b];
  auto& s = *bodies_.fields[b];
  s.rhs_theta.copy_from(s.rhs_theta_base);
  if (s.heating) {  // −K_θu u̇ = θ₀ K_uθᵀ u̇ (docs/choices.md)
    iterate_velocity(problem_, sys, bodies_.states[b], s);
    s.work_theta.zero();
    sys.matrices().coupling_u_theta.mult_transpose(s.velocity, s.work_theta);
    s.rhs_theta.axpy(problem_.physics.reference_temperature, s.work_theta);
  }
}

void BodySteps::heat_step(int b, int step, int iteration) {
  // (6.1) with the velocity of the current displacement iterate.
  auto scope = timers_.scope("heat_solve");
  const auto& sys = *bodies_.systems[b];
  auto& s = *bodies_.fields[b];
  heat_rhs(b);
  const double t = step * problem_.time.step;
  sys.prescribe_theta(t, s.theta_new);
  if (!sys.has_boundary_term()) {
    const double theta0 = problem_.physics.reference_temperature;
    const bool deviation = deviation_applies(s);
    if (deviation) heat_to_deviation(theta0, s);
    s.heat->solve(s.rhs_theta, s.theta_new);
    if (deviation) heat_from_deviation(theta0, sys, t, s);
  } else {  // radiation or a film with h(t): Newton (boundary_heat_newton.hpp)
    const auto& settings = problem_.solver;
    const auto o = solve_boundary_heat(sys, s.a_theta, *s.heat, t, s.rhs_theta, s.theta_new,
                                       settings.newton_tolerance, settings.max_newton_iterations);
    newton_ += o.iterations;
    newton_inner_ += o.inner_iterations;
    require_converged(o, fmt::format("body '{}'", sys.body().name), settings.newton_tolerance, step,
                      iteration);
  }
  require_finite(s.theta_new, "temperature", step, iteration);
}

void BodySteps::mech_load(int b, int step) {
  const auto& sys = *bodies_.systems[b];
  auto& s = *bodies_.fields[b];
  s.rhs_u.copy_from(s.rhs_u_base);
  if (s.expansion) subtract_thermal_force(problem_, sys, s, s.theta_new, s.rhs_u);
  sys.prescribe_u(step * problem_.time.step, s.u_new);
  if (s.coupling) s.coupling->write(s.u_new);  // the faces under load control at their w
}

void BodySteps::mech_step(int b, int step, int iteration) {
  auto scope = timers_.scope("mechanical_solve");
  auto& s = *bodies_.fields[b];
  mech_load(b, step);
  // Outside contact the load fixes the faces' w directly (S w = F − R(0)); in contact the QP
  // does, around this u_free (ContactCoupling).
  if (s.coupling && !s.coupling_in_contact)
    s.coupling->balance(step * problem_.time.step, s.rhs_u, s.u_new, step, iteration);
  s.mech->solve(s.rhs_u, s.u_new);
  require_finite(s.u_new, "displacement", step, iteration);
}

int BodySteps::couple(int b, int step) {
  const auto& sys = *bodies_.systems[b];
  auto& s = *bodies_.fields[b];
  begin_step(problem_, sys, bodies_.states[b], s, step * problem_.time.step);
  int iteration = 1;
  if (!(s.expansion && s.heating)) {
    // One-way coupling: one pass in the right order is the exact solution of the step.
    if (s.expansion) {
      heat_step(b, step, iteration);
      mech_step(b, step, iteration);
    } else {
      mech_step(b, step, iteration);
      heat_step(b, step, iteration);
    }
  } else {
    const double tol = problem_.solver.coupling_tolerance;
    double change = 0;
    for (iteration = 1; iteration <= problem_.solver.max_coupling_iterations; ++iteration) {
      s.u_prev.copy_from(s.u_new);
      s.theta_prev.copy_from(s.theta_new);
      if (heat_before_mechanics(problem_.solver.coupling_order, s.heating)) {
        heat_step(b, step, iteration);
        mech_step(b, step, iteration);
      } else {
        mech_step(b, step, iteration);
        heat_step(b, step, iteration);
      }
      s.u_prev.axpy(-1.0, s.u_new);
      s.theta_prev.axpy(-1.0, s.theta_new);
      const double du = s.u_prev.norm(), un = s.u_new.norm();
      const double dth = s.theta_prev.norm(), thn = s.theta_new.norm();
      change = std::max(un > 0 ? du / un : du, thn > 0 ? dth / thn : dth);
      if (du <= tol * un && dth <= tol * thn) break;
    }
    if (iteration > problem_.solver.max_coupling_iterations)
      throw NumericalError(
          fmt::format("the staggered fixed point (6.3) of body '{}' did not converge to {:.1e}",
                      sys.body().name, tol),
          step, iteration - 1, change);
  }
  end_step(problem_, sys, bodies_.states[b], s);
  return iteration;
}

}  // namespace tc::physics
