#pragma once
// Problems built in code for the physics tests (no case file), and small dense helpers.
#include <Eigen/Dense>
#include <optional>
#include <string>

#include "tc/core/numeric/petsc.hpp"
#include "tc/mesh/box.hpp"
#include "tc/model/problem.hpp"

namespace tc::test {

/// Steel-like constants (SI).
inline fem::Material steel() {
  fem::Material m;
  m.density = 7850;
  m.young_modulus = 2.0e11;
  m.poisson_ratio = 0.3;
  m.thermal_expansion = 1.2e-5;
  m.specific_heat = 450;
  m.thermal_conductivity = 50;
  return m;
}

/// One box body [0, size] with `cells`, the given material and scheme.
inline physics::Problem box_problem(int dim, const mesh::Point& size,
                                    const std::array<int, 3>& cells, const fem::Material& mat,
                                    physics::Scheme scheme, double step, int n_steps) {
  physics::Problem p;
  p.dimension = dim;
  p.time.scheme = scheme;
  p.time.step = step;
  p.time.end = step * n_steps;
  p.physics.reference_temperature = 293.15;
  physics::Body b;
  b.name = "block";
  b.material = mat;
  b.mesh = mesh::make_box(dim, {0, 0, 0}, size, cells);
  b.initial_temperature = p.physics.reference_temperature;
  p.bodies.push_back(std::move(b));
  return p;
}

/// A [[boundary]] entry holding the listed components at zero.
inline physics::BoundaryCondition hold(const std::string& where, std::initializer_list<int> comps) {
  physics::BoundaryCondition bc;
  bc.where = where;
  for (const int k : comps) bc.displacement[k] = core::TimeTable(0.0);
  return bc;
}

/// A [[boundary]] entry of `body` prescribing the listed displacement components.
inline physics::BoundaryCondition displacement_bc(
    int body, const std::string& where,
    std::initializer_list<std::pair<int, core::TimeTable>> comps) {
  physics::BoundaryCondition bc;
  bc.body = body;
  bc.where = where;
  for (const auto& [k, t] : comps) bc.displacement[k] = t;
  return bc;
}

/// A [[boundary]] entry of `body` holding its temperature at `value`.
inline physics::BoundaryCondition temperature_bc(int body, const std::string& where, double value) {
  physics::BoundaryCondition bc;
  bc.body = body;
  bc.where = where;
  bc.temperature = core::TimeTable(value);
  return bc;
}

/// A 3D box body [lo, hi] with `cells`, starting at temperature θ.
inline physics::Body box_body(const std::string& name, const fem::Material& mat,
                              const mesh::Point& lo, const mesh::Point& hi,
                              std::array<int, 3> cells, double theta) {
  physics::Body b;
  b.name = name;
  b.material = mat;
  b.mesh = mesh::make_box(3, lo, hi, cells);
  b.initial_temperature = theta;
  return b;
}

/// The [contact] of a two-body problem: slave body and surface, master body and surface, 𝔉.
inline physics::ContactSettings contact_pair(int slave, std::string slave_where, int master,
                                             std::string master_where, double friction = 0) {
  physics::ContactSettings c;
  c.slave_body = slave;
  c.master_body = master;
  c.slave_where = std::move(slave_where);
  c.master_where = std::move(master_where);
  c.friction = friction;
  return c;
}

/// A 3D quasistatic problem of `steps` steps of τ at reference temperature θ₀, without
/// thermoelastic heating; the caller adds bodies, supports and contact.
inline physics::Problem quasistatic_3d(double tau, int steps, double theta0) {
  physics::Problem p;
  p.dimension = 3;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = tau;
  p.time.end = tau * steps;
  p.physics.reference_temperature = theta0;
  p.physics.thermoelastic_heating = false;
  return p;
}

/// A slider [0,1]²×[1,1.5] (4×4×2 cells, at `slider_theta`) pressed 10 µm in the first step of τ
/// onto a base [−0.25,1.25]²×[0,1] (5×5×3, at θ₀, bottom held) and dragged along x by its top
/// at v for `slide_steps` more steps; quasistatic, no thermoelastic heating. The contact: the
/// slider's bottom (slave) on the base's top, wider, so the slave stays covered; 𝔉 as given,
/// γ_C^s = 1e-4, γ_C^m = 4e-4 (δ_C = 0.2, β_C = 8e-5 W/(m²K Pa)), the QP and the coupling to
/// 1e-10 and 1e-8 (above the QP's accuracy of λ, ~1e-9 here).
inline physics::Problem slider_on_base(const fem::Material& mat, double tau, double v,
                                       int slide_steps, double theta0, double slider_theta,
                                       double friction) {
  auto p = quasistatic_3d(tau, slide_steps + 1, theta0);
  p.bodies.push_back(box_body("slider", mat, {0, 0, 1}, {1, 1, 1.5}, {4, 4, 2}, slider_theta));
  p.bodies.push_back(box_body("base", mat, {-0.25, -0.25, 0}, {1.25, 1.25, 1}, {5, 5, 3}, theta0));
  const core::TimeTable press({0, tau}, {0, -1e-5});
  const core::TimeTable drag({0, tau, tau * (slide_steps + 1)}, {0, 0, v * tau * slide_steps});
  p.boundaries.push_back(displacement_bc(0, "zmax", {{0, drag}, {1, 0.0}, {2, press}}));
  p.boundaries.push_back(displacement_bc(1, "zmin", {{0, 0.0}, {1, 0.0}, {2, 0.0}}));
  auto c = contact_pair(0, "zmin", 1, "zmax", friction);
  c.conductance_slave = 1e-4;
  c.conductance_master = 4e-4;
  p.contacts = {c};
  p.solver.qp_tolerance = 1e-10;
  p.solver.coupling_tolerance = 1e-8;
  p.solver.max_coupling_iterations = 50;
  return p;
}

/// Steady conduction through two pressed blocks (verification.md's 4C case): lower
/// [0.5,1.5]²×[−0.5,0.5] (3×3×3) and upper [0.5,1.5]²×[0.5,1.5] (2×2×2), E = 4000, ν = 0,
/// α = 0, ρ = c_p = 1, κ as given; the lower's bottom held in z, the upper's top pushed down
/// `push`, both on rollers at xmin and ymin; τ = 1e4 s for `steps` quasistatic steps, no
/// thermoelastic heating, QP and coupling to 1e-12. The caller adds temperatures and contact.
inline physics::Problem pressed_conduction_blocks(double theta0, double kappa, double push,
                                                  int steps) {
  fem::Material mat;
  mat.density = 1;
  mat.young_modulus = 4000;
  mat.poisson_ratio = 0;
  mat.thermal_expansion = 0;
  mat.specific_heat = 1;
  mat.thermal_conductivity = kappa;
  physics::Problem p;
  p.dimension = 3;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = 1e4;
  p.time.end = steps * p.time.step;
  p.physics.reference_temperature = theta0;
  p.physics.thermoelastic_heating = false;
  p.bodies.push_back(box_body("lower", mat, {0.5, 0.5, -0.5}, {1.5, 1.5, 0.5}, {3, 3, 3}, theta0));
  p.bodies.push_back(box_body("upper", mat, {0.5, 0.5, 0.5}, {1.5, 1.5, 1.5}, {2, 2, 2}, theta0));
  p.boundaries.push_back(displacement_bc(0, "zmin", {{2, 0.0}}));
  p.boundaries.push_back(displacement_bc(1, "zmax", {{2, -push}}));
  for (int b = 0; b < 2; ++b) {
    p.boundaries.push_back(displacement_bc(b, "xmin", {{0, 0.0}}));
    p.boundaries.push_back(displacement_bc(b, "ymin", {{1, 0.0}}));
  }
  p.solver.qp_tolerance = 1e-12;
  p.solver.coupling_tolerance = 1e-12;
  p.solver.max_coupling_iterations = 50;
  return p;
}

/// Dense copy of a (small) PETSc matrix.
inline Eigen::MatrixXd to_dense(const core::SparseMatrix& a) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(a.rows(), a.cols());
  for (PetscInt i = 0; i < a.rows(); ++i) {
    PetscInt n = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    TC_PETSC(MatGetRow(a.get(), i, &n, &cols, &vals));
    for (PetscInt j = 0; j < n; ++j) d(i, cols[j]) = vals[j];
    TC_PETSC(MatRestoreRow(a.get(), i, &n, &cols, &vals));
  }
  return d;
}

inline Eigen::VectorXd to_eigen(const core::Vector& v) {
  const auto s = v.to_std();
  return Eigen::Map<const Eigen::VectorXd>(s.data(), static_cast<Eigen::Index>(s.size()));
}

}  // namespace tc::test
