#include "tc/physics/body/body_field.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include "tc/core/error.hpp"
#include "tc/core/numeric/matrix_views.hpp"
#include "tc/core/verify.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/physics/body/time_scheme.hpp"

namespace tc::physics {

core::SparseMatrix combine(double a, const core::SparseMatrix& x, double b,
                           const core::SparseMatrix& y) {
  core::SparseMatrix out = x.copy();
  out.scale(a);
  out.axpy(b, y);
  return out;
}

namespace {

/// A_u of (5.3): 4/τ² M_u + K_u with Newmark, K_u with the quasistatic scheme.
core::SparseMatrix mechanics_operator(const Problem& p, const core::SparseMatrix& mass_u,
                                      const core::SparseMatrix& stiffness_u) {
  const double c = body_time_scheme(p).mass_factor(p.time.step);
  // M_u in K_u's pattern first (core::drop_zeros took its zeros out): the sum entry by entry.
  return c != 0.0 ? combine(c, core::in_pattern_of(mass_u, stiffness_u), 1.0, stiffness_u)
                  : stiffness_u.copy();
}

/// A_θ of (5.6), M_θ/τ + K_θ (backward Euler; a constant film's h∫θv is added by the caller).
core::SparseMatrix heat_operator(const Problem& p, const core::SparseMatrix& mass_theta,
                                 const core::SparseMatrix& stiffness_theta) {
  return combine(1.0 / p.time.step, mass_theta, 1.0, stiffness_theta);
}

/// A unit pivot, scaled by the mean diagonal, on the massless dofs of subdomain s's M_u.
void massless_pivots(const BodySystem& sys, int s, core::SparseMatrix& mass) {
  const auto& sub = sys.subdomains().at(static_cast<size_t>(s));
  const int d = sys.dim();
  core::Vector diag(mass.rows());
  TC_PETSC(MatGetDiagonal(mass.get(), diag.get()));
  double mean = 0;
  {
    const auto v = diag.read();
    for (PetscInt i = 0; i < mass.rows(); ++i) mean += v[i];
  }
  mean /= static_cast<double>(std::max<PetscInt>(mass.rows(), 1));
  const auto& massless = sys.massless_dofs();
  {
    auto v = diag.view();
    for (PetscInt i = 0; i < mass.rows(); ++i) v[i] = 0.0;
    for (size_t a = 0; a < sub.global_node.size(); ++a)
      for (int k = 0; k < d; ++k)
        if (std::binary_search(massless.begin(), massless.end(),
                               static_cast<PetscInt>(d * sub.global_node[a] + k)))
          v[d * static_cast<PetscInt>(a) + k] = mean;
  }
  TC_PETSC(MatDiagonalSet(mass.get(), diag.get(), ADD_VALUES));
}

}  // namespace

std::unique_ptr<ConstrainedSolver> body_solver(const Problem& p, const BodySystem& sys,
                                               const core::SparseMatrix& a, BodyOperator op) {
  const bool mech = op != BodyOperator::heat;
  std::vector<PetscInt> dirichlet = mech ? sys.u_dirichlet_dofs() : sys.theta_dirichlet_dofs();
  if (op == BodyOperator::mass && !sys.massless_dofs().empty()) {
    // M_u is singular on the massless dofs: ü = 0 there (their equations are static ones).
    std::vector<PetscInt> both;
    std::set_union(dirichlet.begin(), dirichlet.end(), sys.massless_dofs().begin(),
                   sys.massless_dofs().end(), std::back_inserter(both));
    dirichlet = std::move(both);
  }
  if (sys.subdomains().empty())
    // One factorisation shared by the ranks rather than one per rank (linalg::CholeskySolver).
    return std::make_unique<ConstrainedSolver>(a, dirichlet, p.solver.factorization,
                                               linalg::FactorRanks::all_ranks);
  const bool inertia = body_time_scheme(p).mass_factor(p.time.step) != 0.0;
  auto local = [&](int s) {
    const auto m = sys.subdomain_matrices(s);
    switch (op) {
      case BodyOperator::mechanics:
        return mechanics_operator(p, m.mass_u, m.stiffness_u);
      case BodyOperator::statics:
        return m.stiffness_u.copy();
      case BodyOperator::heat: {
        auto heat = heat_operator(p, m.mass_theta, m.stiffness_theta);
        if (sys.constant_film()) heat.axpy(1.0, sys.subdomain_constant_film(s));
        return heat;
      }
      case BodyOperator::mass: {
        // TFETI keeps the Dirichlet dofs in the subdomain matrices (multipliers fix them), so
        // the massless dofs, which ü = 0 constrains as Dirichlet dofs, need a pivot: the mean
        // diagonal, which changes only their multipliers.
        auto mass = m.mass_u.copy();
        if (!sys.massless_dofs().empty()) massless_pivots(sys, s, mass);
        return mass;
      }
    }
    return core::SparseMatrix{};
  };
  // Without inertia the subdomains of an elastic body float: TFETI's rigid-body kernels. With
  // it they nearly float when τ is large, and the same modes deflate (feti.hpp); constants
  // likewise for heat. The mass matrix alone needs no coarse space.
  const auto kernel = op == BodyOperator::heat   ? feti::Kernel::constant
                      : op == BodyOperator::mass ? feti::Kernel::none
                                                 : feti::Kernel::rigid;
  const auto singular = (op == BodyOperator::mechanics && !inertia) || op == BodyOperator::statics
                            ? feti::Singular::yes
                            : feti::Singular::no;
  feti::FetiOptions options;
  options.tolerance = p.solver.feti_tolerance;
  options.max_iterations = p.solver.max_feti_iterations;
  options.preconditioner = p.solver.feti_preconditioner;
  options.package = p.solver.factorization;
  return std::make_unique<ConstrainedSolver>(std::make_unique<feti::Feti>(
      sys.subdomains(), sys.body().mesh.n_nodes(), mech ? sys.dim() : 1, dirichlet, kernel,
      singular, local, options));
}

std::unique_ptr<ConstrainedSolver> body_solver(const Problem& p, const BodySystem& sys,
                                               core::SparseMatrix&& a, BodyOperator op) {
  if (!sys.subdomains().empty()) return body_solver(p, sys, std::as_const(a), op);
  std::vector<PetscInt> dirichlet =
      op != BodyOperator::heat ? sys.u_dirichlet_dofs() : sys.theta_dirichlet_dofs();
  TC_VERIFY(op != BodyOperator::mass, "body_solver: M_u is kept, not consumed");
  return std::make_unique<ConstrainedSolver>(
      std::move(a), std::move(dirichlet), p.solver.factorization, linalg::FactorRanks::all_ranks);
}

BodyField::BodyField(const Problem& p, const BodySystem& sys) {
  const auto& m = sys.matrices();
  a_theta = heat_operator(p, m.mass_theta, m.stiffness_theta);
  if (const auto* film = sys.constant_film()) a_theta.axpy(1.0, *film);  // + h∫θv
  // A_u (4/τ² M_u + K_u, or K_u quasistatic) only for its factorisation: products use M_u, K_u.
  mech =
      body_solver(p, sys, mechanics_operator(p, m.mass_u, m.stiffness_u), BodyOperator::mechanics);
  heat = body_solver(p, sys, a_theta, BodyOperator::heat);
  if (!sys.coupled_faces().empty()) {
    const double c = body_time_scheme(p).mass_factor(p.time.step);
    coupling = std::make_unique<RigidCoupling>(
        sys, *mech, [&m, c](const core::Vector& x, core::Vector& y) {  // A x = c M x + K x
          m.stiffness_u.mult(x, y);
          if (c != 0.0) {
            core::Vector mx(x.size());
            m.mass_u.mult(x, mx);
            y.axpy(c, mx);
          }
        });
  }
  const bool coupled_material = sys.body().material.thermal_expansion != 0.0;
  expansion = p.physics.thermal_expansion && coupled_material;
  heating = p.physics.thermoelastic_heating && coupled_material;
  for (auto* v : {&f_u, &rhs_u_base, &rhs_u, &u_new, &u_prev, &velocity, &work_u, &u_pred})
    *v = core::Vector(sys.n_u());
  for (auto* v : {&f_theta, &rhs_theta_base, &rhs_theta, &theta_new, &theta_prev, &dtheta,
                  &work_theta, &theta0_load})
    *v = core::Vector(sys.n_theta());
  // M_θ's part formed as begin_step forms M_θ θ^k/τ (θ^k/τ, then added to a vector by the same
  // product): for a body at θ₀ everywhere the two cancel to the bit.
  const double theta0 = p.physics.reference_temperature;
  work_theta.fill(theta0);
  work_theta.scale(1.0 / p.time.step);
  m.mass_theta.mult_add(work_theta, theta0_load);
  if (const auto* film = sys.constant_film()) {
    work_theta.fill(theta0);
    film->mult_add(work_theta, theta0_load);
  }
}

void BodyField::refactorise_mechanics(const Problem& p, const BodySystem& sys) {
  // The faces under load control form Φ = A_u⁻¹ once (RigidCoupling): `check` refuses them
  // with E(θ), ν(θ), as it refuses FETI.
  TC_VERIFY(!coupling && !mech->feti(), "refactorise_mechanics: a direct A_u without load control");
  const auto& m = sys.matrices();
  mech->refactorise(mechanics_operator(p, m.mass_u, m.stiffness_u));
}

bool deviation_applies(const BodyField& s) {
  return !s.heat->feti();
}

void heat_to_deviation(double theta0, BodyField& s) {
  s.rhs_theta.axpy(-1.0, s.theta0_load);
  s.theta_new.shift(-theta0);
}

void heat_from_deviation(double theta0, const BodySystem& sys, double t, BodyField& s) {
  s.theta_new.shift(theta0);
  sys.prescribe_theta(t, s.theta_new);
}

void solve_initial_acceleration(const BodySystem& sys, const core::Vector& r, core::Vector& a) {
  std::vector<PetscInt> fixed;
  const auto& dirichlet = sys.u_dirichlet_dofs();
  const auto& massless = sys.massless_dofs();
  std::set_union(dirichlet.begin(), dirichlet.end(), massless.begin(), massless.end(),
                 std::back_inserter(fixed));
  const auto& mass = sys.matrices().mass_u;
  auto b = r.clone();
  {
    auto v = b.view();
    for (const PetscInt d : fixed) v[d] = 0.0;
  }
  a.zero();
  // Scaled to ‖b‖_∞ = 1: an extreme but finite load (1e290) would overflow CG's norms.
  const double scale = b.max_abs();
  if (scale == 0.0 || !std::isfinite(scale)) {
    if (scale != 0.0) a.fill(scale);  // non-finite: left for the step's finiteness checks
    return;
  }
  b.scale(1.0 / scale);
  // Jacobi-scaled mass matrices have a condition number bounded independently of h (Wathen,
  // IMA J. Numer. Anal. 7, 1987: ≤ 27 for trilinear hexahedra), so 1e-12 costs some 70
  // iterations and leaves ü⁰ accurate to ~1e-11, far below the steps' own tolerances.
  constexpr double rtol = 1e-12;
  int iterations = 0;
  // On M_u with the fixed dofs masked, not on a copy with them eliminated: the same iterates,
  // without a second M_u beside every factor at the run's memory peak.
  const double reached =
      core::jacobi_cg(mass, fixed, core::mean_diagonal(mass), b, a, rtol, 10000, iterations);
  if (!(reached <= rtol))
    throw NumericalError("initial acceleration: CG on M_u did not converge", 0, iterations,
                         reached);
  a.scale(scale);
}

void thermal_deviation(const Problem& p, const BodySystem& sys, const core::Vector& theta,
                       core::Vector& out) {
  const double theta0 = p.physics.reference_temperature;
  const auto& mat = sys.body().material;
  out.copy_from(theta);
  if (!mat.nonlinear_expansion()) {
    out.shift(-theta0);
    return;
  }
  // The strain interpolated from its nodal values, ε_h = Σ N_a ε_th(θ_a): exact for a uniform
  // temperature, and of the interpolation's order otherwise (docs/choices.md).
  auto v = out.view();
  for (PetscInt a = 0; a < out.size(); ++a) v[a] = mat.expansion_deviation(v[a], theta0);
}

void subtract_thermal_force(const Problem& p, const BodySystem& sys, BodyField& s,
                            const core::Vector& theta, core::Vector& f) {
  // f ← f − K_uθ ϑ_α(θ), the thermal stress's load of (2.5), with the body's scratch vectors.
  thermal_deviation(p, sys, theta, s.dtheta);
  sys.matrices().coupling_u_theta.mult(s.dtheta, s.work_u);
  f.axpy(-1.0, s.work_u);
}

}  // namespace tc::physics
