#pragma once
// One body's discrete thermo-elastic system (ch. 4): its constant matrices, its Dirichlet
// dofs with their time tables, and its time-dependent loads f_u(t) (3.2) and f_θ(t) (3.3).
// Displacement dofs are interleaved (dim·a + k), temperature dofs one per node.
#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tc/fem/assembler.hpp"
#include "tc/fem/nonlinear_heat.hpp"
#include "tc/mesh/partition.hpp"
#include "tc/model/problem.hpp"

namespace tc::physics {

/// The support of one [[boundary]] with a displacement: its history columns
/// reaction_<body>_<where>_x|y|z sum the reactions over its constrained dofs per component.
struct ReactionGroup {
  std::string label;                          // reaction_<body>_<where>
  std::array<std::vector<PetscInt>, 3> dofs;  // constrained dofs per component
};

/// A face under load control ([[boundary]] force): component `component` of its nodes is one
/// unknown, whose resultant nodal force is `force`(t) (rigid_coupling.hpp).
struct CoupledFace {
  std::string label;  // <body>_<where>: the history columns displacement_…_x|y|z, force_…
  int component = 0;
  std::vector<PetscInt> dofs;  // sorted
  TimeTable force;             // [N]
};

class BodySystem {
 public:
  /// Assembles the matrices and load integrals of body `index` of the problem.
  BodySystem(const Problem& problem, int index);

  [[nodiscard]] const Body& body() const { return *body_; }
  [[nodiscard]] int dim() const { return dim_; }
  [[nodiscard]] PetscInt n_u() const { return dim_ * body_->mesh.n_nodes(); }
  [[nodiscard]] PetscInt n_theta() const { return body_->mesh.n_nodes(); }
  /// All five have their rows spread over the ranks (core::SparseMatrix::over_ranks) when the
  /// body is undecomposed and its factors are spread (linalg::ranks_sharing_a_factor > 1): M_u,
  /// K_u and K_uθ in the displacement dofs' blocks, M_θ and K_θ in the temperature dofs'.
  [[nodiscard]] const fem::BodyMatrices& matrices() const { return m_; }

  [[nodiscard]] const std::vector<PetscInt>& u_dirichlet_dofs() const { return u_dofs_; }
  [[nodiscard]] const std::vector<PetscInt>& theta_dirichlet_dofs() const { return th_dofs_; }
  /// Writes u_D(t) (resp. θ_D(t)) into the constrained entries of x; others are untouched.
  void prescribe_u(double t, core::Vector& x) const;
  void prescribe_theta(double t, core::Vector& x) const;
  /// Writes the right derivative du_D/dt at t into the constrained entries of v.
  void prescribe_u_rate(double t, core::Vector& v) const;

  /// f_u(t) of (3.2): tractions p_N on Γ_uN and body force f.
  void mechanical_load(double t, core::Vector& f) const;
  /// f_θ(t) of (3.3): heat flux q_N on Γ_θN and heat source r.
  void thermal_load(double t, core::Vector& f) const;

  // Film and radiation boundaries (q = h(θ − θ∞), q = εσ(θ⁴ − θ∞⁴) leaving the body).
  // A film whose h is constant in time is linear and fixed: H = Σ h∫N_aN_b dS joins the heat
  // operator M_θ/τ + K_θ + H (factorised once), its h∫θ∞N_a dS the load (thermal_load). A film
  // whose h changes in time and every radiation are the boundary term N(t, θ) of the heat
  // step A θ + N(t, θ) = b, solved by Newton (physics/body/boundary_heat_newton.hpp).

  /// Σ h ∫N_aN_b dS of the films with constant h (K_θ's pattern); null when there is none.
  [[nodiscard]] const core::SparseMatrix* constant_film() const {
    return constant_film_.get() ? &constant_film_ : nullptr;
  }
  /// The same on the cells of subdomain s (Σ_s = constant_film()); empty when there is none.
  [[nodiscard]] core::SparseMatrix subdomain_constant_film(int s) const;
  /// The heat step has the boundary term N(t, θ): radiation, or a film with h(t).
  [[nodiscard]] bool has_boundary_term() const {
    return !radiation_.empty() ||
           std::any_of(films_.begin(), films_.end(), [](const auto& f) { return !f.constant; });
  }
  /// y += N(t, θ) = Σ_{films with h(t)} h(t) H θ + Σ_radiation w_a εσ(θ_a|θ_a|³ − θ∞⁴), the
  /// radiation integrated by the nodal (trapezoidal) rule, w_a = ∫N_a dS (docs/choices.md).
  void add_boundary_term(double t, const core::Vector& theta, core::Vector& y) const;
  /// y += N'(t, θ) x, the derivative: h(t) H x + diag(4 w_a εσ |θ_a|³) x.
  void add_boundary_derivative(double t, const core::Vector& theta, const core::Vector& x,
                               core::Vector& y) const;
  /// The heat leaving the body at t through its film and its radiation boundaries [W]:
  /// Σ h ∫(θ − θ∞) dS = Σ_a h w_a (θ_a − θ∞) and Σ_a w_a εσ(θ_a|θ_a|³ − θ∞⁴).
  struct BoundaryPower {
    double film = 0, radiation = 0;
  };
  [[nodiscard]] BoundaryPower boundary_heat_loss(double t, const core::Vector& theta) const;

  [[nodiscard]] const std::vector<ReactionGroup>& reaction_groups() const { return reactions_; }
  /// The faces under load control; their dofs are among u_dirichlet_dofs(), with values the
  /// coupling (RigidCoupling) writes, not prescribe_u.
  [[nodiscard]] const std::vector<CoupledFace>& coupled_faces() const { return coupled_; }
  /// ∫ N_a dx per node: turns nodal fields into integrals (e.g. thermal energy).
  [[nodiscard]] const std::vector<double>& node_volumes() const { return volumes_; }
  /// The weights of the heat capacity ρc·w_a that the heat step's M_θ holds on the diagonal
  /// sum 1ᵀM_θ(θ − θ₀) = Σ_a ρc w_a(θ_a − θ₀): ∫N_a, or fem::lumped_volumes when M_θ is lumped
  /// by HRZ somewhere (then the thermal energy is what the scheme conserves).
  [[nodiscard]] const std::vector<double>& capacity_volumes() const {
    return capacity_volumes_.empty() ? volumes_ : capacity_volumes_;
  }

  /// The FETI subdomains of the body (6.2; empty unless body().subdomains > 1) and the
  /// subdomain of every cell (all 0 when not decomposed).
  [[nodiscard]] const std::vector<mesh::SubMesh>& subdomains() const { return subdomains_; }
  [[nodiscard]] const std::vector<int>& cell_subdomain() const { return cell_part_; }
  /// The body's matrices assembled on the cells of subdomain s only (Σ_s = matrices()),
  /// with the same heat-capacity treatment.
  [[nodiscard]] fem::BodyMatrices subdomain_matrices(int s) const;
  /// The displacement dofs without inertia (contact_scheme = "modified_mass": the body's
  /// contact boundary), sorted; empty otherwise. M_u is zero on their rows and columns.
  [[nodiscard]] const std::vector<PetscInt>& massless_dofs() const { return massless_dofs_; }
  /// The material part of the heat step when κ or c_p is a table in θ (fem::NonlinearHeat,
  /// with the heat capacity lumped as M_θ is); null for constant properties.
  [[nodiscard]] const fem::NonlinearHeat* nonlinear_heat() const { return nonlinear_heat_.get(); }

  /// E or ν is a table in θ (fem::Material::nonlinear_moduli): K_u and K_uθ follow θ.
  [[nodiscard]] bool moduli_follow_temperature() const { return !cell_young_.empty(); }
  /// E and ν of cell c as K_u and K_uθ hold them (the material's numbers when constant): the
  /// stress output's (io::body_fields).
  [[nodiscard]] std::pair<double, double> cell_moduli(int c) const {
    if (cell_young_.empty()) return {body_->material.young_modulus, body_->material.poisson_ratio};
    return {cell_young_[static_cast<size_t>(c)], cell_poisson_[static_cast<size_t>(c)]};
  }
  /// The largest relative change max_c max(|E(θ_c) − E_c|/E_c, |ν(θ_c) − ν_c|/ν_c) of the
  /// cells' moduli at θ against those K_u and K_uθ hold, θ_c the mean of the cell's nodal θ
  /// (0 for constant moduli, or ν = 0 on both sides for the ν part).
  [[nodiscard]] double modulus_change(const core::Vector& theta) const;
  /// When modulus_change(θ) > tolerance (strictly: tolerance 0 re-assembles at every change),
  /// re-assembles K_u and K_uθ in place with the moduli of every cell at θ and returns true:
  /// the caller refactorises A_u (BodyField::refactorise_mechanics). Not collective.
  bool update_moduli(const core::Vector& theta, double tolerance);

 private:
  // y += h(t) H x over the films whose h changes in time (H = ∫N_aN_b dS of each)
  void add_varying_films(double t, const core::Vector& x, core::Vector& y) const;
  // visit(a, q) for each radiating node a, q = w_a εσ(θ_a|θ_a|³ − θ∞⁴) its heat loss [W]
  template <class Visit>
  void for_each_radiated(double t, const core::Vector& theta, Visit&& visit) const;
  struct NodalLoad {  // value(t) · weights[a] on dof block·a + component
    TimeTable value;
    int component = 0;
    std::vector<std::pair<PetscInt, double>> weights;
  };
  void add_reaction_group(ReactionGroup group);  // merged with a group of the same face
  void add_boundary(const BoundaryCondition& bc, const std::string& body_name);
  struct FilmBoundary {
    Film film;
    bool constant = true;                              // h the same at every t
    std::vector<std::pair<PetscInt, double>> weights;  // ∫N_a dS
    core::SparseMatrix unit;                           // ∫N_aN_b dS (h(t) films only)
  };
  struct RadiationBoundary {
    Radiation radiation;
    std::vector<std::pair<PetscInt, double>> weights;  // ∫N_a dS
  };
  static void apply(const std::vector<NodalLoad>& loads, int block, double t, core::Vector& f);

  const Body* body_;
  int dim_;
  // The rows of the matrices held by this rank: spread over the ranks as the body's factors
  // are (an undecomposed body on several ranks with MUMPS), else whole. theta_rows_ also
  // deals K_uθ's columns, and the film matrices' rows.
  core::RowBlocks u_rows_;
  core::RowBlocks theta_rows_;
  fem::BodyMatrices m_;
  std::vector<double> volumes_;
  std::vector<double> capacity_volumes_;  // lumped_volumes on a mesh with HRZ cells
  std::map<PetscInt, TimeTable> u_prescribed_, th_prescribed_;  // a later [[boundary]] wins
  std::vector<PetscInt> u_dofs_, th_dofs_;
  std::vector<NodalLoad> u_loads_, th_loads_;
  std::vector<ReactionGroup> reactions_;
  std::vector<CoupledFace> coupled_;
  std::vector<int> cell_part_;
  std::vector<mesh::SubMesh> subdomains_;
  bool lumped_ = false;
  std::vector<char> massless_;  // per node
  std::vector<PetscInt> massless_dofs_;
  std::vector<FilmBoundary> films_;
  mutable core::Vector film_work_;  // add_varying_films
  std::vector<RadiationBoundary> radiation_;
  std::vector<fem::WeightedFacet> constant_film_facets_;  // body numbering, weight h
  core::SparseMatrix constant_film_;
  std::unique_ptr<fem::NonlinearHeat> nonlinear_heat_;
  // E(θ), ν(θ): the moduli per cell K_u and K_uθ are assembled with (empty when constant),
  // and the cells' moduli at the θ of the last modulus_change
  std::vector<double> cell_young_, cell_poisson_;
  mutable std::vector<double> young_at_, poisson_at_;
};

}  // namespace tc::physics
