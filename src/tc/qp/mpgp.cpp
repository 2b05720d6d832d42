#include "tc/qp/mpgp.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "tc/core/verify.hpp"
#include "tc/qp/stopping.hpp"

namespace tc::qp {

const char* name(QpStatus s) {
  switch (s) {
    case QpStatus::converged:
      return "converged";
    case QpStatus::max_iterations:
      return "max_iterations";
    case QpStatus::breakdown:
      return "breakdown";
  }
  return "?";
}

double objective_from_gradient(const Vector& x, const Vector& g, const Vector& d) {
  // g = Fx − d ⇒ xᵀFx = xᵀ(g + d) ⇒ f = ½ xᵀ(g + d) − xᵀd = ½ xᵀ(g − d).
  return 0.5 * (x.dot(g) - x.dot(d));
}

Mpgp::Mpgp(const LinearOperator& f, const FeasibleSet& set, QpOptions options)
    : f_(f), set_(set), options_(options) {}

Mprgp::Mprgp(const LinearOperator& f, const FeasibleSet& set, QpOptions options)
    : impl_(f, set, options) {
  TC_VERIFY(!set.has_discs(), "MPRGP projects on boxes; friction discs need Mpgp");
}

namespace {

/// The work vectors and counters of one solve; the steps below are the three moves of the
/// algorithm (Dostál 2009, Alg. 5.8; Dostál & Kozubek 2012, Alg. 3.1).
struct State {
  const LinearOperator& f;
  const FeasibleSet& set;
  const QpOptions& opt;
  const Vector& d;
  Vector& x;
  Vector g, phi, beta, gp, p, fp, z, work, x_save, g_save, e, hp;
  double alpha_bar = 0;
  QpResult r;

  // ---- λ_max and ᾱ (QpOptions::eigenvalue_estimate)
  bool alpha_known = false;
  /// Whether λ_max came from a full Lanczos estimate on F in this solve (else: given, or of
  /// one face): an expansion that raises f then halves ᾱ rather than estimating again.
  bool full_estimate = false;
  /// The Lanczos tridiagonal of F in the face of the current CG run, from its coefficients
  /// (Saad 2003, §6.7.3): with r_j = φ_j, α_j = φ_jᵀφ_j/p_jᵀFp_j and
  /// β_j = φ_{j+1}ᵀφ_{j+1}/φ_jᵀφ_j, T_jj = 1/α_j + β_{j−1}/α_{j−1} and
  /// T_{j,j+1} = √β_j/α_j. Kept only while ᾱ is unknown and the run is plain CG on F.
  bool track_lanczos = false;
  std::vector<double> lz_diag, lz_off;
  double lz_alpha = 0, lz_beta = 0, phi_norm2 = 0;  // α_{j−1}, β_{j−1}, φ_jᵀφ_j

  void set_lambda(double lambda) {
    r.max_eigenvalue = lambda;
    alpha_bar = opt.alpha_factor / lambda;
    alpha_known = true;
  }
  /// Lanczos on the whole of F (operator.hpp), counted; λ_max never decreases.
  void estimate_full() {
    const auto est = estimate_max_eigenvalue(f, opt.lanczos_steps, opt.lanczos_tolerance);
    r.operator_applications += est.applications;
    r.estimate_applications += est.applications;
    r.face_eigenvalue = false;
    full_estimate = true;
    set_lambda(std::max(est.bound, alpha_known ? r.max_eigenvalue : 0.0));
  }
  void ensure_alpha() {
    if (!alpha_known) estimate_full();
  }
  /// A new CG run starts along z: the tridiagonal starts again.
  void restart_cg() {
    p.copy_from(z);
    lz_diag.clear();
    lz_off.clear();
    if (track_lanczos && !alpha_known) phi_norm2 = phi.dot(phi);
  }
  /// Records CG's α_j (the step just taken) and β_j (from the new φ) in the tridiagonal.
  void record_cg_step(double a) {
    if (!track_lanczos || alpha_known || !(phi_norm2 > 0)) return;
    lz_diag.push_back(1 / a + (lz_diag.empty() ? 0.0 : lz_beta / lz_alpha));
    const double next = phi.dot(phi);
    lz_alpha = a;
    lz_beta = next / phi_norm2;
    lz_off.push_back(std::sqrt(lz_beta) / a);
    phi_norm2 = next;
  }
  /// λ_max of the face from the CG run that ends here, at the step α = a_cg that would leave
  /// the set (fp = Fp at hand, x still in the face): T_k from the run plus this step, whose
  /// residual φ − α (Fp restricted to the face) needs no application. If its bound is not
  /// within lanczos_tolerance, Lanczos goes on in the face from the last two residuals (one
  /// masked application each) up to lanczos_steps in all.
  void estimate_from_cg(double a) {
    if (!(phi_norm2 > 0) || !(a > 0)) return estimate_full();
    std::vector<double> diag = lz_diag, off = lz_off;
    diag.push_back(1 / a + (diag.empty() ? 0.0 : lz_beta / lz_alpha));
    Vector q_prev = phi.clone(), q = g.duplicate(), w = g.duplicate();
    q.copy_from(g);
    q.axpy(-a, fp);
    set.restrict_to_free(x, q);
    const double next = q.norm();
    off.push_back(next / std::sqrt(phi_norm2) / a);
    q_prev.scale(1 / std::sqrt(phi_norm2));
    auto est = largest_ritz_value(diag, off);
    int apps = 0;
    while (next > 0 && static_cast<int>(diag.size()) < opt.lanczos_steps &&
           est.bound - est.ritz > opt.lanczos_tolerance * est.ritz) {
      if (apps == 0) q.scale(1 / next);
      apply(q, w);
      ++apps;
      set.restrict_to_free(x, w);
      // Orthogonal to the last two basis vectors; the signs of the CG residuals (which
      // alternate against the Lanczos vectors) only flip off-diagonal signs, which the
      // eigenvalues of T do not see.
      const double delta = q.dot(w), gamma = q_prev.dot(w);
      w.axpy(-delta, q);
      w.axpy(-gamma, q_prev);
      const double b = w.norm();
      diag.push_back(delta);
      off.push_back(b);
      est = largest_ritz_value(diag, off);
      if (!(b > 1e-12 * std::abs(delta))) break;  // an invariant subspace of the face
      q_prev.copy_from(q);
      q.copy_from(w);
      q.scale(1 / b);
    }
    r.estimate_applications += apps;
    r.face_eigenvalue = true;
    set_lambda(est.bound);
  }

  /// With a change of variables, 1/s: ‖g^P‖ = ‖S⁻¹ĝ^P‖ in the original variables, since the
  /// splitting commutes with a positive diagonal scaling (one factor per disc).
  const Vector* unscale = nullptr;
  double stop_norm() {
    if (!unscale) return gp.norm();
    TC_PETSC(VecPointwiseMult(work.get(), gp.get(), unscale->get()));
    return work.norm();
  }

  State(const LinearOperator& f_, const FeasibleSet& s, const QpOptions& o, const Vector& d_,
        Vector& x_)
      : f(f_),
        set(s),
        opt(o),
        d(d_),
        x(x_),
        g(x_.duplicate()),
        phi(g.duplicate()),
        beta(g.duplicate()),
        gp(g.duplicate()),
        p(g.duplicate()),
        fp(g.duplicate()),
        z(g.duplicate()),
        work(g.duplicate()),
        x_save(g.duplicate()),
        g_save(g.duplicate()),
        e(g.duplicate()),
        hp(g.duplicate()) {}

  int cauchy_rejected = 0;  // Cauchy steps tried and not taken: stop trying when they dominate
  /// sᵀs / sᵀFs of the last direction s along which a step was taken (CG, feasible or
  /// proportioning step): the Barzilai–Borwein length for the next expansion; 0 = none yet.
  double last_inverse_rayleigh = 0;
  void remember_step(const Vector& s, double sfs) {
    const bool needed = opt.expansion_step == ExpansionStep::barzilai_borwein ||
                        opt.arc_step == ExpansionStep::barzilai_borwein;
    if (needed && sfs > 0) last_inverse_rayleigh = s.dot(s) / sfs;  // the dot only if used
  }

  void apply(const Vector& in, Vector& out) {
    f.apply(in, out);
    ++r.operator_applications;
  }
  void gradient() {  // g = F x − d
    apply(x, g);
    g.axpy(-1.0, d);
  }
  /// CircleFace::slide with discs present: circles are part of the face.
  bool slide = false;
  void split() { set.split_gradient(x, g, phi, beta, gp, slide); }
  /// The search direction in the face: φ, or the masked preconditioned φ.
  void precondition() {
    if (!opt.preconditioner) {
      z.copy_from(phi);
      return;
    }
    opt.preconditioner->apply(phi, z);
    set.restrict_to_free(x, z, slide);
  }
  /// Dostál's proportioning test ‖β‖² ≤ Γ² g̃ᵀφ with the reduced free gradient
  /// g̃ = (x − P(x − ᾱ φ))/ᾱ, which never lets a step of length ᾱ leave the set.
  bool proportional() {
    if (opt.proportioning_test == ProportioningTest::free || !alpha_known)
      return beta.dot(beta) <= opt.gamma * opt.gamma * phi.dot(phi);
    work.copy_from(x);
    work.axpy(-alpha_bar, phi);
    set.project(work);
    work.axpy(-1.0, x);  // = −ᾱ g̃
    const double reduced = -work.dot(phi) / alpha_bar;
    return beta.dot(beta) <= opt.gamma * opt.gamma * reduced;
  }

  /// A conjugate gradient step, or an expansion step when CG would leave the set.
  /// Returns false on breakdown (F not positive definite on p).
  bool cg_or_expansion() {
    apply(p, fp);
    const double pfp = p.dot(fp);
    if (!(pfp > 0)) return false;
    const bool on_circles = slide && set.moves_on_circles(x, p);
    // Sliding, the step sees F plus the circles' curvature (FeasibleSet::add_circle_curvature):
    // with F alone the CG step overshoots along the arcs, and the retraction raises f.
    double php = pfp;
    if (on_circles) {
      hp.copy_from(fp);
      set.add_circle_curvature(x, g, p, hp);
      php = p.dot(hp);
    }
    const double a_cg = g.dot(p) / php;
    const double a_f = set.max_step(x, p, slide);
    remember_step(p, pfp);
    if (a_cg <= a_f && on_circles) return slide_step(a_cg, php);
    if (a_cg <= a_f) {
      ++r.cg_steps;
      x.axpy(-a_cg, p);
      g.axpy(-a_cg, fp);
      split();
      record_cg_step(a_cg);
      precondition();
      const double b = z.dot(fp) / pfp;  // keeps p F-conjugate to the previous direction
      p.scale(-b);
      p.axpy(1.0, z);
      return true;
    }
    if (!alpha_known) {
      if (track_lanczos)
        estimate_from_cg(a_cg);
      else
        estimate_full();
    }
    ++r.expansion_steps;
    if (opt.expansion == Expansion::projected_cg && projected_cg_step(a_cg)) return true;
    if (on_circles) {
      // The feasible step slides nodes along their circles as well: the retraction changes
      // x off the line, so g is recomputed; if f rose, the step is undone and the
      // projected gradient move below starts from where it was.
      x_save.copy_from(x);
      g_save.copy_from(g);
      set.advance(x, p, a_f);
      gradient();
      if (change_of_f() > change_noise()) {
        x.copy_from(x_save);
        g.copy_from(g_save);
        ++r.fallbacks;
      }
    } else {
      set.advance(x, p, a_f);  // as far as feasible: components reaching the boundary bind
      g.axpy(-a_f, fp);
    }
    split();
    expand(opt.expansion == Expansion::full_gradient ? g : phi, opt.expansion_step);
    return true;
  }

  /// CircleFace::slide: the CG step x − α_cg p with the nodes on circles moved along their
  /// tangent and put back on the circle (FeasibleSet::advance snaps them, since a tangent
  /// leaves the circle at once). The retraction moves x off the CG line by O(α²‖p‖²/r), so
  /// g is recomputed (one application) and the step is kept only if f fell; otherwise the
  /// projected gradient step P(x − ᾱg), which descends for ᾱ ≤ 2/λ_max, replaces it. The
  /// next direction is conjugated as in CG and turned into the new tangents: exact
  /// conjugacy is lost with the curvature, which is why this is an option.
  bool slide_step(double a_cg, double php) {
    x_save.copy_from(x);
    g_save.copy_from(g);
    set.advance(x, p, a_cg);
    gradient();
    if (change_of_f() > change_noise()) {
      x.copy_from(x_save);
      g.copy_from(g_save);
      ++r.fallbacks;
      ++r.expansion_steps;
      split();
      expand(g, ExpansionStep::fixed);
      return true;
    }
    ++r.cg_steps;
    ++r.slides;
    split();
    precondition();
    const double b = z.dot(hp) / php;  // conjugate with respect to F + C
    p.scale(-b);
    p.axpy(1.0, z);
    set.restrict_to_free(x, p, true);
    return true;
  }

  /// ½ sᵀ(g_old + g_new) with s = x − x_save: the exact change of f from (x_save, g_save)
  /// for a quadratic, without subtracting two values of f near the minimum.
  double change_of_f() {
    work.copy_from(x);
    work.axpy(-1.0, x_save);  // s
    return 0.5 * (work.dot(g_save) + work.dot(g));
  }
  /// s itself carries the round-off of x − x_old (ε‖x‖ per entry), so Δf is known to
  /// ~ε‖x‖‖g‖ only; an underestimated λ_max raises f by O(ᾱ‖g‖²), far above that.
  double change_noise() const {
    return 1e3 * std::numeric_limits<double>::epsilon() * x.norm() * g_save.norm();
  }

  /// x ← P(x − α_cg p) from the point before the feasible step; kept if f falls (one
  /// application), else undone (the standard expansion follows).
  bool projected_cg_step(double a_cg) {
    x_save.copy_from(x);
    g_save.copy_from(g);
    x.axpy(-a_cg, p);
    set.project(x);
    gradient();
    if (change_of_f() < -change_noise()) {
      ++r.long_expansions;
      split();
      precondition();
      restart_cg();
      return true;
    }
    ++r.fallbacks;
    x.copy_from(x_save);
    g.copy_from(g_save);
    return false;
  }

  /// The length of the expansion move along e (ExpansionStep): never below ᾱ, since ᾱ is
  /// what the fall-back takes anyway.
  double expansion_length(ExpansionStep kind) {
    switch (kind) {
      case ExpansionStep::fixed:
        return alpha_bar;
      case ExpansionStep::barzilai_borwein:
        return std::max(alpha_bar, last_inverse_rayleigh);
      case ExpansionStep::cauchy: {
        apply(e, fp);
        const double efe = e.dot(fp), eg = e.dot(g);
        return efe > 0 && eg > 0 ? std::max(alpha_bar, eg / efe) : alpha_bar;
      }
    }
    return alpha_bar;
  }

  /// x ← P(x_save − α e), its gradient, and whether f fell (rose by no more than round-off
  /// when `strict` is false); if not, x and g are restored.
  bool projected_move(double alpha, bool strict) {
    x.copy_from(x_save);
    x.axpy(-alpha, e);
    set.project(x);
    gradient();
    const double change = change_of_f(), noise = change_noise();
    if (strict ? change < -noise : change <= noise) return true;
    x.copy_from(x_save);
    g.copy_from(g_save);
    return false;
  }

  /// The projected gradient move that follows the feasible step, along `direction` (φ or g).
  /// A move longer than ᾱ (ExpansionStep) is kept only if f falls; else the fixed step ᾱ.
  /// f cannot rise for ᾱ ≤ 2/λ_max; if it does, λ_max was underestimated: undo, halve ᾱ, go
  /// on.
  void expand(const Vector& direction, ExpansionStep kind) {
    ensure_alpha();
    x_save.copy_from(x);
    g_save.copy_from(g);
    e.copy_from(direction);  // direction may be g, which the trial moves overwrite
    const double length = expansion_length(kind);
    bool moved = false;
    if (length > alpha_bar) {
      moved = projected_move(length, true);
      ++(moved ? r.long_expansions : r.fallbacks);
    }
    if (!moved && !projected_move(alpha_bar, false)) {
      // f rose: ᾱ > 2/sᵀFs·sᵀs on this move, λ_max was underestimated. A value given or of
      // one face (deferred) is replaced by a full Lanczos estimate on F first; only if f
      // rose with that one as well is ᾱ halved. Either way x stays, and the next iteration
      // tries again.
      if (!full_estimate) {
        estimate_full();
        ++r.reestimates;
      } else {
        alpha_bar *= 0.5;
        ++r.step_halvings;
      }
    }
    split();
    precondition();
    restart_cg();
  }

  /// P(x − α*β) with α* the exact minimiser along β; true (and the step taken) when it
  /// lowers f by more than the fixed-step projected gradient step is guaranteed to (½ᾱ‖β‖²
  /// is a cheap proxy: the ᾱ step lowers f by at least about that on the chopped part).
  bool cauchy_on_circle() {
    ensure_alpha();
    apply(beta, fp);
    const double bb = beta.dot(beta), bfb = beta.dot(fp);
    if (!(bfb > 0) || !(bb > 0) || bb / bfb <= alpha_bar) {
      ++cauchy_rejected;
      return false;
    }
    const double a = bb / bfb;
    x_save.copy_from(x);
    g_save.copy_from(g);
    x.axpy(-a, beta);
    set.project(x);
    gradient();
    work.copy_from(x);
    work.axpy(-1.0, x_save);
    const double change = 0.5 * (work.dot(g_save) + work.dot(g));
    if (!(change < -0.5 * alpha_bar * bb)) {
      x.copy_from(x_save);
      g.copy_from(g_save);
      ++cauchy_rejected;
      return false;
    }
    ++r.cauchy_steps;
    split();
    precondition();
    restart_cg();
    return true;
  }

  /// A step along the chopped gradient β, releasing components from the boundary. With
  /// upper bounds or discs it may leave the set: then it stops at the boundary, and when it
  /// cannot move at all (a disc's tangent leaves the circle at once) a projected gradient
  /// step of length ᾱ takes its place.
  bool proportioning() {
    ++r.proportioning_steps;
    const double a_f = set.chopped_step_may_leave() ? set.max_step(x, beta) : infinity;
    if (a_f <= 0) {
      // A disc's tangent leaves the circle at once. Try the projected Cauchy step along β,
      // P(x − α*β) with α* = βᵀβ/βᵀFβ ≥ 1/λ_max: on a circle it slides the node along the arc
      // by the step a line search would take, often many times ᾱ. Kept only if f falls;
      // otherwise the fixed-step projected gradient step, which always does.
      if (cauchy_rejected <= r.cauchy_steps && cauchy_on_circle()) return true;
      expand(g, opt.arc_step);  // the active components must move: the full gradient, not φ
      return true;
    }
    apply(beta, fp);
    const double bfb = beta.dot(fp);
    if (!(bfb > 0)) return false;
    // gᵀβ = βᵀβ exactly for the chopped gradient of intervals and discs; computed as gᵀβ
    // it would carry the round-off of β's normal part on a circle (ε‖g‖‖β‖), which for a
    // small β can even change its sign.
    remember_step(beta, bfb);
    const double a = std::min(beta.dot(beta) / bfb, a_f);
    if (a < a_f)
      x.axpy(-a, beta);
    else
      set.advance(x, beta, a);
    g.axpy(-a, fp);
    split();
    precondition();
    restart_cg();
    return true;
  }
};

/// y = D A D x for a diagonal D: the operator in the scaled variables x̂ = S⁻¹x
/// (QpOptions::scaling) is S F S, and the preconditioned direction z = M⁻¹g seen in x̂ is
/// ẑ = S⁻¹ M⁻¹ S⁻¹ ĝ (ĝ = Sg).
class DiagonalSandwich final : public LinearOperator {
 public:
  DiagonalSandwich(const LinearOperator& a, const Vector& d) : a_(a), d_(d), t_(d.duplicate()) {}
  void apply(const Vector& x, Vector& y) const override {
    TC_PETSC(VecPointwiseMult(t_.get(), d_.get(), x.get()));
    a_.apply(t_, y);
    TC_PETSC(VecPointwiseMult(y.get(), d_.get(), y.get()));
  }
  [[nodiscard]] Vector make_vector() const override { return a_.make_vector(); }

 private:
  const LinearOperator& a_;
  const Vector& d_;
  mutable Vector t_;
};

}  // namespace

QpResult Mpgp::solve(const Vector& d, Vector& x) const {
  // The tolerance's scale is d on the components that are free to move: a fixed one (a
  // frictionless node's tangential rows, a held node) has its solution from the set alone and
  // its d may be of any size (in a frictionless slide, the slip: 10¹⁴ × d_n once scaled).
  const Vector d_free = free_part(d, set_);
  const double tolerance = std::max(options_.rtol * d_free.norm(), options_.atol);
  const std::optional<Vector> weights = group_weights(d_free, options_.row_groups);
  if (!options_.scaling)
    return run(f_, set_, options_, d, x, tolerance, weights ? &*weights : nullptr);
  // The change of variables x = S x̂: F̂ = SFS, d̂ = Sd, Ω̂ = S⁻¹Ω; the tolerance stays the
  // one of the original problem and is tested on S⁻¹ĝ^P (State::stop_norm).
  const Vector& s = *options_.scaling;
  Vector inverse_s = s.clone();
  TC_PETSC(VecReciprocal(inverse_s.get()));
  Vector unscale = inverse_s.clone();  // S⁻¹, weighted by the groups
  if (weights) TC_PETSC(VecPointwiseMult(unscale.get(), unscale.get(), weights->get()));
  const DiagonalSandwich f_hat(f_, s);
  const FeasibleSet set_hat = set_.scaled(s);
  Vector d_hat = d.duplicate();
  TC_PETSC(VecPointwiseMult(d_hat.get(), s.get(), d.get()));
  TC_PETSC(VecPointwiseMult(x.get(), inverse_s.get(), x.get()));
  QpOptions o = options_;
  o.scaling = nullptr;
  std::optional<DiagonalSandwich> pc;
  if (options_.preconditioner) o.preconditioner = &pc.emplace(*options_.preconditioner, inverse_s);
  QpResult r = run(f_hat, set_hat, o, d_hat, x, tolerance, &unscale);
  TC_PETSC(VecPointwiseMult(x.get(), s.get(), x.get()));
  return r;
}

QpResult Mpgp::run(const LinearOperator& f, const FeasibleSet& set, const QpOptions& options,
                   const Vector& d, Vector& x, double tolerance, const Vector* unscale) {
  State s(f, set, options, d, x);
  s.unscale = unscale;
  s.slide = options.circle_face == CircleFace::slide && set.has_discs();
  if (options.max_eigenvalue > 0)
    s.set_lambda(options.max_eigenvalue);
  else if (options.eigenvalue_estimate == EigenvalueEstimate::upfront)
    s.estimate_full();
  // Deferred: from the CG coefficients when the face iterations are plain CG on F.
  s.track_lanczos = !s.alpha_known && !options.preconditioner && !s.slide;
  s.r.tolerance = tolerance;

  set.project(x);
  s.gradient();
  s.split();
  s.precondition();
  s.restart_cg();

  for (;;) {
    s.r.projected_gradient = s.stop_norm();
    if (!std::isfinite(s.r.projected_gradient) || !std::isfinite(s.alpha_bar)) {
      s.r.status = QpStatus::breakdown;
      s.r.message = fmt::format("non-finite projected gradient at iteration {}", s.r.iterations);
      break;
    }
    if (s.r.projected_gradient <= s.r.tolerance) {
      s.r.status = QpStatus::converged;
      break;
    }
    if (s.r.iterations >= options.max_iterations) {
      s.r.status = QpStatus::max_iterations;
      s.r.message = fmt::format(
          "not converged in {} iterations: projected gradient {:.3e} > tolerance {:.3e} "
          "({} applications of F)",
          s.r.iterations, s.r.projected_gradient, s.r.tolerance, s.r.operator_applications);
      break;
    }
    const bool prop = s.proportional();
    const bool ok = prop ? s.cg_or_expansion() : s.proportioning();
    ++s.r.iterations;
    if (!ok) {
      s.r.status = QpStatus::breakdown;
      s.r.message = fmt::format(
          "F is not positive definite on the search direction at iteration {} (projected "
          "gradient {:.3e})",
          s.r.iterations, s.r.projected_gradient);
      s.r.projected_gradient = s.stop_norm();
      break;
    }
  }
  return s.r;
}

}  // namespace tc::qp
