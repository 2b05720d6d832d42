#pragma once
// Solves A x = b with x prescribed on a fixed set of dofs (Dirichlet data, 2.2 and 2.9) by
// symmetric elimination: the reduced matrix (rows and columns of the constrained dofs
// replaced by a scaled identity) is factorised once; each solve lifts the prescribed values
// to the right-hand side. The constrained set must not change over the run; their values may.
// A body cut into subdomains is solved by Total FETI instead (feti::Feti, 6.2), with the same
// contract: callers do not know which one they have.
#include <memory>
#include <span>
#include <vector>

#include "tc/core/petsc.hpp"
#include "tc/feti/feti.hpp"

namespace tc::physics {

class ConstrainedSolver {
 public:
  /// `ranks`: core::FactorRanks::all_ranks spreads the factor over the ranks (MUMPS; every
  /// method is then collective), as core::CholeskySolver says.
  ConstrainedSolver(const core::SparseMatrix& a, std::vector<PetscInt> dofs,
                    const std::string& package,
                    core::FactorRanks ranks = core::FactorRanks::this_rank);
  /// The same consuming `a` (core::CholeskySolver's consuming constructor): the factor's peak
  /// holds no copy of the operator.
  ConstrainedSolver(core::SparseMatrix&& a, std::vector<PetscInt> dofs, const std::string& package,
                    core::FactorRanks ranks = core::FactorRanks::this_rank);
  /// The same system solved by FETI over subdomains (the FETI object owns the Dirichlet dofs).
  explicit ConstrainedSolver(std::unique_ptr<feti::Feti> feti);
  ~ConstrainedSolver();
  ConstrainedSolver(ConstrainedSolver&&) noexcept;

  /// On entry x holds the prescribed values at the constrained dofs (other entries are
  /// ignored); on exit x solves the equations of the free dofs.
  void solve(const core::Vector& b, core::Vector& x) const;
  /// X = A⁻¹B with zero prescribed values, for k right-hand sides at once (dense n × k; the
  /// constrained rows of B are zeroed in place).
  void solve_homogeneous_many(::Mat b, ::Mat x) const;
  /// The rows `rows` of A⁻¹[e_c for c in cols] with zero prescribed values (a constrained c
  /// gives a zero column), column-major |rows| × |cols|, without forming the n × k block:
  /// core::CholeskySolver::unit_solve_rows, the same bits as solve_homogeneous_many on that
  /// block; with a factor over the ranks, MUMPS's selected entries of A⁻¹, any number of
  /// columns at once (to round-off). False (nothing written) when the factorisation cannot
  /// (FETI, MUMPS on one rank).
  bool solve_unit_rows(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                       double* out) const;
  /// Whether forward_compliance pays for a first set of `dofs` (blocks of `block` columns
  /// otherwise): core::CholeskySolver::forward_compliance_pays. False with FETI or MUMPS.
  [[nodiscard]] bool forward_compliance_pays(std::span<const PetscInt> dofs, int block) const;
  /// S(T, fresh) of S = (A⁻¹)_TT with zero prescribed values, T the dofs of the earlier calls
  /// with `kept` then `fresh` (a constrained dof gives a zero row and column), by forward solves
  /// only: core::CholeskySolver::forward_compliance. Equal to solve_unit_rows to round-off.
  /// False (nothing written) when the factorisation cannot.
  bool forward_compliance(core::ForwardColumnsPtr& kept, std::span<const PetscInt> fresh,
                          double* out) const;
  /// x = A⁻¹(b + E_T w), w given on T (kept's dofs, in their order), by the kept forward
  /// columns and the backward solve alone (core::CholeskySolver::solve_from_forward): with z
  /// empty b = 0 and the prescribed values zero; with z = L⁻¹P b from solve_forward_half, the
  /// second half of that solve, writing all of x. False (x untouched) when the factorisation
  /// cannot.
  bool solve_from_forward(const core::ForwardColumns& kept, std::span<const double> w,
                          core::Vector& x, std::span<const double> z = {}) const;
  /// The first half of solve() where the forward columns Y of a compliance on T are kept (x
  /// holding the prescribed values on entry, as solve): the lifting and the forward solve
  /// z = L⁻¹P b; writes x on T only, (A⁻¹b)_T = Yᵀz (core::CholeskySolver::forward_values),
  /// leaving x's other entries as they were. solve_from_forward with z finishes it: one forward
  /// and one backward solve for both A⁻¹b and A⁻¹E_T w. False (x untouched) when the
  /// factorisation cannot.
  bool solve_forward_half(const core::ForwardColumns& kept, std::span<const PetscInt> t,
                          const core::Vector& b, core::Vector& x, std::vector<double>& z) const;
  [[nodiscard]] const std::string& package() const {
    return feti_ ? feti_->package() : factor_.package();
  }
  /// Whether solve_unit_rows is MUMPS's selected inverse over the ranks, which prunes its
  /// solves by itself and is best given all columns in one call.
  [[nodiscard]] bool unit_rows_at_once() const { return !feti_ && factor_.distributed(); }
  /// The FETI solver when the body is decomposed, else null.
  [[nodiscard]] const feti::Feti* feti() const { return feti_.get(); }

 private:
  // Sorts dofs_ and keeps A(:, D) on the free rows (the lifting).
  void keep_lifting(const core::SparseMatrix& a);
  // The right-hand side with the prescribed values x_D lifted (symmetric elimination).
  const core::Vector& lifted(const core::Vector& b, const core::Vector& x) const;

  std::vector<PetscInt> dofs_;
  // A(:, D) on the free rows, column by column (CSC): the lifting b − A·x_D touches only
  // these entries (a full product with A cost 3.6 % of the ch. 7 example, where x_D = 0 on
  // the clamped body and |D| is a face).
  std::vector<PetscInt> lift_start_, lift_row_;
  std::vector<double> lift_value_;
  double diag_ = 1.0;  // of the constrained rows: the mean diagonal keeps the scale uniform
  core::CholeskySolver factor_;
  mutable core::Vector lift_, rhs_;
  std::unique_ptr<feti::Feti> feti_;
};

}  // namespace tc::physics
