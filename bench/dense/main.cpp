// The dense kernels of the contact path, each against the one it replaced, in the same process
// (docs/choices.md, "Dense kernels by the BLAS"): the explicit dual operator's product by dsymv
// on its upper triangle (qp::SymmetricDenseOperator) against the general product PETSc's
// MatMult makes (dgemv), and the interface heat solver's LU by LAPACK dgetrf against Eigen's
// PartialPivLU. Sizes are those of the examples' F (492 rows, example 07; 2 205, its refined
// case; 3 267, ch. 7 refined ×5.3; 6 615) and of I + S L_JJ (1 400, 2 020).
//   build/bin/bench_dense [--reps-scale X]
#include <Eigen/Dense>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "tc/core/numeric/blas.hpp"
#include "tc/core/numeric/petsc.hpp"

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void products(int m, double scale) {
  std::vector<double> a(static_cast<size_t>(m) * m), x(m), y(m);
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i <= j; ++i) a[size_t(j) * m + i] = a[size_t(i) * m + j] = u(gen);
  for (auto& v : x) v = u(gen);
  const int reps = std::max(3, static_cast<int>(scale * 2e9 / (double(m) * m)));
  const int one = 1;
  const double alpha = 1, beta = 0;
  auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < reps; ++r)
    dgemv_("N", &m, &m, &alpha, a.data(), &m, x.data(), &one, &beta, y.data(), &one);
  const double gemv = seconds_since(t0) / reps;
  t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < reps; ++r)
    dsymv_("U", &m, &alpha, a.data(), &m, x.data(), &one, &beta, y.data(), &one);
  const double symv = seconds_since(t0) / reps;
  std::printf("F x, %5d rows (%6.1f MB): dgemv %8.3f ms, dsymv %8.3f ms, ratio %.2f\n", m,
              8e-6 * m * m, 1e3 * gemv, 1e3 * symv, gemv / symv);
}

void factorisations(int n, double scale) {
  std::mt19937 gen(2);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd a(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) a(i, j) = u(gen) + (i == j ? n : 0.0);
  const int reps = std::max(2, static_cast<int>(scale * 3));
  double eigen = 0, lapack = 0;
  for (int r = 0; r < reps; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
    eigen += seconds_since(t0);
    Eigen::MatrixXd b = a;
    std::vector<int> piv(n);
    int info = 0;
    t0 = std::chrono::steady_clock::now();
    dgetrf_(&n, &n, b.data(), &n, piv.data(), &info);
    lapack += seconds_since(t0);
    if (info != 0 || lu.matrixLU().size() != b.size()) std::abort();
  }
  std::printf("LU, %5d rows: Eigen PartialPivLU %7.3f s, dgetrf %7.3f s, ratio %.2f\n", n,
              eigen / reps, lapack / reps, eigen / lapack);
}

}  // namespace

int main(int argc, char** argv) {
  double scale = 1;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--reps-scale") == 0) scale = std::atof(argv[i + 1]);
  int pargc = 1;
  tc::core::PetscSession session(&pargc, &argv);  // one BLAS thread, as the solver runs
  for (const int m : {492, 2205, 3267, 6615}) products(m, scale);
  for (const int n : {1400, 2020}) factorisations(n, scale);
  return 0;
}
