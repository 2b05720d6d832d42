#pragma once
// CHOLMOD's factorisation A = PᵀLLᵀP through SuiteSparse's public API (cholmod_analyze,
// cholmod_factorize, cholmod_solve2 and the public fields of cholmod_factor), for
// core::CholeskySolver and the supernodal restricted and forward solves of
// cholmod_columns.cpp and cholmod_forward.cpp. PETSc's own CHOLMOD matrix keeps its factor in a
// private structure; owning the factor here removes any dependence on PETSc's version
// (docs/choices.md, "CHOLMOD through its own API").
#include <petscmat.h>

#include <functional>
#include <memory>
#include <span>
#include <string>

struct cholmod_factor_struct;  // cholmod.h's cholmod_factor, kept out of the includers

namespace tc::core {

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
  /// add no fill (the 10⁶-dof case's factors 5 % smaller, issue 39).
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

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The CHOLMOD this binary is built with and the path it takes, for `thermocontact info`.
[[nodiscard]] std::string cholmod_path();

}  // namespace tc::core
