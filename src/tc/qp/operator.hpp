#pragma once
// The dual operator F of the QP (6.9), applied and never stored: later its application is a
// set of subdomain solves (F = B K⁻¹ Bᵀ), here any SPD linear map on PETSc vectors.
#include <functional>
#include <vector>

#include "tc/core/numeric/petsc.hpp"

namespace tc::qp {

using core::Vector;

/// y = F x for a symmetric positive (semi)definite F. Collective over the vectors' ranks.
class LinearOperator {
 public:
  virtual ~LinearOperator() = default;
  virtual void apply(const Vector& x, Vector& y) const = 0;
  /// A zero vector with the layout of F's domain (= range).
  [[nodiscard]] virtual Vector make_vector() const = 0;
};

/// F given as an assembled PETSc matrix (tests, benchmarks, explicit Schur complements).
class MatrixOperator final : public LinearOperator {
 public:
  explicit MatrixOperator(::Mat a) : a_(a) {}
  void apply(const Vector& x, Vector& y) const override;
  [[nodiscard]] Vector make_vector() const override;

 private:
  ::Mat a_;  // not owned
};

/// F given as a sequential dense matrix whose upper triangle holds F (the explicit dual
/// operators, symmetric to the bit). The product reads that triangle only (BLAS dsymv): half
/// the memory traffic of a general product, which is what the QP's applications cost once F
/// leaves the cache (2.0–2.3× faster from 2 205 to 6 615 rows, bench/RESULTS.md).
class SymmetricDenseOperator final : public LinearOperator {
 public:
  explicit SymmetricDenseOperator(::Mat a);  // MATSEQDENSE, square
  void apply(const Vector& x, Vector& y) const override;
  [[nodiscard]] Vector make_vector() const override;

 private:
  ::Mat a_;  // not owned
  PetscInt n_ = 0;
};

/// F given as a function y = F x and a layout template (matrix-free dual operators).
class FunctionOperator final : public LinearOperator {
 public:
  using Apply = std::function<void(const Vector&, Vector&)>;
  FunctionOperator(Apply apply, const Vector& layout)
      : apply_(std::move(apply)), layout_(layout.duplicate()) {}
  void apply(const Vector& x, Vector& y) const override { apply_(x, y); }
  [[nodiscard]] Vector make_vector() const override { return layout_.duplicate(); }

 private:
  Apply apply_;
  Vector layout_;
};

/// An upper estimate of λ_max(F) by `steps` Lanczos steps from a deterministic start vector:
/// the largest Ritz value plus its residual bound |β_k s_k|, which by the Kahan–Parlett
/// bound brackets an eigenvalue of F. Lanczos finds the extreme eigenvalue in far fewer
/// applications than the power method (a 1.9/λ step taken on an underestimate could break
/// the descent guarantee of the fixed-step expansion). Costs `steps` applications, fewer when
/// `tolerance` > 0: it stops as soon as the residual bound is within tolerance·ritz, since a
/// tighter estimate changes ᾱ = c/bound by less than that fraction.
struct EigenEstimate {
  double ritz = 0;   // the largest Ritz value (≤ λ_max)
  double bound = 0;  // ritz + residual: the value to divide by
  int applications = 0;
};
[[nodiscard]] EigenEstimate estimate_max_eigenvalue(const LinearOperator& f, int steps = 20,
                                                    double tolerance = 0);

/// The largest Ritz value of a Lanczos tridiagonal T_k (diagonal `diag`, off-diagonal
/// `off`, off[k−1] the coupling β_k to the next Lanczos vector) and its residual bound
/// β_k |s_k| (s the Ritz vector in the Lanczos basis). `applications` is left 0.
[[nodiscard]] EigenEstimate largest_ritz_value(const std::vector<double>& diag,
                                               const std::vector<double>& off);

}  // namespace tc::qp
