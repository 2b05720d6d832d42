#pragma once
// Load control of a face through a rigid coupling ([[boundary]] force = …; docs/theory.md,
// "Load control"): the displacement component k of every node of the face is one unknown w
// (the face moves as the reference point of Abaqus' and CalculiX's kinematic coupling), and
// the resultant of the forces the body exerts on the face's nodes in k balances the
// prescribed force F(t):
//   u_d = w for d in the face's dofs D_j,   h_j = Σ_{d∈D_j} (A u − b)_d − F_j(t) = 0.
// The face's dofs are eliminated as Dirichlet dofs (ConstrainedSolver) whose value w is found
// per step: with Φ_j = A_D⁻¹-harmonic lifting of the face (Φ_j = 1 on D_j, 0 on the other
// constrained dofs, (AΦ_j) = 0 on the free ones) and u = A_D⁻¹(b − Bᵀλ) with the constrained
// values u_D, symmetry of A gives without forming u
//   Σ_{D_j}(A u − b) = (AΦ_j)_Dᵀ u_D − Φ_jᵀ b + (BΦ_j)ᵀ λ    (rows B not on D_j),
// affine in w: ∂/∂w_l = S_jl = Σ_{d∈D_l}(AΦ_j)_d = Φ_jᵀAΦ_l. Without contact the step's
// w solves S w = F − R(0) (one solve); with contact w is eliminated from the contact QP, a
// rank-one term gᵀ = (BΦ)ᵀ (ContactCoupling::solve_qp).
// Owned by a BodyField; the Φ_j are formed once (A is factorised once per run).
#include <Eigen/Dense>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/physics/body/body_system.hpp"

namespace tc::physics {

class RigidCoupling {
 public:
  /// The faces of `sys` with a force, their liftings Φ_j by `solver` (A_u factorised with
  /// the faces' dofs constrained) and S; `a` applies A (A x → y). `dynamic`: A has inertia.
  RigidCoupling(const BodySystem& sys, const ConstrainedSolver& solver,
                const std::function<void(const core::Vector&, core::Vector&)>& a);

  [[nodiscard]] int size() const { return static_cast<int>(faces_->size()); }
  [[nodiscard]] const CoupledFace& face(int j) const { return (*faces_)[j]; }
  [[nodiscard]] const core::Vector& lifting(int j) const { return phi_[j]; }
  [[nodiscard]] const Eigen::MatrixXd& stiffness() const { return s_; }
  /// e_jᵀA e_j (e_j the face's indicator): the face moved alone, the rest held; bounds every
  /// slope of the face's resultant in w from above (a first secant slope).
  [[nodiscard]] double face_stiffness(int j) const { return face_stiffness_[j]; }

  /// The faces' displacements w (the unknowns; start: u⁰ on each face).
  [[nodiscard]] std::vector<double>& w() { return w_; }
  [[nodiscard]] const std::vector<double>& w() const { return w_; }
  /// Writes w into the faces' dofs of x, and remembers it as the value x was solved with.
  void write(core::Vector& x);
  /// The w that x was last written with (write()).
  [[nodiscard]] const std::vector<double>& written() const { return written_; }
  /// R_j = (AΦ_j)_Dᵀ x_D − Φ_jᵀ b: Σ_{D_j}(A u − b) of u = A_D⁻¹b with x's constrained
  /// values (only those are read), before any contact force.
  [[nodiscard]] std::vector<double> free_resultant(const core::Vector& x,
                                                   const core::Vector& b) const;
  /// Without contact: w of S w = F(t) − R(0), written into x (throws NumericalError when S is
  /// singular: the body floats in a loaded direction).
  void balance(double t, const core::Vector& b, core::Vector& x, int step, int iteration);
  /// x += Σ_j (w_j − written_j) Φ_j, then written = w: the u of the faces' final w from a
  /// solve with the written ones (linear in w).
  void shift_to_w(core::Vector& x);

 private:
  const BodySystem* sys_;
  const std::vector<CoupledFace>* faces_;
  std::vector<core::Vector> phi_;
  // (AΦ_j) on the constrained dofs, (dof, value) pairs: the lifting's reaction.
  std::vector<std::vector<std::pair<PetscInt, double>>> a_phi_;
  Eigen::MatrixXd s_;
  std::vector<double> face_stiffness_;
  std::vector<double> w_, written_;
};

}  // namespace tc::physics
