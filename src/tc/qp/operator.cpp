#include "tc/qp/operator.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "tc/core/numeric/blas.hpp"
#include "tc/core/verify.hpp"

namespace tc::qp {

void MatrixOperator::apply(const Vector& x, Vector& y) const {
  TC_PETSC(MatMult(a_, x.get(), y.get()));
}

Vector MatrixOperator::make_vector() const {
  ::Vec v = nullptr;
  TC_PETSC(MatCreateVecs(a_, &v, nullptr));
  auto out = Vector::adopt(v);
  out.zero();
  return out;
}

SymmetricDenseOperator::SymmetricDenseOperator(::Mat a) : a_(a) {
  PetscBool dense = PETSC_FALSE;
  TC_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(a), MATSEQDENSE, &dense));
  PetscInt m = 0;
  TC_PETSC(MatGetSize(a, &m, &n_));
  TC_VERIFY(dense && m == n_, "the dense dual operator is square and MATSEQDENSE");
}

void SymmetricDenseOperator::apply(const Vector& x, Vector& y) const {
  const PetscScalar* f = nullptr;
  PetscInt lda = 0;
  TC_PETSC(MatDenseGetArrayRead(a_, &f));
  TC_PETSC(MatDenseGetLDA(a_, &lda));
  {
    const auto xv = x.read();
    auto yv = y.view();
    const int n = static_cast<int>(n_), ld = static_cast<int>(std::max<PetscInt>(lda, 1));
    const int one = 1;
    const double alpha = 1.0, beta = 0.0;
    if (n > 0)
      dsymv_("U", &n, &alpha, f, &ld, xv.span().data(), &one, &beta, yv.span().data(), &one);
  }
  TC_PETSC(MatDenseRestoreArrayRead(a_, &f));
  TC_PETSC(PetscLogFlops(2.0 * static_cast<double>(n_) * static_cast<double>(n_)));
}

Vector SymmetricDenseOperator::make_vector() const {
  return Vector(n_);
}

namespace {
/// A start vector with no special structure, identical for every rank count: entry i of the
/// global numbering gets a fixed pseudo-random value, so 1 and N ranks estimate the same λ.
void fill_start_vector(Vector& v) {
  PetscInt begin = 0, end = 0;
  TC_PETSC(VecGetOwnershipRange(v.get(), &begin, &end));
  auto view = v.view();
  for (PetscInt i = begin; i < end; ++i) {
    const auto h = static_cast<std::uint64_t>(i + 1) * 0x9E3779B97F4A7C15ULL;
    view[i - begin] = 0.5 + static_cast<double>((h >> 11) % 1000003) / 1000003.0;
  }
}
}  // namespace

namespace {
/// The largest Ritz value of the Lanczos tridiagonal (alpha, beta) and its residual
/// ‖F y − θ y‖ = β_k |s_k| (y = Q s): an eigenvalue of F lies within it of θ.
std::pair<double, double> largest_ritz(const std::vector<double>& alpha,
                                       const std::vector<double>& beta) {
  const auto n = static_cast<Eigen::Index>(alpha.size());
  Eigen::VectorXd diag = Eigen::Map<const Eigen::VectorXd>(alpha.data(), n);
  Eigen::VectorXd sub =
      Eigen::Map<const Eigen::VectorXd>(beta.data(), n).head(std::max<Eigen::Index>(n - 1, 0));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  eig.computeFromTridiagonal(diag, sub, Eigen::ComputeEigenvectors);
  return {eig.eigenvalues()(n - 1), std::abs(beta.back() * eig.eigenvectors()(n - 1, n - 1))};
}
}  // namespace

EigenEstimate estimate_max_eigenvalue(const LinearOperator& f, int steps, double tolerance) {
  Vector q = f.make_vector(), q_prev = f.make_vector(), w = f.make_vector();
  fill_start_vector(q);
  q.scale(1.0 / q.norm());
  steps = std::max<PetscInt>(1, std::min<PetscInt>(steps, q.size()));

  std::vector<double> alpha, beta;  // the Lanczos tridiagonal T_k
  EigenEstimate est;
  double beta_prev = 0;
  for (int k = 0; k < steps; ++k) {
    f.apply(q, w);
    ++est.applications;
    const double a = w.dot(q);
    w.axpy(-a, q);
    if (k > 0) w.axpy(-beta_prev, q_prev);
    alpha.push_back(a);
    const double b = w.norm();
    beta.push_back(b);
    if (!(b > 1e-12 * std::abs(a))) break;  // an invariant subspace: T_k is exact
    if (tolerance > 0 && k > 0) {           // the bound is tight enough: stop early
      const auto [ritz, residual] = largest_ritz(alpha, beta);
      if (residual <= tolerance * ritz) break;
    }
    q_prev.copy_from(q);
    q.copy_from(w);
    q.scale(1.0 / b);
    beta_prev = b;
  }
  const auto [ritz, residual] = largest_ritz(alpha, beta);
  est.ritz = ritz;
  est.bound = ritz + residual;
  return est;
}

EigenEstimate largest_ritz_value(const std::vector<double>& diag, const std::vector<double>& off) {
  EigenEstimate est;
  if (diag.empty() || off.size() != diag.size()) return est;
  const auto [ritz, residual] = largest_ritz(diag, off);
  est.ritz = ritz;
  est.bound = ritz + residual;
  return est;
}

}  // namespace tc::qp
