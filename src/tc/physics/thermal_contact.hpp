#pragma once
// The heat step of a contact pair with the conductance L_θγ of §4.4 on the left (implicit):
//
//   (A + L) θ = b,   A = diag(A_s, A_m),  A_i = M_θ^i/τ + K_θ^i  (factorised once, Dirichlet
//                                                                  data eliminated),
//
// where L = β_C ∫ γ [θ][χ] changes with γ = λ_n at every iteration of the fixed point (6.3).
// L lives on the interface only: L = Pᵀ L_Γ P with P the restriction to Γ, the nodes of the
// two contact surfaces (a fixed set). With G the solve with A (Dirichlet values θ_D kept) and
// S = P G₀ Pᵀ (G₀: the same solve with homogeneous data; S is symmetric positive semidefinite,
// zero on constrained nodes), the interface values y = Pθ solve
//
//   (I + S L_Γ) y = P G(b),   then   θ = G(b − Pᵀ L_Γ y),
//
// an exact solve of the coupled system (Woodbury's identity written on the interface) with two
// solves per body and one dense LU of the nodes that L touches: A is never refactorised.
// I + S L_Γ is similar to I + S^½ L_Γ S^½ (on the free nodes), so its eigenvalues are ≥ 1.
//
// A column of S costs one solve with A_i; columns are computed when their node first carries
// conductance and kept for the run (the matrices do not change while τ does not).
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

#include "tc/contact/mortar_pair.hpp"
#include "tc/core/petsc.hpp"
#include "tc/physics/constrained_solver.hpp"

namespace tc::physics {

class InterfaceHeatSolver {
 public:
  /// `slave_nodes` / `master_nodes`: the nodes of each contact surface (each body's node
  /// numbering = its temperature dofs); `n_slave` / `n_master`: the bodies' node counts. The
  /// solvers must outlive this object.
  InterfaceHeatSolver(const ConstrainedSolver& slave, PetscInt n_slave,
                      const std::vector<int>& slave_nodes, const ConstrainedSolver& master,
                      PetscInt n_master, const std::vector<int>& master_nodes);

  /// Takes L_θγ (blocks over the full node numbering, as MortarPair::thermal_conductance
  /// returns them) for the following solves; throws Error when L has an entry off Γ.
  void set_conductance(const contact::ThermalContact& l);

  /// Solves (A + L) θ = b for both bodies. On entry x_* hold the Dirichlet values at their
  /// constrained dofs (other entries are ignored), as for ConstrainedSolver::solve.
  void solve(const core::Vector& b_slave, const core::Vector& b_master, core::Vector& x_slave,
             core::Vector& x_master) const;

  /// Number of interface nodes L currently couples (the size of the dense system).
  [[nodiscard]] int active_nodes() const { return static_cast<int>(active_.size()); }
  /// Solves with A spent on columns of S so far (one per interface node that ever carried
  /// conductance).
  [[nodiscard]] long setup_solves() const { return setup_solves_; }

 private:
  const std::vector<double>& column(int g);  // S e_g over the interface of g's body

  const ConstrainedSolver* solver_[2];
  PetscInt n_[2];
  std::vector<int> nodes_[2];  // interface nodes of each body (sorted)
  std::vector<int> index_[2];  // body node → interface index (global: slave first), or −1
  int n_gamma_ = 0;
  std::vector<std::vector<double>> columns_;  // S columns, by global interface index (lazy)
  long setup_solves_ = 0;

  std::vector<int> active_;                  // global interface indices with a row of L
  Eigen::SparseMatrix<double> l_active_;     // L_Γ on the active nodes
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;  // of I + S_JJ L_JJ
  mutable core::Vector rhs_[2];
};

}  // namespace tc::physics
