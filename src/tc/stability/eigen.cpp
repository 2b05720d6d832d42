#include "tc/stability/eigen.hpp"

#include <slepceps.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "tc/core/error.hpp"

namespace tc::stability {

SlepcSession::SlepcSession() {
  TC_PETSC(SlepcInitializeNoArguments());
}

SlepcSession::~SlepcSession() {
  (void)SlepcFinalize();
}

namespace {

struct EpsHandle {
  EPS eps = nullptr;
  ~EpsHandle() {
    if (eps) (void)EPSDestroy(&eps);
  }
};

struct VecPair {
  Vec re = nullptr, im = nullptr;
  ~VecPair() {
    if (re) (void)VecDestroy(&re);
    if (im) (void)VecDestroy(&im);
  }
};

/// The eigenpairs of A x = λ B x nearest σ by shift-and-invert, normalised on the θ entries
/// [theta_begin, theta_end) (the whole vector when that range is empty).
EigenResult solve_pencil(Mat a, Mat b, double sigma, int count, PetscInt theta_begin,
                         PetscInt theta_end, const std::vector<double>& scale) {
  EpsHandle h;
  TC_PETSC(EPSCreate(PETSC_COMM_SELF, &h.eps));
  TC_PETSC(EPSSetOperators(h.eps, a, b));
  TC_PETSC(EPSSetProblemType(h.eps, EPS_GNHEP));
  TC_PETSC(EPSSetTarget(h.eps, sigma));
  TC_PETSC(EPSSetWhichEigenpairs(h.eps, EPS_TARGET_MAGNITUDE));
  TC_PETSC(EPSSetDimensions(h.eps, count, PETSC_DEFAULT, PETSC_DEFAULT));
  TC_PETSC(EPSSetTolerances(h.eps, 1e-10, 2000));
  ST st = nullptr;
  TC_PETSC(EPSGetST(h.eps, &st));
  TC_PETSC(STSetType(st, STSINVERT));
  TC_PETSC(STSetMatStructure(st, DIFFERENT_NONZERO_PATTERN));
  KSP ksp = nullptr;
  TC_PETSC(STGetKSP(st, &ksp));
  TC_PETSC(KSPSetType(ksp, KSPPREONLY));
  PC pc = nullptr;
  TC_PETSC(KSPGetPC(ksp, &pc));
  TC_PETSC(PCSetType(pc, PCLU));
  // MUMPS pivots: the constraint rows have a zero diagonal (a saddle point).
  TC_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  TC_PETSC(EPSSetOptionsPrefix(h.eps, "stability_"));
  TC_PETSC(EPSSetFromOptions(h.eps));
  TC_PETSC(EPSSolve(h.eps));
  EigenResult out;
  out.target = sigma;
  PetscInt nconv = 0, its = 0;
  TC_PETSC(EPSGetConverged(h.eps, &nconv));
  TC_PETSC(EPSGetIterationNumber(h.eps, &its));
  out.converged = static_cast<int>(nconv);
  out.iterations = static_cast<int>(its);
  VecPair x;
  TC_PETSC(MatCreateVecs(a, &x.re, nullptr));
  TC_PETSC(VecDuplicate(x.re, &x.im));
  for (PetscInt i = 0; i < nconv; ++i) {
    PetscScalar kr = 0, ki = 0;
    TC_PETSC(EPSGetEigenpair(h.eps, i, &kr, &ki, x.re, x.im));
    if (!std::isfinite(kr) || !std::isfinite(ki) ||
        std::abs(std::complex<double>(kr - sigma, ki)) > 1e8 * (std::abs(sigma) + 1))
      continue;
    Eigenpair e;
    e.re = kr;
    e.im = ki;
    PetscReal err = 0;
    TC_PETSC(EPSComputeError(h.eps, i, EPS_ERROR_BACKWARD, &err));
    e.residual = err;
    PetscInt n = 0;
    TC_PETSC(VecGetSize(x.re, &n));
    const PetscScalar *xr = nullptr, *xi = nullptr;
    TC_PETSC(VecGetArrayRead(x.re, &xr));
    TC_PETSC(VecGetArrayRead(x.im, &xi));
    std::vector<std::complex<double>> z(static_cast<size_t>(n));
    for (PetscInt j = 0; j < n; ++j)
      z[j] = std::complex<double>(xr[j], ki != 0 ? xi[j] : 0.0) * scale[static_cast<size_t>(j)];
    TC_PETSC(VecRestoreArrayRead(x.re, &xr));
    TC_PETSC(VecRestoreArrayRead(x.im, &xi));
    // Scaled so that the θ entry of largest modulus is 1 (its phase 0).
    const PetscInt lo = theta_end > theta_begin ? theta_begin : 0;
    const PetscInt hi = theta_end > theta_begin ? theta_end : n;
    std::complex<double> peak = 0;
    for (PetscInt j = lo; j < hi; ++j)
      if (std::abs(z[j]) > std::abs(peak)) peak = z[j];
    if (peak == 0.0) peak = 1.0;
    for (const auto& v : z) {
      e.x_re.push_back((v / peak).real());
      e.x_im.push_back((v / peak).imag());
    }
    out.pairs.push_back(std::move(e));
  }
  std::stable_sort(out.pairs.begin(), out.pairs.end(),
                   [](const Eigenpair& p, const Eigenpair& q) { return p.re > q.re; });
  return out;
}

struct MatHandle {
  Mat m = nullptr;
  ~MatHandle() {
    if (m) (void)MatDestroy(&m);
  }
};

}  // namespace

double default_target(const Linearisation& lin, double speed) {
  const double lambda = lin.heating_wavenumber * speed;
  return lin.diffusivity * lambda * lambda;
}

EigenResult growth_rates(const Linearisation& lin, double speed, int count, double target) {
  MatHandle a;
  TC_PETSC(MatDuplicate(lin.a0.get(), MAT_COPY_VALUES, &a.m));
  TC_PETSC(MatAXPY(a.m, speed, lin.a1.get(), DIFFERENT_NONZERO_PATTERN));
  return solve_pencil(a.m, lin.mass.get(), target, count, lin.x.theta_offset(),
                      lin.x.lambda_offset(), lin.scale);
}

std::optional<Eigenpair> critical_speed(const Linearisation& lin, int count, int* iterations) {
  MatHandle b;
  TC_PETSC(MatDuplicate(lin.a1.get(), MAT_COPY_VALUES, &b.m));
  TC_PETSC(MatScale(b.m, -1.0));
  auto r = solve_pencil(lin.a0.get(), b.m, 0.0, count, lin.x.theta_offset(), lin.x.lambda_offset(),
                        lin.scale);
  if (iterations) *iterations = r.iterations;
  std::optional<Eigenpair> best;
  for (auto& e : r.pairs)
    if (e.re > 0 && std::abs(e.im) <= 1e-8 * e.re && (!best || e.re < best->re)) best = e;
  return best;
}

}  // namespace tc::stability
