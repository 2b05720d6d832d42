#include "tc/physics/body_system.hpp"

#include <algorithm>
#include <cmath>

namespace tc::physics {

namespace {

std::vector<std::pair<PetscInt, double>> sparse_weights(const std::vector<double>& per_node) {
  std::vector<std::pair<PetscInt, double>> out;
  for (size_t a = 0; a < per_node.size(); ++a)
    if (per_node[a] != 0.0) out.emplace_back(static_cast<PetscInt>(a), per_node[a]);
  return out;
}

std::vector<PetscInt> keys(const std::map<PetscInt, TimeTable>& m) {
  std::vector<PetscInt> out;
  out.reserve(m.size());
  for (const auto& [dof, table] : m) out.push_back(dof);
  return out;
}

}  // namespace

BodySystem::BodySystem(const Problem& problem, int index)
    : body_(&problem.bodies.at(index)),
      dim_(problem.dimension),
      m_(fem::assemble_body(body_->mesh, body_->material)),
      volumes_(fem::volume_integrals(body_->mesh)) {
  for (int k = 0; k < dim_; ++k)
    u_loads_.push_back({body_->body_force[k], k, sparse_weights(volumes_)});
  th_loads_.push_back({body_->heat_source, 0, sparse_weights(volumes_)});
  for (const auto& bc : problem.boundaries)
    if (bc.body == index) add_boundary(bc, body_->name);
  u_dofs_ = keys(u_prescribed_);
  th_dofs_ = keys(th_prescribed_);
  lumped_ = problem.physics.lumped_heat_capacity;
  if (lumped_) lump(m_.mass_theta);
  const auto& c = problem.contact;
  if (c && problem.time.scheme == Scheme::Dynamic &&
      problem.time.contact_scheme == ContactScheme::ModifiedMass &&
      (index == c->slave_body || index == c->master_body)) {
    massless_.assign(static_cast<size_t>(body_->mesh.n_nodes()), 0);
    for (const int a :
         body_->mesh.boundary_nodes(index == c->slave_body ? c->slave_where : c->master_where))
      massless_[static_cast<size_t>(a)] = 1;
    for (int a = 0; a < body_->mesh.n_nodes(); ++a)
      if (massless_[static_cast<size_t>(a)])
        for (int k = 0; k < dim_; ++k) massless_dofs_.push_back(dim_ * a + k);
    m_.mass_u = fem::singular_mass_u(body_->mesh, body_->material, massless_);
  }
  cell_part_ = mesh::partition_cells(body_->mesh, std::max(1, body_->subdomains));
  if (body_->subdomains > 1) subdomains_ = mesh::split(body_->mesh, cell_part_, body_->subdomains);
}

fem::BodyMatrices BodySystem::subdomain_matrices(int s) const {
  auto m = fem::assemble_body(subdomains_.at(static_cast<size_t>(s)).mesh, body_->material);
  if (lumped_) lump(m.mass_theta);  // row sums are additive over cells: Σ_s lumped = lumped
  if (!massless_.empty()) {         // cell by cell, so Σ_s of the subdomains' is the body's
    const auto& sub = subdomains_.at(static_cast<size_t>(s));
    std::vector<char> local(sub.global_node.size());
    for (size_t a = 0; a < local.size(); ++a)
      local[a] = massless_[static_cast<size_t>(sub.global_node[a])];
    m.mass_u = fem::singular_mass_u(sub.mesh, body_->material, local);
  }
  return m;
}

void BodySystem::lump(core::SparseMatrix& m) {
  // Row sums on the diagonal, the pattern kept (so a·M + b·K still shares it with K).
  core::Vector sums(m.rows());
  TC_PETSC(MatGetRowSum(m.get(), sums.get()));
  TC_PETSC(MatZeroEntries(m.get()));
  TC_PETSC(MatDiagonalSet(m.get(), sums.get(), INSERT_VALUES));
}

void BodySystem::add_boundary(const BoundaryCondition& bc, const std::string& body_name) {
  const auto& mesh = body_->mesh;
  const auto nodes = mesh.boundary_nodes(bc.where);
  bool any_displacement = false;
  ReactionGroup group{"reaction_" + body_name + "_" + bc.where, {}};
  std::vector<std::pair<PetscInt, double>> facet_weights;  // ∫ N_a dS, computed once if needed
  if (bc.heat_flux || std::any_of(bc.traction.begin(), bc.traction.end(),
                                  [](const auto& t) { return t.has_value(); }))
    facet_weights = sparse_weights(fem::boundary_integrals(mesh, bc.where));
  for (int k = 0; k < dim_; ++k) {
    if (bc.displacement[k]) {
      any_displacement = true;
      for (const int a : nodes) {
        const PetscInt dof = dim_ * a + k;
        u_prescribed_[dof] = *bc.displacement[k];
        group.dofs[k].push_back(dof);
      }
    }
    if (bc.traction[k]) u_loads_.push_back({*bc.traction[k], k, facet_weights});
  }
  if (any_displacement) reactions_.push_back(std::move(group));
  if (bc.temperature)
    for (const int a : nodes) th_prescribed_[a] = *bc.temperature;
  if (bc.heat_flux) th_loads_.push_back({*bc.heat_flux, 0, facet_weights});
}

void BodySystem::prescribe_u(double t, core::Vector& x) const {
  auto v = x.view();
  for (const auto& [dof, table] : u_prescribed_) v[dof] = table(t);
}

void BodySystem::prescribe_u_rate(double t, core::Vector& x) const {
  // Tables are piecewise linear: a one-sided difference inside the segment is exact.
  const double h = 1e-7 * (1.0 + std::abs(t));
  auto v = x.view();
  for (const auto& [dof, table] : u_prescribed_) v[dof] = (table(t + h) - table(t)) / h;
}

void BodySystem::prescribe_theta(double t, core::Vector& x) const {
  auto v = x.view();
  for (const auto& [dof, table] : th_prescribed_) v[dof] = table(t);
}

void BodySystem::apply(const std::vector<NodalLoad>& loads, int block, double t, core::Vector& f) {
  f.zero();
  auto v = f.view();
  for (const auto& load : loads) {
    const double value = load.value(t);
    if (value == 0.0) continue;
    for (const auto& [a, w] : load.weights) v[block * a + load.component] += value * w;
  }
}

void BodySystem::mechanical_load(double t, core::Vector& f) const {
  apply(u_loads_, dim_, t, f);
}

void BodySystem::thermal_load(double t, core::Vector& f) const {
  apply(th_loads_, 1, t, f);
}

}  // namespace tc::physics
