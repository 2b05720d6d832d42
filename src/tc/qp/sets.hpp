#pragma once
// The feasible set of the dual QP (6.9): a product over the multipliers of simple convex sets
// — free components (Dirichlet and gluing multipliers), lower bounds (λ_n ≥ 0), intervals
// (2D friction, |λ_τ| ≤ 𝔉γ) and discs (3D friction, ‖λ_τ,k‖ ≤ 𝔉γ_k per slave node).
//
// For the proportioning algorithms every set supplies, at a feasible x and gradient g:
//   free gradient     φ_i = g_i on the free (inactive) components, 0 on the active ones;
//   chopped gradient  β_i on the active components: the part of g_i along which −g_i can
//                     move into the set (0 on the free ones);
//   projected gradient g^P = φ + β, zero exactly at the KKT point (Dostál 2009, §5.1; for
//                     discs Dostál & Kozubek 2012, §2).
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "tc/core/numeric/petsc.hpp"

namespace tc::qp {

using core::Vector;

inline constexpr double infinity = std::numeric_limits<double>::infinity();
/// Activity is decided relative to the bound: the solver lands on the boundary exactly
/// (FeasibleSet::advance snaps), so only round-off of the bound's own size is tolerated.
inline constexpr double active_tolerance = 1e-13;

/// lo ≤ x ≤ hi for one component; lo = −∞, hi = +∞ is a free component, lo = hi a fixed one.
struct Interval {
  double lo = -infinity;
  double hi = infinity;

  [[nodiscard]] double project(double x) const { return std::min(std::max(x, lo), hi); }
  // An infinite bound is never reached. Its tolerance is not formed: ∞ − ∞ is a NaN that
  // compares false anyway, but raises FE_INVALID, which aborts a run under -fp_trap.
  [[nodiscard]] bool at_lower(double x) const {
    return lo != -infinity && x <= lo + active_tolerance * std::abs(lo);
  }
  [[nodiscard]] bool at_upper(double x) const {
    return hi != infinity && x >= hi - active_tolerance * std::abs(hi);
  }
  [[nodiscard]] bool active(double x) const { return at_lower(x) || at_upper(x); }
  /// Chopped gradient of an active component: −g may only point into the interval.
  [[nodiscard]] double chopped(double x, double g) const {
    const bool low = at_lower(x), up = at_upper(x);
    if (low && up) return 0.0;  // a fixed component cannot move
    return low ? std::min(g, 0.0) : std::max(g, 0.0);
  }
  /// The largest α ≥ 0 with lo ≤ x − α p ≤ hi.
  [[nodiscard]] double max_step(double x, double p) const {
    if (p > 0) return (x - lo) / p;
    if (p < 0) return (x - hi) / p;
    return infinity;
  }
};

/// ‖x‖ ≤ r for a pair of components (the two tangential multipliers of one slave node).
struct Disc {
  double r = 0;

  [[nodiscard]] std::array<double, 2> project(std::array<double, 2> x) const {
    const double n = std::hypot(x[0], x[1]);
    if (n <= r) return x;
    const double s = r / n;  // r = 0 maps everything to the centre
    return {s * x[0], s * x[1]};
  }
  [[nodiscard]] bool active(std::array<double, 2> x) const {
    return std::hypot(x[0], x[1]) >= r * (1 - active_tolerance);
  }
  /// Chopped gradient on the circle: the outward normal part of g is blocked when −g points
  /// out, the tangential part stays (moving along it is the sliding direction).
  [[nodiscard]] std::array<double, 2> chopped(std::array<double, 2> x,
                                              std::array<double, 2> g) const {
    const double n = std::hypot(x[0], x[1]);
    if (r == 0 || n == 0) return {0.0, 0.0};  // the set is the centre: nothing can move
    const double nx = x[0] / n, ny = x[1] / n;
    const double gn = std::min(g[0] * nx + g[1] * ny, 0.0);
    return {g[0] - gn * nx, g[1] - gn * ny};
  }
  /// The largest α ≥ 0 with ‖x − α p‖ ≤ r: the positive root of a quadratic.
  [[nodiscard]] double max_step(std::array<double, 2> x, std::array<double, 2> p) const {
    const double pp = p[0] * p[0] + p[1] * p[1];
    if (pp == 0) return infinity;
    if (r == 0) return 0.0;
    const double xp = x[0] * p[0] + x[1] * p[1];
    // On the circle (to the activity tolerance) c = 0: a tangential p leaves at once instead
    // of allowing a spurious step of √(round-off)/‖p‖.
    const double c = active(x) ? 0.0 : std::max(r * r - (x[0] * x[0] + x[1] * x[1]), 0.0);
    return std::max((xp + std::sqrt(xp * xp + pp * c)) / pp, 0.0);
  }
};

/// Indices (local to this rank) of the two components of a disc, and its radius.
struct DiscBlock {
  PetscInt first = 0;
  PetscInt second = 0;
  Disc disc;
};

/// The product set Ω = Π Ω_i over the local components of a (possibly distributed) vector:
/// every component has an Interval (default free); components listed in a DiscBlock are
/// governed by their disc instead. Operations on vectors are collective where they reduce.
class FeasibleSet {
 public:
  /// All components free, with the layout of `layout`.
  explicit FeasibleSet(const Vector& layout);

  void set_interval(PetscInt local_index, Interval iv);
  void add_disc(DiscBlock block);  // its components' intervals are ignored
  [[nodiscard]] PetscInt local_size() const { return static_cast<PetscInt>(intervals_.size()); }
  [[nodiscard]] bool has_discs() const { return !discs_.empty(); }
  /// True when a step along a chopped gradient can leave the set (upper bounds or discs);
  /// with lower bounds only (MPRGP's classic case) it never can.
  [[nodiscard]] bool chopped_step_may_leave() const;

  void project(Vector& x) const;
  /// Largest violation of the set by x (0 when feasible). Collective.
  [[nodiscard]] double violation(const Vector& x) const;
  /// φ, β and g^P = φ + β at a feasible x (see the header comment). With `slide`, the
  /// tangential part of g at a node on its circle (r > 0) goes to φ instead of β, and β keeps
  /// only an inward normal part (g·n)⁺n: the circle is then part of the face, along which
  /// the solver slides (QpOptions::circle_face); g^P is the same either way.
  void split_gradient(const Vector& x, const Vector& g, Vector& free, Vector& chopped,
                      Vector& projected, bool slide = false) const;
  /// Largest α ≥ 0 with x − α p ∈ Ω (∞ if unbounded). With `slide`, nodes on their circle
  /// (r > 0) do not limit α: they move along their tangent and `advance` puts them back on
  /// the circle. Collective.
  [[nodiscard]] double max_step(const Vector& x, const Vector& p, bool slide = false) const;
  /// y += C p with C the curvature term of f restricted to the circles: (μ/r) on the two
  /// components of a node on its circle (r > 0), μ = max(−g·n, 0) the normal force. Along a
  /// tangent p, f on the circle has second derivative pᵀFp + Σ (μ/r)‖p_k‖² (differentiate
  /// f(r(cos θ, sin θ)) twice), which is what a step that slides and retracts sees.
  void add_circle_curvature(const Vector& x, const Vector& g, const Vector& p, Vector& y) const;
  /// Whether a step along p moves a node that is on its circle (r > 0), i.e. whether
  /// `advance` will retract something and the gradient must be recomputed. Collective.
  [[nodiscard]] bool moves_on_circles(const Vector& x, const Vector& p) const;
  /// x ← x − α p for α ≤ max_step(x, p), putting the components that reach the boundary
  /// exactly on it, so that they are active afterwards without a tolerance.
  void advance(Vector& x, const Vector& p, double alpha) const;
  /// Zeros the active components of v (the masked preconditioner works in the free face);
  /// with `slide`, keeps the tangential part of v at nodes on their circle (r > 0).
  void restrict_to_free(const Vector& x, Vector& v, bool slide = false) const;
  /// Zeros the components whose set is one point (an interval lo = hi, a disc of radius 0):
  /// their solution is the set's alone, so their part of a vector (of d) says nothing of how
  /// far a solver is from the rest's.
  void zero_fixed(Vector& v) const;
  /// Number of active components (a disc counts as two). Collective.
  [[nodiscard]] PetscInt count_active(const Vector& x) const;

  /// The set in the variables x̂ = S⁻¹x for S = diag(s), s > 0: intervals [lo/s_i, hi/s_i],
  /// discs of radius r/s. Both components of a disc must share one factor (then the image of
  /// a disc is a disc and its projection is the scaled projection); std::invalid_argument
  /// otherwise. Local, no communication.
  [[nodiscard]] FeasibleSet scaled(const Vector& s) const;
  /// Jacobi factors that keep discs discs: s_i = diag_i^(−1/2) on interval components and
  /// (diag_a diag_b)^(−1/4) on both components of a disc (the geometric mean of the two
  /// Jacobi factors), so that SFS has a unit diagonal except on the discs. diag > 0.
  [[nodiscard]] Vector jacobi_scaling(const Vector& diagonal) const;

 private:
  std::vector<Interval> intervals_;
  std::vector<char> in_disc_;
  std::vector<DiscBlock> discs_;
};

}  // namespace tc::qp
