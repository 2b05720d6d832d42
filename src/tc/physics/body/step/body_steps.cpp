#include "tc/physics/body/step/body_steps.hpp"

#include <fmt/format.h>

#include <memory>

#include "tc/core/error.hpp"
#include "tc/physics/body/boundary_heat_newton.hpp"
#include "tc/physics/body/step/finite_checks.hpp"
#include "tc/physics/body/step/staggered_loop.hpp"
#include "tc/physics/body/time_scheme.hpp"

namespace tc::physics {

void BodySteps::heat_rhs(int b) {
  const auto& sys = *bodies_.systems[b];
  auto& s = *bodies_.fields[b];
  s.rhs_theta.copy_from(s.rhs_theta_base);
  if (s.heating) {  // −K_θu u̇ = θ₀ K_uθᵀ u̇ (docs/choices.md)
    body_time_scheme(problem_).iterate_velocity(problem_, sys, bodies_.states[b], s);
    s.work_theta.zero();
    sys.matrices().coupling_u_theta.mult_transpose(s.velocity, s.work_theta);
    if (const auto& mat = sys.body().material; mat.nonlinear_expansion()) {
      // θ₀ β(θ) div u̇ with α(θ): row a by dϑ_α/dθ = α(θ_a)/α at the current iterate, the
      // derivative of the thermal force's ϑ_α (docs/theory.md)
      const auto th = s.theta_new.read();
      auto w = s.work_theta.view();
      for (PetscInt a = 0; a < sys.n_theta(); ++a) w[a] *= mat.expansion_rate(th[a]);
    }
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
  if (sys.nonlinear_heat()) {  // κ(θ) or c_p(θ), with the boundary terms if any
    const auto& settings = problem_.solver;
    const auto o = solve_nonlinear_heat(sys, s.a_theta, *s.heat, problem_.time.step, t, s.rhs_theta,
                                        s.theta_new, settings.newton_tolerance,
                                        settings.max_newton_iterations);
    newton_ += o.iterations;
    newton_inner_ += o.inner_iterations;
    require_converged(o, fmt::format("body '{}'", sys.body().name), settings.newton_tolerance, step,
                      iteration, kMaterialLawTerms);
  } else if (!sys.has_boundary_term()) {
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
  const double tol = problem_.solver.coupling_tolerance;
  const bool two_way = s.expansion && s.heating;
  // One-way coupling: one pass in the order of the dependence is the exact solution of the
  // step; two-way: the sweeps of (6.3) in the case's order until u and θ are within ε.
  const auto order = !two_way ? (s.expansion ? SweepOrder::heat_first : SweepOrder::mechanics_first)
                     : heat_before_mechanics(problem_.solver.coupling_order, s.heating)
                         ? SweepOrder::heat_first
                         : SweepOrder::mechanics_first;
  StaggeredLoop loop(order, two_way ? problem_.solver.max_coupling_iterations : 1);
  if (two_way)
    loop.stop_when(std::make_unique<ChangesWithin>(tol));
  else
    loop.stop_when(std::make_unique<OnePass>());
  const StaggeredSweep sweep{.begin =
                                 [&](SweepState&) {
                                   if (!two_way) return;  // nothing to compare with
                                   s.u_prev.copy_from(s.u_new);
                                   s.theta_prev.copy_from(s.theta_new);
                                 },
                             .heat = [&](SweepState& st) { heat_step(b, step, st.iteration); },
                             .mechanics = [&](SweepState& st) { mech_step(b, step, st.iteration); },
                             .end =
                                 [&](SweepState& st) {
                                   if (!two_way) return;
                                   s.u_prev.axpy(-1.0, s.u_new);
                                   s.theta_prev.axpy(-1.0, s.theta_new);
                                   st.primal = {s.u_prev.norm(), s.u_new.norm()};
                                   st.theta = {s.theta_prev.norm(), s.theta_new.norm()};
                                 }};
  const auto result = loop.run(sweep);
  if (!result.converged)
    throw NumericalError(
        fmt::format("the staggered fixed point (6.3) of body '{}' did not converge to {:.1e}",
                    sys.body().name, tol),
        step, result.iterations, result.change);
  return result.iterations;
}

}  // namespace tc::physics
