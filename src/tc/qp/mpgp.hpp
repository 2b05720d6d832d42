#pragma once
// MPRGP (Dostál & Schöberl 2005) and MPGP (Dostál & Kozubek 2012): minimise
//   f(λ) = ½ λᵀFλ − λᵀd   over a product of simple convex sets Ω   (the dual QP (6.9)).
// Conjugate gradients in the face of the current active set, proportioning steps that release
// components when the chopped gradient dominates, and expansion steps — a maximal feasible
// step followed by a projected gradient step of fixed length ᾱ ∈ (0, 2/‖F‖] — that add
// them. The rate of convergence is bounded in terms of the spectrum of F only, which is what
// makes the FETI solver numerically scalable.
#include <string>
#include <vector>

#include "tc/qp/operator.hpp"
#include "tc/qp/sets.hpp"

namespace tc::qp {

enum class Expansion {
  free_gradient,  // x ← P(x − ᾱ φ(x)): the original MPRGP step
  full_gradient,  // x ← P(x − ᾱ g(x)): also moves active components (Kružík et al. 2020)
  /// x ← P(x − α_cg p): the CG step that would have left the set, projected, then CG restarts
  /// (Kružík et al. 2020, "projCG"); kept only if f falls, else the free-gradient expansion.
  projected_cg,
};

/// The length of the projected gradient move of an expansion step (PERMON's expansion length
/// types). Anything longer than ᾱ is kept only if f falls; otherwise the fixed ᾱ step follows.
enum class ExpansionStep {
  fixed,   // ᾱ = alpha_factor/λ_max: the step of the convergence theory
  cauchy,  // the minimiser along the direction, eᵀg/eᵀFe: one more application of F
  /// Barzilai–Borwein from the step just taken, sᵀs/sᵀFs (s the last CG, feasible or
  /// proportioning direction, whose F s is at hand): no application of F.
  barzilai_borwein,
};

/// When is x proportional (CG goes on in the face) rather than released by proportioning?
enum class ProportioningTest {
  reduced,  // ‖β‖² ≤ Γ² g̃ᵀφ with the reduced free gradient g̃ (Dostál 2009, Alg. 5.8)
  free,  // ‖β‖² ≤ Γ² φᵀφ (PERMON): g̃ᵀφ ≤ φᵀφ, so proportioning happens less often
};

/// How a node that lies on its friction circle takes part in the face (MPGP only).
enum class CircleFace {
  /// Dostál & Kozubek (2012): the node is active, the tangential part of g is chopped (part of
  /// β), and only proportioning steps and projected moves slide it along the circle.
  chopped,
  /// The circle belongs to the face: the tangential part of g is free (part of φ), only the
  /// inward normal part is chopped. CG moves such nodes along their tangent and puts them back
  /// on the circle (the projection, a retraction in the sense of Absil et al. 2008, §4.1);
  /// the gradient is then recomputed (one more application) and the step kept only if f
  /// fell, else replaced by the projected gradient step P(x − ᾱg). A heuristic outside
  /// MPGP's convergence theory, safeguarded like the long expansion moves.
  slide,
};

/// When λ_max(F), which fixes ᾱ, is estimated (if QpOptions::max_eigenvalue is not given).
enum class EigenvalueEstimate {
  /// Lanczos on F before the first step (lanczos_steps, lanczos_tolerance): always paid.
  upfront,
  /// Only when ᾱ is first needed (the first expansion step; a solve without one never pays
  /// for it), and then from the conjugate gradient steps already taken: their coefficients
  /// are the Lanczos tridiagonal of F restricted to the face, continued by Lanczos steps in
  /// that face only while its residual bound exceeds lanczos_tolerance (docs/theory.md).
  /// λ_max of the face bounds the curvature of that expansion move; a later move in a larger
  /// face that raises f triggers one full Lanczos estimate on F. Until ᾱ is known the
  /// proportioning test is ProportioningTest::free. With a preconditioner in face or
  /// CircleFace::slide the CG coefficients belong to another operator: then the full
  /// Lanczos estimate, at the first need.
  deferred,
};

struct QpOptions {
  double rtol = 1e-8;  // stop when ‖g^P‖ ≤ max(rtol ‖d‖, atol)
  /// The rows' groups for the stopping test (empty: one group). Group 0 is tested against
  /// the whole ‖d‖ as usual; each other group G is weighted by ‖d‖/‖d_G‖ (≥ 1), so that it is
  /// solved to rtol of its own size even where another group's d dwarfs it: the contact QP's
  /// normal rows (group 1) in a slide, where ‖d‖ is the tangential rows' slip V τ D (mm) and
  /// d_n the indentation (µm). ‖d_G‖ is floored at 1e-6 ‖d‖. Weighted, the test is
  /// ‖w ∘ g^P‖ ≤ max(rtol ‖d‖, atol); with group 0 dominant, Σ_{G≥1} (‖g^P_G‖/‖d_G‖)² +
  /// ‖g^P_0‖²/‖d‖² ≤ rtol².
  std::vector<int> row_groups;
  double atol = 1e-30;        // absolute floor (d = 0 has the solution of the set alone)
  int max_iterations = 2000;  // iterations (CG, expansion and proportioning steps)
  double gamma = 1.0;         // proportioning parameter Γ
  double alpha_factor = 1.9;  // ᾱ = alpha_factor / λ_max(F); theory allows (0, 2]
  double max_eigenvalue = 0;  // λ_max(F) if known (e.g. reused across steps); 0 = estimate
  int lanczos_steps = 20;     // for the estimate (at most)
  /// The estimate stops once its bound is within this fraction of the Ritz value: with 0.05,
  /// ᾱλ_max ≥ 1.9/1.05 ≈ 1.81, still near the edge of (0, 2] (docs/choices.md). 0 = all steps.
  double lanczos_tolerance = 0.05;
  Expansion expansion = Expansion::free_gradient;
  /// Optional SPD preconditioner applied to the free gradient in the face (masked); null = none.
  const LinearOperator* preconditioner = nullptr;
  // Added last, so that existing aggregate initialisations keep their meaning. The defaults
  // were measured against the alternatives: docs/choices.md, bench/RESULTS.md (bench/qp).
  ExpansionStep expansion_step = ExpansionStep::fixed;
  /// The same choice for the projected gradient move that replaces a proportioning step when
  /// a disc's tangent leaves its circle at once (MPGP only).
  ExpansionStep arc_step = ExpansionStep::fixed;
  ProportioningTest proportioning_test = ProportioningTest::reduced;
  /// Optional change of variables x = S x̂, S = diag(s), s > 0 (e.g.
  /// FeasibleSet::jacobi_scaling): the algorithm runs on SFS, Sd and the scaled set, so that
  /// its fixed-step expansion, proportioning and arc moves — not only CG in the face, as
  /// with `preconditioner` — see the better conditioned problem (Dostál 2009, §5.7 on
  /// preconditioning by a change of variables). The two components of a disc need one factor
  /// (the disc stays a disc). ‖g^P‖ is still measured in the original variables, x and the
  /// result are in them; `max_eigenvalue` (given or returned) is λ_max(SFS). null = none.
  const Vector* scaling = nullptr;
  CircleFace circle_face = CircleFace::chopped;
  /// `upfront` by default: with `deferred` the physics path took different (equally valid)
  /// steps that two exact-comparison tests of the friction loop and FETI noticed
  /// (docs/choices.md); bench/qp uses `deferred`.
  EigenvalueEstimate eigenvalue_estimate = EigenvalueEstimate::upfront;
};

enum class QpStatus { converged, max_iterations, breakdown };
[[nodiscard]] const char* name(QpStatus s);

struct [[nodiscard]] QpResult {
  QpStatus status = QpStatus::breakdown;
  int iterations = 0;
  int operator_applications = 0;  // including the eigenvalue estimate
  double projected_gradient = 0;  // final ‖g^P‖
  double tolerance = 0;           // the ‖g^P‖ required
  double max_eigenvalue = 0;      // the λ_max used (to reuse); 0 if ᾱ was never needed
  int cg_steps = 0, expansion_steps = 0, proportioning_steps = 0;
  int cauchy_steps = 0;  // proportioning steps taken as projected Cauchy steps along an arc
  /// ᾱ halved after an expansion that raised f although λ_max came from a full estimate.
  int step_halvings = 0;
  std::string message;      // why it stopped, with the numbers
  int long_expansions = 0;  // expansion moves longer than ᾱ (ExpansionStep, projected CG) kept
  int fallbacks = 0;        // ... and rejected because f rose (the ᾱ move taken instead)
  int slides = 0;           // CG steps that moved nodes along their circles (CircleFace::slide)
  int estimate_applications = 0;  // the share of operator_applications spent on λ_max
  /// max_eigenvalue is λ_max of a face (EigenvalueEstimate::deferred, from CG), ≤ λ_max(F).
  bool face_eigenvalue = false;
  /// Full Lanczos estimates made because an expansion raised f with a λ_max given or of a
  /// face (then ᾱ is not halved but recomputed).
  int reestimates = 0;
  [[nodiscard]] bool converged() const { return status == QpStatus::converged; }
};

/// The proportioning solver on any FeasibleSet: with intervals only it is MPRGP, with discs
/// MPGP. x holds the initial guess (projected onto Ω first) and returns the solution.
class Mpgp {
 public:
  Mpgp(const LinearOperator& f, const FeasibleSet& set, QpOptions options = {});
  QpResult solve(const Vector& d, Vector& x) const;

 private:
  /// The algorithm itself, on (f, set, d) as given; `unscale` (may be null) maps the
  /// projected gradient back for the stopping test (QpOptions::scaling).
  static QpResult run(const LinearOperator& f, const FeasibleSet& set, const QpOptions& options,
                      const Vector& d, Vector& x, double tolerance, const Vector* unscale);

  const LinearOperator& f_;
  const FeasibleSet& set_;
  QpOptions options_;
};

/// MPRGP: the same algorithm on bound and interval constraints (no discs).
class Mprgp {
 public:
  Mprgp(const LinearOperator& f, const FeasibleSet& set, QpOptions options = {});
  QpResult solve(const Vector& d, Vector& x) const { return impl_.solve(d, x); }

 private:
  Mpgp impl_;
};

/// ½ xᵀFx − xᵀd from the gradient g = Fx − d, without another application of F.
[[nodiscard]] double objective_from_gradient(const Vector& x, const Vector& g, const Vector& d);

}  // namespace tc::qp
