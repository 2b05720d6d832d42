#pragma once
// CHOLMOD's factorisation A = PᵀLLᵀP through SuiteSparse's public API (cholmod_analyze,
// cholmod_factorize, cholmod_solve2 and the public fields of cholmod_factor), for
// linalg::CholeskySolver, and the supernodal restricted and forward solves on it
// (cholmod_columns.cpp, cholmod_forward.cpp) that only the CHOLMOD compliance
// (linalg/compliance.hpp, CholmodCompliance) calls. PETSc's own CHOLMOD matrix keeps its factor in
// a private structure; owning the factor here removes any dependence on PETSc's version
// (docs/choices.md, "CHOLMOD through its own API").
#include <petscmat.h>

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

struct cholmod_factor_struct;  // cholmod.h's cholmod_factor, kept out of the includers

namespace tc::linalg {

struct CholeskyColumns;  // cholmod_supernodes.hpp
struct ForwardColumns;  // cholmod_forward.cpp: Y = L⁻¹P E_T kept between forward_compliance calls
struct ForwardColumnsDeleter {
  void operator()(ForwardColumns* y) const;
};
using ForwardColumnsPtr = std::unique_ptr<ForwardColumns, ForwardColumnsDeleter>;

/// The Cholesky factor of one SPD sequential AIJ matrix, made once on construction. The
/// matrix handed to CHOLMOD is the one PETSc's MATSOLVERCHOLMOD hands it (the upper triangle
/// of the rows read as the lower triangle of the columns), with CHOLMOD's default ordering
/// (AMD, METIS where AMD fills too much) and defaults: the same factor, the same bits.
class CholmodFactor {
 public:
  explicit CholmodFactor(::Mat a);
  /// The same, calling `release` once CHOLMOD's copy of a's triangle is made: the caller may
  /// free `a` there, before the factor is allocated. The sorted `decoupled` rows (eliminated
  /// dofs: zero off their diagonal) enter without their zero entries, so that their couplings
  /// add no fill (a smaller factor and fewer flops: bench/RESULTS.md, the 10⁶-dof case's memory).
  CholmodFactor(::Mat a, const std::function<void()>& release,
                std::span<const PetscInt> decoupled = {});
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  /// X = A⁻¹B for k right-hand sides, column-major with leading dimensions ldb and ldx (b and
  /// x distinct): one cholmod_solve2, level-3 BLAS for k > 1.
  void solve(const double* b, int ldb, double* x, int ldx, int k) const;
  [[nodiscard]] int size() const;
  /// The factor itself, for the restricted supernodal solves (read only).
  [[nodiscard]] const cholmod_factor_struct& factor() const;
  /// Whether CHOLMOD chose a supernodal factor (it takes a simplicial one below its flop
  /// threshold): the restricted and forward solves need one.
  [[nodiscard]] bool supernodal() const;

  // The supernodal solves of the compliance (A⁻¹)_TT (linalg/compliance.hpp): each returns
  // false, writing nothing, on a simplicial factor (or for another factor than kept's).

  /// out(i, j) = (A⁻¹ e_c)[rows[i]] for c = cols[j] (a column −1 is a zero right-hand side),
  /// column-major |rows| × |cols|: the forward solve visits only the supernodes the columns
  /// reach and the backward solve only those of the rows and their ancestors, each with
  /// CHOLMOD's own BLAS calls, so the entries are those of solve() on the same block, bit for
  /// bit.
  bool unit_solve_rows(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                       double* out) const;
  /// Whether forward_compliance is worth it for a first cover of `dofs`: when unit_solve_rows in
  /// blocks of `block` columns would cost more flops than the forward solves and more than a
  /// third of a second (or -tc_forward_compliance). Below that, the restricted solves keep the
  /// set-up's bits as they were.
  [[nodiscard]] bool forward_compliance_pays(std::span<const PetscInt> dofs, int block) const;
  /// Grows S = (A⁻¹)_TT by the forward solve alone: S = YᵀY with Y = L⁻¹P E_T (A = PᵀLLᵀP,
  /// E_T the unit columns of T), each supernode once with all the columns that reach it, and
  /// no backward solve. T is the dofs of the earlier calls with `kept`, then `fresh`; out is
  /// S(T, fresh), column-major |T| × |fresh| (on the first call |fresh| × |fresh|, exactly
  /// symmetric). A dof −1 gives a zero row and column. `kept` holds Y for later calls (on the
  /// supernodes each column reaches; about as large as S). The entries agree with
  /// unit_solve_rows to round-off, not to the bit (other sums).
  bool forward_compliance(ForwardColumnsPtr& kept, std::span<const PetscInt> fresh,
                          double* out) const;
  /// x = A⁻¹(b + E_T w) for w given on T (kept's dofs, in their order) and z = L⁻¹P b from
  /// forward_half (empty: b = 0): Y w = L⁻¹P E_T w from the kept columns, then the backward
  /// solve alone, x = PᵀL⁻ᵀ(z + Y w). Half a solve plus one pass over Y; equal to solve() on
  /// that right-hand side to round-off.
  bool solve_from_forward(const ForwardColumns& kept, std::span<const double> w, double* x,
                          std::span<const double> z = {}) const;
  /// The first half of solve(): z = L⁻¹P b (its own BLAS calls), for solve_from_forward to
  /// finish.
  bool forward_half(std::span<const double> b, std::vector<double>& z) const;
  /// (A⁻¹b)_T = Yᵀz for z = forward_half(b) without the backward solve: one pass over Y
  /// (E_Tᵀ A⁻¹ = (L⁻¹P E_T)ᵀ L⁻¹P). out is on T in kept's order; a dof of T given as −1 to
  /// forward_compliance gets 0.
  bool forward_values(const ForwardColumns& kept, std::span<const double> z,
                      std::span<double> out) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
  mutable std::shared_ptr<CholeskyColumns> columns_;  // the factor's structure, on first use
};

/// The CHOLMOD this binary is built with and the path it takes, for `thermocontact info`.
[[nodiscard]] std::string cholmod_path();

}  // namespace tc::linalg
