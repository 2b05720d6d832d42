#pragma once
// One body's discrete thermo-elastic system (ch. 4): its constant matrices, its Dirichlet
// dofs with their time tables, and its time-dependent loads f_u(t) (3.2) and f_θ(t) (3.3).
// Displacement dofs are interleaved (dim·a + k), temperature dofs one per node.
#include <map>
#include <string>
#include <vector>

#include "tc/fem/assembler.hpp"
#include "tc/mesh/partition.hpp"
#include "tc/physics/problem.hpp"

namespace tc::physics {

/// The support of one [[boundary]] with a displacement: its history columns
/// reaction_<body>_<where>_x|y|z sum the reactions over its constrained dofs per component.
struct ReactionGroup {
  std::string label;                          // reaction_<body>_<where>
  std::array<std::vector<PetscInt>, 3> dofs;  // constrained dofs per component
};

class BodySystem {
 public:
  /// Assembles the matrices and load integrals of body `index` of the problem.
  BodySystem(const Problem& problem, int index);

  [[nodiscard]] const Body& body() const { return *body_; }
  [[nodiscard]] int dim() const { return dim_; }
  [[nodiscard]] PetscInt n_u() const { return dim_ * body_->mesh.n_nodes(); }
  [[nodiscard]] PetscInt n_theta() const { return body_->mesh.n_nodes(); }
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

  [[nodiscard]] const std::vector<ReactionGroup>& reaction_groups() const { return reactions_; }
  /// ∫ N_a dx per node: turns nodal fields into integrals (e.g. thermal energy).
  [[nodiscard]] const std::vector<double>& node_volumes() const { return volumes_; }

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

 private:
  struct NodalLoad {  // value(t) · weights[a] on dof block·a + component
    TimeTable value;
    int component = 0;
    std::vector<std::pair<PetscInt, double>> weights;
  };
  void add_boundary(const BoundaryCondition& bc, const std::string& body_name);
  static void lump(core::SparseMatrix& m);  // row-sum lumping, in place
  static void apply(const std::vector<NodalLoad>& loads, int block, double t, core::Vector& f);

  const Body* body_;
  int dim_;
  fem::BodyMatrices m_;
  std::vector<double> volumes_;
  std::map<PetscInt, TimeTable> u_prescribed_, th_prescribed_;  // a later [[boundary]] wins
  std::vector<PetscInt> u_dofs_, th_dofs_;
  std::vector<NodalLoad> u_loads_, th_loads_;
  std::vector<ReactionGroup> reactions_;
  std::vector<int> cell_part_;
  std::vector<mesh::SubMesh> subdomains_;
  bool lumped_ = false;
  std::vector<char> massless_;  // per node
  std::vector<PetscInt> massless_dofs_;
};

}  // namespace tc::physics
