#include "tc/run/energies.hpp"

#include <algorithm>
#include <cmath>

#include "tc/physics/body/time_scheme.hpp"
#include "tc/physics/contact/step/contact_coupling.hpp"

namespace tc::physics {

double kinetic_energy(const Problem& p, const Bodies& bodies) {
  if (!body_time_scheme(p).inertia()) return 0.0;
  double e = 0;
  for (int b = 0; b < bodies.size(); ++b)
    e += 0.5 * bodies.systems[b]->matrices().mass_u.quadratic_form(bodies.states[b].v,
                                                                   bodies.fields[b]->work_u);
  return e;
}

double strain_energy(const Bodies& bodies) {
  double e = 0;
  for (int b = 0; b < bodies.size(); ++b)
    e += 0.5 * bodies.systems[b]->matrices().stiffness_u.quadratic_form(bodies.states[b].u,
                                                                        bodies.fields[b]->work_u);
  return e;
}

double thermal_energy(const Problem& p, const Bodies& bodies) {
  const double theta0 = p.physics.reference_temperature;
  double e = 0;
  for (int b = 0; b < bodies.size(); ++b) {
    if (const auto* heat = bodies.systems[b]->nonlinear_heat()) {  // ∫ρ∫c_p dθ: the enthalpy
      e += heat->total_enthalpy(bodies.states[b].theta);
      continue;
    }
    const auto& vol = bodies.systems[b]->capacity_volumes();
    const auto theta = bodies.states[b].theta.to_std();
    const double c = bodies.systems[b]->body().material.heat_capacity();
    for (size_t a = 0; a < vol.size(); ++a) e += c * vol[a] * (theta[a] - theta0);
  }
  return e;
}

double thermal_free_energy(const Problem& p, const Bodies& bodies) {
  const double theta0 = p.physics.reference_temperature;
  double e = 0;
  for (int b = 0; b < bodies.size(); ++b) {
    auto& s = *bodies.fields[b];
    s.dtheta.copy_from(bodies.states[b].theta);
    s.dtheta.shift(-theta0);
    e += bodies.systems[b]->matrices().mass_theta.quadratic_form(s.dtheta, s.work_theta) /
         (2.0 * theta0);
  }
  return e;
}

double extreme_temperature(const Bodies& bodies, bool largest) {
  double e = largest ? -INFINITY : INFINITY;
  for (const auto& st : bodies.states) {
    PetscReal v = 0;
    if (largest) {
      TC_PETSC(VecMax(st.theta.get(), nullptr, &v));
      e = std::max(e, static_cast<double>(v));
    } else {
      TC_PETSC(VecMin(st.theta.get(), nullptr, &v));
      e = std::min(e, static_cast<double>(v));
    }
  }
  return e;
}

void support_forces(const Problem& p, const Bodies& bodies, int b, double t, core::Vector& r,
                    const ContactCoupling* contact) {
  const auto& sys = *bodies.systems[b];
  const auto& m = sys.matrices();
  const auto& st = bodies.states[b];
  auto& s = *bodies.fields[b];
  core::Vector& f = s.f_u;
  sys.mechanical_load(t, f);
  m.stiffness_u.mult(st.u, r);
  if (body_time_scheme(p).inertia()) m.mass_u.mult_add(st.a, r);
  if (p.physics.thermal_expansion) {
    thermal_deviation(p, sys, st.theta, s.dtheta);
    m.coupling_u_theta.mult_add(s.dtheta, r);
  }
  // A u + B_bᵀλ = f holds on the free dofs; on a constrained dof the support takes what the
  // contact puts there as well (λ is the step's, as M ü^{k+1} of the scheme holds it).
  if (contact) contact->add_multiplier_load(b, r);
  {  // f is scratch: overwrite its constrained entries with the support forces, keep the rest
    auto rv = r.view();
    auto fv = f.view();
    for (const PetscInt d : sys.u_dirichlet_dofs()) fv[d] = rv[d];
  }
  r.copy_from(f);
}

void EnergyBalance::start(double t) {
  forces_.clear();
  for (int b = 0; b < bodies_.size(); ++b) {
    forces_.emplace_back(bodies_.systems[b]->n_u());
    support_forces(problem_, bodies_, b, t, forces_[b], contact_);
  }
}

void EnergyBalance::account_step(const std::vector<core::Vector>& old_u, double t) {
  // External work by the trapezoidal rule, ½(F^k + F^{k+1})·(u^{k+1} − u^k): with Newmark's
  // average acceleration this makes the discrete energy balance exact for linear elasticity.
  for (int b = 0; b < bodies_.size(); ++b) {
    auto& s = *bodies_.fields[b];
    s.work_u.copy_from(bodies_.states[b].u);
    s.work_u.axpy(-1.0, old_u[b]);
    const double before = forces_[b].dot(s.work_u);
    support_forces(problem_, bodies_, b, t, forces_[b], contact_);
    external_work_ += 0.5 * (before + forces_[b].dot(s.work_u));
  }
}

void EnergyBalance::register_history(History& h) const {
  h.add("kinetic_energy", [this] { return kinetic_energy(problem_, bodies_); });
  h.add("strain_energy", [this] { return strain_energy(bodies_); });
  h.add("thermal_energy", [this] { return thermal_energy(problem_, bodies_); });
  h.add("external_work", History::value_of(external_work_));
  h.add("max_temperature", [this] { return extreme_temperature(bodies_, true); });
  h.add("min_temperature", [this] { return extreme_temperature(bodies_, false); });
  // The force on each reaction group per axis, Σ F_d over its dofs (F: support_forces).
  const char* axes = "xyz";
  for (int b = 0; b < bodies_.size(); ++b)
    for (const auto& g : bodies_.systems[b]->reaction_groups())
      for (int k = 0; k < problem_.dimension; ++k)
        h.add(g.label + "_" + axes[k], [this, b, &dofs = g.dofs[k]] {
          const auto f = forces_[b].read();
          double sum = 0;
          for (const PetscInt d : dofs) sum += f[d];
          return sum;
        });
}

}  // namespace tc::physics
