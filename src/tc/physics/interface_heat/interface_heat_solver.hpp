#pragma once
// The heat step of a contact pair with the conductance L_θγ of §4.4 on the left (implicit):
//
//   (A + L) θ = b,   A = diag(A_1, …, A_N) over the bodies of the contact pairs,  A_i = M_θ^i/τ +
//   K_θ^i  (factorised once, Dirichlet
//                                                                  data eliminated),
//
// where L = β_C ∫ γ [θ][χ] changes with γ = λ_n at every iteration of the fixed point (6.3).
// L lives on the interface only: L = Pᵀ L_Γ P with P the restriction to Γ, the nodes of the
// contact surfaces (a fixed set). With G the solve with A (Dirichlet values θ_D kept) and
// S = P G₀ Pᵀ (G₀: the same solve with homogeneous data; S is symmetric positive semidefinite,
// zero on constrained nodes), the interface values y = Pθ solve
//
//   (I + S L_Γ) y = P G(b),   then   θ = G(b − Pᵀ L_Γ y),
//
// an exact solve of the coupled system (Woodbury's identity written on the interface) with two
// solves per body and one dense LU of the nodes that L touches: A is never refactorised. Where
// the compliance can (linalg::Compliance::begin_corrected: CHOLMOD's kept forward columns), the
// two solves are one corrected solve, for the price of one.
// I + S L_Γ is similar to I + S^½ L_Γ S^½ (on the free nodes), so its eigenvalues are ≥ 1.
//
// L changes little from one iteration of (6.3) to the next (γ = λ_n moves by the fixed point's
// residual), so where L's nodes are among those of the last LU (the working set J), the dense
// system is solved by iterative refinement with that LU, each step a product with S_JJ L_JJ
// and a pair of triangular solves (O(|J|²) against the LU's O(|J|³)), to a residual of
// 1e-12‖y₀‖; a new LU only when J must grow or the refinement does not contract.
//
// A column of S costs one solve with A_i; columns are computed when their node first carries
// conductance, all the new ones of a body together, and kept for the run (the matrices do not
// change while τ does not).
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <array>
#include <span>
#include <vector>

#include "tc/contact/mortar_pair.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/linalg/compliance.hpp"

namespace tc::physics {

/// L_θγ of one contact pair between two bodies of an InterfaceHeatSolver.
struct PairConductance {
  const contact::ThermalContact* l;
  int slave, master;  // the solver's bodies
};

class InterfaceHeatSolver {
 public:
  /// Per body (the bodies of the contact pairs): its solver, its node count and the nodes of its
  /// contact surfaces, of every pair (its node numbering = its temperature dofs). The solvers
  /// must outlive this object.
  InterfaceHeatSolver(std::vector<const ConstrainedSolver*> solvers, std::vector<PetscInt> n,
                      std::vector<std::vector<int>> nodes);
  /// One pair: the slave is body 0, the master body 1.
  InterfaceHeatSolver(const ConstrainedSolver& slave, PetscInt n_slave,
                      const std::vector<int>& slave_nodes, const ConstrainedSolver& master,
                      PetscInt n_master, const std::vector<int>& master_nodes)
      : InterfaceHeatSolver({&slave, &master}, {n_slave, n_master}, {slave_nodes, master_nodes}) {}

  /// Takes L_θγ of every pair (blocks over the full node numbering, as
  /// MortarPair::thermal_conductance returns them) for the following solves; throws Error when L
  /// has an entry off Γ. `refine`: keep the last LU for refinement where it can serve; without
  /// it J and the LU are those of this L, whatever came before (the first heat step of a time
  /// step: then no state passes from one step to the next, and a restart repeats a run).
  void set_conductance(std::span<const PairConductance> pairs, bool refine = false);
  void set_conductance(const contact::ThermalContact& l, bool refine = false) {
    const PairConductance one{&l, 0, 1};
    set_conductance(std::span(&one, 1), refine);
  }

  /// Solves (A + L) θ = b for every body. On entry x_i hold the Dirichlet values at their
  /// constrained dofs (other entries are ignored), as for ConstrainedSolver::solve.
  void solve(std::span<const core::Vector* const> b, std::span<core::Vector* const> x) const;
  void solve(const core::Vector& b_slave, const core::Vector& b_master, core::Vector& x_slave,
             core::Vector& x_master) const {
    solve(std::array{&b_slave, &b_master}, std::array{&x_slave, &x_master});
  }

  /// Number of interface nodes in the dense system: the working set J, which holds those L
  /// currently couples.
  [[nodiscard]] int active_nodes() const { return static_cast<int>(active_.size()); }
  /// Solves with A spent on columns of S so far (one per interface node that ever carried
  /// conductance).
  [[nodiscard]] long setup_solves() const { return setup_solves_; }
  /// LUs of I + S_JJ L_JJ so far, and refinement steps with an earlier one.
  [[nodiscard]] long factorizations() const { return factorizations_; }
  [[nodiscard]] long refinement_steps() const { return refinement_steps_; }

  /// The record of each body's S (linalg::Compliance::dofs, chunks: the columns added in which
  /// blocks), appended to `record`, and S rebuilt from such a record: a restart's S then has the
  /// bits of the run's (the columns grow with the nodes that carried conductance, in blocks of
  /// their first contact; one block of all of them gave other bits, history.csv differed from
  /// the uninterrupted run's by 1e-10 relative after a few steps, issue 41).
  void save_compliance(std::vector<std::vector<int>>& record) const;
  void replay_compliance(std::span<const std::vector<int>> record);
  /// How body i's S is grown (linalg::Compliance::path).
  [[nodiscard]] const linalg::Compliance& compliance(int i) const { return *compliance_[i]; }

 private:
  [[nodiscard]] int n_bodies() const { return static_cast<int>(solver_.size()); }
  [[nodiscard]] int body_of(int g) const;  // the body of global interface index g
  void factorize() const;                  // the LU of I + S_JJ L_JJ with the current L
  void lu_solve(Eigen::VectorXd& y) const;
  // y ← (I + S_JJ L_JJ)⁻¹ y, by the LU where it is current, else refining with it
  void interface_solve(Eigen::VectorXd& y) const;

  std::vector<const ConstrainedSolver*> solver_;
  std::vector<PetscInt> n_;
  std::vector<std::vector<int>> nodes_;  // interface nodes of each body (sorted)
  std::vector<std::vector<int>> index_;  // body node → global interface index, or −1
  std::vector<int> offset_;              // first global interface index of each body, then n_Γ
  // S_i = (A_i⁻¹) on the interface nodes of body i that have carried conductance, grown as
  // nodes first do: their columns in blocks of right-hand sides (restricted to the supernodes
  // they reach when the factor allows), not one solve each (linalg::Compliance).
  std::vector<std::unique_ptr<linalg::Compliance>> compliance_;
  long setup_solves_ = 0;

  std::vector<int> active_;               // J: global interface indices, ⊇ the rows of L
  Eigen::SparseMatrix<double> l_active_;  // L_Γ on J
  Eigen::MatrixXd s_;                     // S_JJ (zero between bodies)
  // LU of I + S_JJ L_JJ with partial pivoting, by LAPACK (dgetrf: the BLAS's kernels, 2× Eigen's
  // PartialPivLU at 1 400–2 000 nodes, which is 0.1–0.3 s per coupling iteration), for the L of
  // the last factorisation; a cache that solve() renews when refinement fails.
  mutable Eigen::MatrixXd lu_;
  mutable std::vector<int> pivots_;
  mutable bool lu_current_ = false;  // the LU is of the current L
  mutable long factorizations_ = 0, refinement_steps_ = 0;
  mutable std::vector<core::Vector> rhs_;
  mutable std::vector<linalg::CorrectedSolve> corrected_;  // per body, within solve()
};

}  // namespace tc::physics
