#pragma once
// PETSc TAO's bound-constrained solvers (TAOBQPIP, TAOGPCG, TAOBLMVM) and plain CG (KSPCG) on
// min ½xᵀFx − xᵀd, l ≤ x ≤ u, with every application of F counted: F is wrapped in a
// MATSHELL whose MatMult counts, and TAO's objective/gradient callback applies F through that
// same shell (one gradient evaluation = one application). The same F is what the qp layer's
// Mprgp applies, so the counts compare like with like. Shared by tests/verification/
// qp_tao_test.cpp and bench/qp.
//
// No preconditioner anywhere (PCNONE): F is only applied in the dual problem, never stored,
// so a preconditioner built from its entries is not available to any of the solvers.
#include <petsctao.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <string>

#include "tc/core/numeric/petsc.hpp"
#include "tc/qp/operator.hpp"
#include "tc/qp/sets.hpp"

namespace tc::test {

/// A limit on the work of one solve: applications of F and wall time. Checked by the solvers'
/// convergence tests, so a solve stops at the first test after the limit is passed.
struct Budget {
  long max_applications = std::numeric_limits<long>::max();
  double max_seconds = std::numeric_limits<double>::infinity();
};

/// F as a MATSHELL that counts its applications; the wrapped operator outlives it.
class CountingShell {
 public:
  explicit CountingShell(const qp::LinearOperator& f) : f_(f) {
    const core::Vector layout = f.make_vector();
    TC_PETSC(MatCreateShell(layout.comm(), layout.local_size(), layout.local_size(), layout.size(),
                            layout.size(), this, mat_.out()));
    TC_PETSC(MatShellSetOperation(mat_.get(), MATOP_MULT, reinterpret_cast<void (*)()>(&mult)));
    // F is symmetric: Mᵀx = Mx (KSPs and TAO may ask).
    TC_PETSC(MatShellSetOperation(mat_.get(), MATOP_MULT_TRANSPOSE,
                                  reinterpret_cast<void (*)()>(&mult)));
    // BQPIP adds its barrier diagonal with MatDiagonalSet(ADD_VALUES), assembles, solves and
    // subtracts it again. MATSHELL's own diagonal shift is reset by MatAssemblyEnd, so the
    // shell keeps the added diagonal D itself: F + D, D = 0 again exactly after a + (−a).
    TC_PETSC(MatShellSetManageScalingShifts(mat_.get()));
    TC_PETSC(MatShellSetOperation(mat_.get(), MATOP_DIAGONAL_SET,
                                  reinterpret_cast<void (*)()>(&diagonal_set)));
    TC_PETSC(MatSetOption(mat_.get(), MAT_SYMMETRIC, PETSC_TRUE));
    TC_PETSC(MatSetOption(mat_.get(), MAT_SPD, PETSC_TRUE));
  }
  CountingShell(const CountingShell&) = delete;
  CountingShell& operator=(const CountingShell&) = delete;

  [[nodiscard]] ::Mat get() const { return mat_.get(); }
  [[nodiscard]] long count() const { return count_; }
  /// Zero count, and no added diagonal (a solver stopped between its add and its removal).
  void reset() {
    count_ = 0;
    diagonal_.reset();
    product_.reset();
  }

 private:
  // A PETSc callback: no exception may unwind through it, so a failure of the wrapped
  // operator (which throws tc::Error) becomes a PETSc error code.
  static PetscErrorCode mult(::Mat a, ::Vec x, ::Vec y) {
    CountingShell* self = nullptr;
    PetscCall(MatShellGetContext(a, &self));
    PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(x)));
    PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(y)));
    try {
      const core::Vector in = core::Vector::adopt(x);  // adopt the extra references only
      core::Vector out = core::Vector::adopt(y);
      self->f_.apply(in, out);
    } catch (const std::exception& e) {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
    }
    if (self->diagonal_) {
      PetscCall(VecPointwiseMult(self->product_.get(), self->diagonal_.get(), x));  // D∘x
      PetscCall(VecAXPY(y, 1.0, self->product_.get()));
    }
    ++self->count_;
    return 0;
  }

  static PetscErrorCode diagonal_set(::Mat a, ::Vec v, InsertMode mode) {
    CountingShell* self = nullptr;
    PetscCall(MatShellGetContext(a, &self));
    PetscCheck(mode == ADD_VALUES, PETSC_COMM_SELF, PETSC_ERR_SUP,
               "CountingShell: only MatDiagonalSet(ADD_VALUES)");
    if (!self->diagonal_) {
      PetscCall(VecDuplicate(v, self->diagonal_.out()));
      PetscCall(VecDuplicate(v, self->product_.out()));
      PetscCall(VecSet(self->diagonal_.get(), 0.0));
    }
    PetscCall(VecAXPY(self->diagonal_.get(), 1.0, v));
    return 0;
  }

  const qp::LinearOperator& f_;
  core::Handle<::Mat, MatDestroy> mat_;
  core::Handle<::Vec, VecDestroy> diagonal_, product_;  // D (only once someone adds one)
  long count_ = 0;
};

/// The bound vectors l, u of a FeasibleSet made of Intervals only, read off the set itself as
/// P(−∞) and P(+∞); an unbounded side becomes PETSc's ±PETSC_INFINITY, as TAO expects.
inline void interval_bounds(const qp::FeasibleSet& set, core::Vector& lower, core::Vector& upper) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  lower.fill(-inf);
  upper.fill(inf);
  set.project(lower);
  set.project(upper);
  for (core::Vector* v : {&lower, &upper}) {
    auto w = v->view();
    for (double& e : w.span())
      if (!std::isfinite(e)) e = e > 0 ? PETSC_INFINITY : PETSC_NINFINITY;
  }
}

/// Replaces infinite bounds by ±radius. BQPIP needs it: it caps infinite bounds at ±1e20, and
/// the slacks of that size put its duality gap, and with it its stopping measure, out of
/// reach of double precision. With radius ≥ ‖x*‖ the solution is unchanged; for example, when
/// 0 ∈ Ω and λ_min(F) ≥ μ, f(x*) ≤ f(0) = 0 gives ½μ‖x*‖² ≤ x*ᵀd, so ‖x*‖ ≤ 2‖d‖/μ.
inline void cap_infinite_bounds(core::Vector& lower, core::Vector& upper, double radius) {
  for (auto* v : {&lower, &upper}) {
    auto w = v->view();
    for (double& e : w.span()) e = std::clamp(e, -radius, radius);
  }
}

/// BQPIP stops on √(gap + ‖dual infeasibility‖) ≤ gatol, not on a projected gradient: the
/// square root lifts the round-off of the gap (ε_mach·|f|, |f| ~ ‖d‖²/λ_max) to a floor of
/// ~1e-8‖d‖/√λ_max, below which it never converges. It gets the projected-gradient
/// tolerance, but not below 1e-7‖d‖, an order above that floor.
[[nodiscard]] inline double bqpip_gatol(double projected_gradient_tolerance, double d_norm) {
  return std::max(projected_gradient_tolerance, 1e-7 * d_norm);
}

struct SolverRun {
  std::string name;
  int reason = 0;            // TaoConvergedReason or KSPConvergedReason (> 0: converged)
  bool converged = false;    // reason > 0 (and not stopped by the budget)
  bool budget_hit = false;   // stopped by Budget
  PetscInt iterations = 0;   // outer iterations
  long applications = 0;     // applications of F (MatMult of the shell; −1: not counted)
  double seconds = 0;        // wall time of the solve
  double reported_norm = 0;  // the solver's own residual measure at exit
};

namespace detail {

struct TaoContext {
  ::Mat f;
  const CountingShell* shell;  // null: nothing counted
  const core::Vector* d;
  Budget budget;
  std::chrono::steady_clock::time_point start;
  bool budget_hit = false;

  [[nodiscard]] bool exceeded() {
    const double t =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const long count = shell ? shell->count() : 0;
    budget_hit = budget_hit || count >= budget.max_applications || t > budget.max_seconds;
    return budget_hit;
  }
};

/// f = ½xᵀFx − xᵀd and g = Fx − d with one application of F: f = ½xᵀ(g − d).
inline PetscErrorCode objective_and_gradient(::Tao, ::Vec x, PetscReal* f, ::Vec g, void* ctx) {
  auto* c = static_cast<TaoContext*>(ctx);
  PetscScalar xg = 0, xd = 0;
  PetscCall(MatMult(c->f, x, g));
  PetscCall(VecAXPY(g, -1.0, c->d->get()));
  PetscCall(VecDot(x, g, &xg));
  PetscCall(VecDot(x, c->d->get(), &xd));
  *f = 0.5 * (xg - xd);
  return 0;
}

/// The Hessian is the constant F itself: nothing to compute.
inline PetscErrorCode hessian(::Tao, ::Vec, ::Mat, ::Mat, void*) {
  return 0;
}

inline PetscErrorCode tao_test(::Tao tao, void* ctx) {
  PetscCall(TaoDefaultConvergenceTest(tao, nullptr));
  TaoConvergedReason reason;
  PetscCall(TaoGetConvergedReason(tao, &reason));
  if (reason == TAO_CONTINUE_ITERATING && static_cast<TaoContext*>(ctx)->exceeded())
    PetscCall(TaoSetConvergedReason(tao, TAO_DIVERGED_USER));
  return 0;
}

/// The inner KSP of BQPIP/GPCG: default test, plus the budget (an inner solve of BQPIP may
/// otherwise run up to n iterations).
struct KspContext {
  TaoContext* tao;
  void* default_ctx = nullptr;
};
inline PetscErrorCode ksp_test(::KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason* r,
                               void* ctx) {
  auto* c = static_cast<KspContext*>(ctx);
  PetscCall(KSPConvergedDefault(ksp, it, rnorm, r, c->default_ctx));
  if (*r == KSP_CONVERGED_ITERATING && c->tao->exceeded()) *r = KSP_DIVERGED_ITS;
  return 0;
}

}  // namespace detail

/// Runs a TAO bound-constrained solver (TAOBQPIP, TAOGPCG, TAOBLMVM) from x (feasible) to
/// ‖projected gradient‖ ≤ gatol (BQPIP: its own measure √(gap + dual infeasibility), see
/// bqpip_gatol). The objective, gradient and Hessian all come from the one matrix f: an
/// assembled F (TAO's defaults: ILU in the inner KSPs, GPCG's reduced Hessian by
/// MatCreateSubMatrix), or a CountingShell (matrix-free: no preconditioner, GPCG's reduced
/// Hessian masked; the applications are counted). x returns the solution. Collective.
inline SolverRun run_tao(const char* type, ::Mat f, CountingShell* shell, const core::Vector& d,
                         const core::Vector& lower, const core::Vector& upper, core::Vector& x,
                         double gatol, PetscInt max_iterations, Budget budget = {}) {
  SolverRun run;
  run.name = type;
  core::Handle<::Tao, TaoDestroy> tao;
  TC_PETSC(TaoCreate(x.comm(), tao.out()));
  TC_PETSC(TaoSetType(tao.get(), type));
  // GPCG's reduced Hessian: TAO's default (MatCreateSubMatrix) needs an assembled matrix; the
  // "matrixfree" subset applies F through the shell with the active rows and columns masked.
  const std::string prefix = std::string("tc_") + type + "_";
  TC_PETSC(TaoSetOptionsPrefix(tao.get(), prefix.c_str()));
  if (shell)
    TC_PETSC(
        PetscOptionsSetValue(nullptr, ("-" + prefix + "tao_subset_type").c_str(), "matrixfree"));
  const auto start = std::chrono::steady_clock::now();
  detail::TaoContext ctx{f, shell, &d, budget, start, false};
  detail::KspContext kctx{&ctx};
  TC_PETSC(KSPConvergedDefaultCreate(&kctx.default_ctx));
  try {
    TC_PETSC(TaoSetSolution(tao.get(), x.get()));
    TC_PETSC(TaoSetVariableBounds(tao.get(), lower.get(), upper.get()));
    TC_PETSC(TaoSetObjectiveAndGradient(tao.get(), nullptr, &detail::objective_and_gradient, &ctx));
    TC_PETSC(TaoSetHessian(tao.get(), f, f, &detail::hessian, nullptr));
    TC_PETSC(TaoSetTolerances(tao.get(), gatol, 0.0, 0.0));
    TC_PETSC(TaoSetMaximumIterations(tao.get(), max_iterations));
    TC_PETSC(TaoSetMaximumFunctionEvaluations(tao.get(), PETSC_MAX_INT));
    TC_PETSC(TaoSetConvergenceTest(tao.get(), &detail::tao_test, &ctx));
    ::KSP ksp = nullptr;
    TC_PETSC(TaoGetKSP(tao.get(), &ksp));
    if (ksp) {
      ::PC pc = nullptr;
      TC_PETSC(KSPGetPC(ksp, &pc));
      if (shell) TC_PETSC(PCSetType(pc, PCNONE));
      TC_PETSC(KSPSetConvergenceTest(ksp, &detail::ksp_test, &kctx, nullptr));
    }
    TC_PETSC(TaoSetFromOptions(tao.get()));  // after the defaults above: options override
    if (shell) shell->reset();
    ctx.start = std::chrono::steady_clock::now();
    TC_PETSC(TaoSolve(tao.get()));
    run.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - ctx.start).count();
    run.applications = shell ? shell->count() : -1;
    TaoConvergedReason reason;
    PetscReal f = 0, gnorm = 0, cnorm = 0, xdiff = 0;
    TC_PETSC(TaoGetSolutionStatus(tao.get(), &run.iterations, &f, &gnorm, &cnorm, &xdiff, &reason));
    run.reason = static_cast<int>(reason);
    run.reported_norm = gnorm;
    run.budget_hit = ctx.budget_hit && reason == TAO_DIVERGED_USER;
    run.converged = reason > 0;
  } catch (...) {
    (void)KSPConvergedDefaultDestroy(kctx.default_ctx);
    throw;
  }
  // The KSP (owned by the Tao) still refers to kctx: destroy the Tao first.
  tao.reset();
  TC_PETSC(KSPConvergedDefaultDestroy(kctx.default_ctx));
  return run;
}

/// Plain CG on F x = d (no constraints) from x = 0, ‖Fx − d‖ ≤ rtol ‖d‖. Collective.
inline SolverRun run_cg(CountingShell& shell, const core::Vector& d, core::Vector& x, double rtol,
                        PetscInt max_iterations) {
  SolverRun run;
  run.name = "CG";
  core::Handle<::KSP, KSPDestroy> ksp;
  TC_PETSC(KSPCreate(x.comm(), ksp.out()));
  TC_PETSC(KSPSetType(ksp.get(), KSPCG));
  TC_PETSC(KSPSetOperators(ksp.get(), shell.get(), shell.get()));
  ::PC pc = nullptr;
  TC_PETSC(KSPGetPC(ksp.get(), &pc));
  TC_PETSC(PCSetType(pc, PCNONE));
  TC_PETSC(KSPSetNormType(ksp.get(), KSP_NORM_UNPRECONDITIONED));
  TC_PETSC(KSPSetTolerances(ksp.get(), rtol, 0.0, PETSC_DEFAULT, max_iterations));
  x.zero();
  shell.reset();
  const auto start = std::chrono::steady_clock::now();
  TC_PETSC(KSPSolve(ksp.get(), d.get(), x.get()));
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.applications = shell.count();
  KSPConvergedReason reason;
  TC_PETSC(KSPGetConvergedReason(ksp.get(), &reason));
  TC_PETSC(KSPGetIterationNumber(ksp.get(), &run.iterations));
  TC_PETSC(KSPGetResidualNorm(ksp.get(), &run.reported_norm));
  run.reason = static_cast<int>(reason);
  run.converged = reason > 0;
  return run;
}

}  // namespace tc::test
