#pragma once
// The eigenproblems of the linearised problem (linearisation.hpp) by SLEPc's EPS: the growth
// rates b of (A₀ + V A₁) x = b M x at a speed V, and the critical speed V_c of the pencil
// A₀ x = −V A₁ x (b = 0, a real crossing), both by shift-and-invert (STSINVERT, the shifted
// matrix factorised once by MUMPS through KSPPREONLY/PCLU) about a target. The singular M
// (no rate in the mechanics and the constraints) gives infinite eigenvalues, which
// shift-and-invert maps to 0 and the target ordering leaves out; SLEPc purifies the vectors
// (EPSSetPurify) and any left with |b − σ| beyond 1e8 (|σ| + 1) are dropped.
// SLEPc's options may be given with the prefix -stability_ (PETSC_OPTIONS="-stability_eps_ncv
// 40"). Not collective: everything on PETSC_COMM_SELF.
#include <optional>
#include <vector>

#include "tc/stability/linearisation.hpp"

namespace tc::stability {

/// SLEPc initialised inside an existing PETSc session (and finalised by the destructor).
class SlepcSession {
 public:
  SlepcSession();
  ~SlepcSession();
  SlepcSession(const SlepcSession&) = delete;
  SlepcSession& operator=(const SlepcSession&) = delete;
};

/// One eigenvalue b = re + i·im [1/s] (or a critical speed [m/s]) and its vector x, split
/// into its real and imaginary parts, scaled so that its θ entry of largest modulus is 1.
struct Eigenpair {
  double re = 0, im = 0;
  double residual = 0;  // ‖A x − b M x‖ / ((‖A‖ + |b| ‖M‖) ‖x‖): SLEPc's backward error
  std::vector<double> x_re, x_im;
};

struct EigenResult {
  std::vector<Eigenpair> pairs;  // by decreasing real part
  double target = 0;             // σ used
  int iterations = 0;            // SLEPc's restarts
  int converged = 0;             // eigenpairs SLEPc returned (before dropping infinite ones)
};

/// The default target at speed V: σ = κ (Λ V)², the largest growth rate a half-plane under
/// the same frictional heating can have (docs/theory.md), so that the eigenvalues nearest σ are
/// those of largest real part.
[[nodiscard]] double default_target(const Linearisation& lin, double speed);

/// The `count` eigenvalues nearest `target`, by decreasing real part.
[[nodiscard]] EigenResult growth_rates(const Linearisation& lin, double speed, int count,
                                       double target);

/// The smallest positive real V with a b = 0 mode (searched among `count` eigenvalues of the
/// pencil nearest 0); none when no positive real one converged.
[[nodiscard]] std::optional<Eigenpair> critical_speed(const Linearisation& lin, int count,
                                                      int* iterations = nullptr);

}  // namespace tc::stability
