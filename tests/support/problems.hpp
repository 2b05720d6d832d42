#pragma once
// Problems built in code for the physics tests (no case file), and small dense helpers.
#include <Eigen/Dense>
#include <optional>
#include <string>

#include "tc/core/petsc.hpp"
#include "tc/mesh/box.hpp"
#include "tc/physics/problem.hpp"

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
