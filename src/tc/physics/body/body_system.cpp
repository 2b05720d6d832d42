#include "tc/physics/body/body_system.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "tc/core/numeric/matrix_views.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/physics/body/time_scheme.hpp"

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

/// The dofs of an undecomposed body (`per_node` a node) in the blocks its factor will have
/// (one rule: linalg::ranks_sharing_a_factor), so that no rank holds a matrix of the body whole;
/// none otherwise.
core::RowBlocks spread_rows(const Problem& problem, const Body& body, int per_node) {
  if (body.subdomains > 1 || linalg::ranks_sharing_a_factor(problem.solver.factorization) <= 1)
    return {};
  return core::RowBlocks::over(PETSC_COMM_WORLD,
                               static_cast<PetscInt>(per_node) * body.mesh.n_nodes());
}

const core::RowBlocks* spread(const core::RowBlocks& r) {
  return r.spread() ? &r : nullptr;
}

}  // namespace

BodySystem::BodySystem(const Problem& problem, int index)
    : body_(&problem.bodies.at(index)),
      dim_(problem.dimension),
      u_rows_(spread_rows(problem, *body_, problem.dimension)),
      theta_rows_(spread_rows(problem, *body_, 1)),
      m_(fem::assemble_body(body_->mesh, body_->material, spread(u_rows_), spread(theta_rows_))),
      volumes_(fem::volume_integrals(body_->mesh)) {
  for (int k = 0; k < dim_; ++k)
    u_loads_.push_back({body_->body_force[k], k, sparse_weights(volumes_)});
  th_loads_.push_back({body_->heat_source, 0, sparse_weights(volumes_)});
  for (const auto& bc : problem.boundaries)
    if (bc.body == index) add_boundary(bc, body_->name);
  if (!constant_film_facets_.empty())
    constant_film_ = fem::boundary_mass(body_->mesh, constant_film_facets_, spread(theta_rows_));
  u_dofs_ = keys(u_prescribed_);
  for (const auto& c : coupled_) u_dofs_.insert(u_dofs_.end(), c.dofs.begin(), c.dofs.end());
  std::sort(u_dofs_.begin(), u_dofs_.end());
  u_dofs_.erase(std::unique(u_dofs_.begin(), u_dofs_.end()), u_dofs_.end());
  th_dofs_ = keys(th_prescribed_);
  lumped_ = problem.physics.lumped_heat_capacity;
  if (lumped_) {
    fem::lump_heat_capacity(m_.mass_theta, body_->mesh, body_->material.heat_capacity());
    if (!fem::lumps_by_row_sums(body_->mesh)) capacity_volumes_ = fem::lumped_volumes(body_->mesh);
  }
  if (body_time_scheme(problem).massless_contact_faces(problem))
    for (const auto& c : problem.contacts)  // every contact surface of the body, of any pair
      for (const auto& [b, where] :
           {std::pair{c.slave_body, &c.slave_where}, {c.master_body, &c.master_where}}) {
        if (b != index) continue;
        massless_.resize(static_cast<size_t>(body_->mesh.n_nodes()), 0);
        for (const int a : body_->mesh.boundary_nodes(*where))
          massless_[static_cast<size_t>(a)] = 1;
      }
  if (!massless_.empty()) {
    for (int a = 0; a < body_->mesh.n_nodes(); ++a)
      if (massless_[static_cast<size_t>(a)])
        for (int k = 0; k < dim_; ++k) massless_dofs_.push_back(dim_ * a + k);
    m_.mass_u = fem::singular_mass_u(body_->mesh, body_->material, massless_, spread(u_rows_));
  }
  // M_u without the zeros between the displacement components (2/3 of K_u's pattern in 3D),
  // M_θ on K_θ's index arrays (one node graph): both held beside the factors for the whole
  // run. The contact-stabilised scheme factorises M_u itself, whose ordering follows its
  // pattern: there M_u keeps K_u's, on K_u's indices.
  if (!u_rows_.spread()) {
    if (problem.time.scheme == Scheme::dynamic &&
        problem.time.contact_scheme == ContactScheme::stabilised)
      core::share_pattern(m_.mass_u, m_.stiffness_u);
    else
      core::drop_zeros(m_.mass_u);
  }
  if (!theta_rows_.spread()) core::share_pattern(m_.mass_theta, m_.stiffness_theta);
  if (body_->material.nonlinear_heat())
    nonlinear_heat_ = std::make_unique<fem::NonlinearHeat>(
        body_->mesh, body_->material, problem.physics.reference_temperature, lumped_);
  if (body_->material.nonlinear_moduli()) {  // assembled above with E, ν at θ_initial
    cell_young_.assign(static_cast<size_t>(body_->mesh.n_cells()), body_->material.young_modulus);
    cell_poisson_.assign(cell_young_.size(), body_->material.poisson_ratio);
  }
  cell_part_ = mesh::partition_cells(body_->mesh, std::max(1, body_->subdomains));
  if (body_->subdomains > 1) subdomains_ = mesh::split(body_->mesh, cell_part_, body_->subdomains);
}

double BodySystem::modulus_change(const core::Vector& theta) const {
  if (cell_young_.empty()) return 0.0;
  const auto& mesh = body_->mesh;
  const auto& mat = body_->material;
  const auto th = theta.read();
  young_at_.resize(cell_young_.size());
  poisson_at_.resize(cell_young_.size());
  const auto relative = [](double now, double then) {
    return now == then ? 0.0 : std::abs(now - then) / std::abs(then);
  };
  double change = 0;
  for (int c = 0; c < mesh.n_cells(); ++c) {
    // The cell's temperature: the mean of its nodal θ, the value at the centroid for a
    // linear field (second order, as θ_h is); one C per cell keeps the element kernels'.
    const auto nodes = mesh.cell(c);
    double sum = 0;
    for (const int a : nodes) sum += th[a];
    const double tc = sum / static_cast<double>(nodes.size());
    const auto i = static_cast<size_t>(c);
    young_at_[i] = mat.young_modulus_at(tc);
    poisson_at_[i] = mat.poisson_ratio_at(tc);
    change = std::max({change, relative(young_at_[i], cell_young_[i]),
                       relative(poisson_at_[i], cell_poisson_[i])});
  }
  return change;
}

bool BodySystem::update_moduli(const core::Vector& theta, double tolerance) {
  if (cell_young_.empty() || !(modulus_change(theta) > tolerance)) return false;
  cell_young_ = young_at_;
  cell_poisson_ = poisson_at_;
  fem::CellModuli cells;
  const double alpha = body_->material.thermal_expansion;
  for (size_t c = 0; c < cell_young_.size(); ++c) {
    const double l = fem::lame_lambda(cell_young_[c], cell_poisson_[c]);
    const double m = fem::lame_mu(cell_young_[c], cell_poisson_[c]);
    cells.lambda.push_back(l);
    cells.mu.push_back(m);
    cells.beta.push_back((3 * l + 2 * m) * alpha);
  }
  fem::reassemble_mechanics(body_->mesh, cells, m_, spread(u_rows_), spread(theta_rows_));
  return true;
}

fem::BodyMatrices BodySystem::subdomain_matrices(int s) const {
  auto m = fem::assemble_body(subdomains_.at(static_cast<size_t>(s)).mesh, body_->material);
  if (lumped_)  // cell by cell: Σ_s of the subdomains' lumped M_θ is the body's
    fem::lump_heat_capacity(m.mass_theta, subdomains_.at(static_cast<size_t>(s)).mesh,
                            body_->material.heat_capacity());
  if (!massless_.empty()) {  // cell by cell, so Σ_s of the subdomains' is the body's
    const auto& sub = subdomains_.at(static_cast<size_t>(s));
    std::vector<char> local(sub.global_node.size());
    for (size_t a = 0; a < local.size(); ++a)
      local[a] = massless_[static_cast<size_t>(sub.global_node[a])];
    m.mass_u = fem::singular_mass_u(sub.mesh, body_->material, local);
  }
  return m;
}

core::SparseMatrix BodySystem::subdomain_constant_film(int s) const {
  if (constant_film_facets_.empty()) return {};
  const auto& sub = subdomains_.at(static_cast<size_t>(s));
  std::map<int, int> cell, node;  // body → subdomain numbering
  for (size_t c = 0; c < sub.global_cell.size(); ++c)
    cell[sub.global_cell[c]] = static_cast<int>(c);
  for (size_t a = 0; a < sub.global_node.size(); ++a)
    node[sub.global_node[a]] = static_cast<int>(a);
  std::vector<fem::WeightedFacet> local;
  for (const auto& f : constant_film_facets_) {
    const auto it = cell.find(f.facet.cell);
    if (it == cell.end()) continue;  // a facet of another subdomain's cell
    auto g = f;
    g.facet.cell = it->second;
    for (int k = 0; k < mesh::n_nodes(g.facet.type); ++k)
      g.facet.nodes[static_cast<size_t>(k)] = node.at(f.facet.nodes[static_cast<size_t>(k)]);
    local.push_back(g);
  }
  return fem::boundary_mass(sub.mesh, local);
}

void BodySystem::add_varying_films(double t, const core::Vector& x, core::Vector& y) const {
  for (const auto& f : films_)
    if (!f.constant) {
      // applied in every inner iteration of the heat step's Newton: one work vector, reused
      if (!film_work_.get() || film_work_.size() != y.size()) film_work_ = core::Vector(y.size());
      f.unit.mult(x, film_work_);
      y.axpy(f.film.coefficient(t), film_work_);
    }
}

void BodySystem::add_boundary_term(double t, const core::Vector& theta, core::Vector& y) const {
  add_varying_films(t, theta, y);
  if (radiation_.empty()) return;
  auto yv = y.view();
  for_each_radiated(t, theta, [&](PetscInt a, double q) { yv[a] += q; });
}

void BodySystem::add_boundary_derivative(double t, const core::Vector& theta, const core::Vector& x,
                                         core::Vector& y) const {
  add_varying_films(t, x, y);  // linear in θ: its derivative is itself
  if (radiation_.empty()) return;
  const auto th = theta.read();
  const auto xv = x.read();
  auto yv = y.view();
  for (const auto& r : radiation_) {
    const double es = r.radiation.emissivity(t) * stefan_boltzmann;
    for (const auto& [a, w] : r.weights) {
      const double v = th[a];
      yv[a] += 4.0 * w * es * std::abs(v * v * v) * xv[a];
    }
  }
}

BodySystem::BoundaryPower BodySystem::boundary_heat_loss(double t,
                                                         const core::Vector& theta) const {
  BoundaryPower p;
  if (films_.empty() && radiation_.empty()) return p;
  {
    const auto th = theta.read();
    for (const auto& f : films_) {
      const double h = f.film.coefficient(t), amb = f.film.ambient(t);
      for (const auto& [a, w] : f.weights) p.film += h * w * (th[a] - amb);
    }
  }
  for_each_radiated(t, theta, [&](PetscInt, double q) { p.radiation += q; });
  return p;
}

template <class Visit>
void BodySystem::for_each_radiated(double t, const core::Vector& theta, Visit&& visit) const {
  const auto th = theta.read();
  for (const auto& r : radiation_) {
    const double es = r.radiation.emissivity(t) * stefan_boltzmann;
    const double amb = r.radiation.ambient(t);
    const double amb4 = amb * amb * amb * amb;
    for (const auto& [a, w] : r.weights) {
      const double x = th[a];
      visit(a, w * es * (x * std::abs(x * x * x) - amb4));
    }
  }
}

void BodySystem::add_reaction_group(ReactionGroup group) {
  // Two [[boundary]] tables on one face (each prescribing its own components) are one support:
  // one set of columns, its dofs the union (a second set would repeat the columns' names).
  const auto same = std::find_if(reactions_.begin(), reactions_.end(),
                                 [&](const ReactionGroup& r) { return r.label == group.label; });
  if (same == reactions_.end()) {
    reactions_.push_back(std::move(group));
    return;
  }
  for (int k = 0; k < dim_; ++k)
    same->dofs[k].insert(same->dofs[k].end(), group.dofs[k].begin(), group.dofs[k].end());
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
    if (bc.force[k]) {
      CoupledFace face{body_name + "_" + bc.where, k, {}, *bc.force[k]};
      for (const int a : nodes) face.dofs.push_back(dim_ * a + k);
      std::sort(face.dofs.begin(), face.dofs.end());
      coupled_.push_back(std::move(face));
    }
  }
  if (any_displacement) add_reaction_group(std::move(group));
  if (bc.temperature)
    for (const int a : nodes) th_prescribed_[a] = *bc.temperature;
  if (bc.heat_flux) th_loads_.push_back({*bc.heat_flux, 0, facet_weights});
  if (bc.film || bc.radiation) {
    const auto weights = sparse_weights(fem::boundary_integrals(mesh, bc.where));
    if (bc.film) {
      FilmBoundary f{*bc.film, true, weights, {}};
      const auto& h = bc.film->coefficient.values();
      f.constant = std::all_of(h.begin(), h.end(), [&](double v) { return v == h.front(); });
      std::vector<fem::WeightedFacet> facets;
      for (const auto& facet : mesh.boundary(bc.where))
        facets.push_back({facet, f.constant ? h.front() : 1.0});
      if (f.constant)
        constant_film_facets_.insert(constant_film_facets_.end(), facets.begin(), facets.end());
      else
        f.unit = fem::boundary_mass(mesh, facets, spread(theta_rows_));
      films_.push_back(std::move(f));
    }
    if (bc.radiation) radiation_.push_back({*bc.radiation, weights});
  }
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
  if (films_.empty()) return;
  auto v = f.view();
  for (const auto& film : films_) {  // h ∫ θ∞ N_a dS: the ambient's side of h(θ − θ∞)
    const double value = film.film.coefficient(t) * film.film.ambient(t);
    for (const auto& [a, w] : film.weights) v[a] += value * w;
  }
}

}  // namespace tc::physics
