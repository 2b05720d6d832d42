#pragma once
// Jaeger's moving band heat source (Jaeger 1942; Carslaw & Jaeger §10.7; Tian & Kennedy 1994),
// its closed forms and the run that checks the heat path of frictional heating against them
// (issue 38; docs/theory.md, "Jaeger's moving band").
//
// The closed form. A line source of q' [W/m] moving at V along the surface z = 0 of a half-space
// (conductivity k, diffusivity k_d, insulated surface, all of q' into the half-space) has in its
// frame X = x − Vt the steady temperature rise θ(X, z) = q'/(πk) e^{−uX} K₀(u r), u = V/(2k_d),
// r = √(X² + z²) (twice the full space's q'/(2πk) e^{−uX}K₀(ur), by the image in the insulated
// surface). A band |X| < l of flux q(X) is the sum of such lines, so on the surface
//   θ(X) = 1/(πk) ∫_{−l}^{l} q(ξ) g(X − ξ) dξ,   g(s) = e^{−us} K₀(u|s|),
// and for the uniform band q its mean over the band is the single integral
//   θ̄ = q/(2lπk) ∫_{−2l}^{2l} (2l − |s|) g(s) ds.
// Péclet number Pe = V l/(2k_d) (Tian & Kennedy's convention, l the half-width), so u l = Pe.
// Large Pe: each surface point is heated for (l − X)/V as a half-space under a flux switched
// on, θ = (2q/k)√(k_d(l − X)/(πV)), θ_max = 2ql/(k√(πPe)) at the trailing edge, θ̄ = ⅔θ_max.
//
// The transient from rest (the band switched on at t = 0 and moving since): the instantaneous
// surface line source Q' [J/m] on the insulated half-space gives Q'/(2πρc k_d s) e^{−x²/(4k_d s)}
// on the surface after s; summed over the band's past positions,
//   θ(X, t) = (q/ρc) ∫_0^t [erf((X + l + Vs)/(2√(k_d s))) − erf((X − l + Vs)/(2√(k_d s)))]
//             / (2√(π k_d s)) ds,
// which tends to the steady θ(X); what is missing at t is ≈ q l/(πk) E₁(V²t/(4k_d)) (the tail
// s > t, where the band is a line 2lq far behind). An insulated bottom at depth D adds its
// image, at most q l/(πk) E₁(D²/(k_d t)).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace tc::test::jaeger {

/// The half-space and the band: half-width l, conductivity k, diffusivity k_d, speed V.
struct Band {
  double l = 1, k = 1, kd = 1, v = 1;
  [[nodiscard]] double pe() const { return v * l / (2 * kd); }
  [[nodiscard]] double u() const { return v / (2 * kd); }
};

/// 8-point Gauss–Legendre on [a, b].
template <class F>
double gauss8(const F& f, double a, double b) {
  static constexpr std::array<double, 4> x{0.1834346424956498, 0.5255324099163290,
                                           0.7966664774136267, 0.9602898564975363};
  static constexpr std::array<double, 4> w{0.3626837833783620, 0.3137066458778873,
                                           0.2223810344533745, 0.1012285362903763};
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  double s = 0;
  for (size_t i = 0; i < 4; ++i) s += w[i] * (f(c - h * x[i]) + f(c + h * x[i]));
  return s * h;
}

/// ∫_a^b f with f integrable but singular (log, s^{−1/2}) or steep at c ∈ [a, b]: each side cut
/// into panels shrinking geometrically (by 2) towards c, down to 2⁻⁵⁰ of its length (what is
/// left there, ~2⁻⁵⁰ × log, is far below round-off of the sum), each panel `pieces` Gauss
/// panels.
template <class F>
double graded(const F& f, double a, double b, double c, int pieces = 1) {
  double s = 0;
  for (const double end : {a, b}) {
    const double d = end - c;
    if (d == 0) continue;
    const double sign = d > 0 ? 1 : -1;
    double outer = std::abs(d);
    for (int n = 0; n < 50; ++n, outer *= 0.5) {
      const double inner = 0.5 * outer, w = (outer - inner) / pieces;
      for (int i = 0; i < pieces; ++i)
        s += sign * gauss8(f, c + sign * (inner + i * w), c + sign * (inner + (i + 1) * w));
    }
  }
  return s;
}

/// g(s) = e^{−us} K₀(u|s|) (std::cyl_bessel_k, C++17's special functions); beyond z = u|s| = 50,
/// where e^{z} overflows first, K₀'s asymptotic series e^{z}K₀(z) ≈ √(π/(2z))(1 − 1/(8z) +
/// 9/(2(8z)²) − 225/(6(8z)³)), whose next term is 2e-8 there.
inline double kernel(const Band& b, double s) {
  const double us = b.u() * s, z = std::abs(us);
  if (z <= 50) return std::exp(-us) * std::cyl_bessel_k(0.0, z);
  const double y = 1 / (8 * z);
  const double scaled =
      std::sqrt(std::numbers::pi / (2 * z)) * (1 - y + 4.5 * y * y - 37.5 * y * y * y);
  return std::exp(-us - z) * scaled;
}

/// Steady surface temperature rise of the uniform band of flux q at X (its frame).
inline double steady_uniform(const Band& b, double q, double x) {
  // ξ ∈ [−l, l] ↔ s = X − ξ ∈ [X − l, X + l]; K₀'s log singularity at s = 0.
  const double lo = x - b.l, hi = x + b.l;
  const double c = std::clamp(0.0, lo, hi);
  const auto g = [&](double s) { return kernel(b, s); };
  return q / (std::numbers::pi * b.k) * graded(g, lo, hi, c);
}

/// Steady mean over the band of the uniform band's surface temperature rise.
inline double steady_uniform_mean(const Band& b, double q) {
  const double w = 2 * b.l;
  const auto f = [&](double s) { return (w - std::abs(s)) * kernel(b, s); };
  return q / (w * std::numbers::pi * b.k) * graded(f, -w, w, 0.0);
}

/// Steady maximum over the band of f (a scan of 81 points, then golden sections about the best).
inline double band_maximum(const std::function<double(double)>& f, double l) {
  int best = 0;
  double fbest = -1e300;
  for (int i = 0; i <= 80; ++i) {
    const double v = f(-l + 2 * l * i / 80.0);
    if (v > fbest) fbest = v, best = i;
  }
  double a = -l + 2 * l * std::max(best - 1, 0) / 80.0,
         c = -l + 2 * l * std::min(best + 1, 80) / 80.0;
  const double r = 0.5 * (std::sqrt(5.0) - 1);
  for (int it = 0; it < 40; ++it) {
    const double x1 = c - r * (c - a), x2 = a + r * (c - a);
    if (f(x1) > f(x2))
      c = x2;
    else
      a = x1;
  }
  return std::max(fbest, f(0.5 * (a + c)));
}

/// Steady surface temperature of a band of piecewise-linear flux through (xs[i], qs[i]) (xs
/// ascending, in the band's frame) at X: the independent computation of what a run's own
/// frictional flux produces.
inline double steady_profile(const Band& b, const std::vector<double>& xs,
                             const std::vector<double>& qs, double x) {
  double s = 0;
  for (size_t i = 0; i + 1 < xs.size(); ++i) {
    const double x0 = xs[i], x1 = xs[i + 1];
    const auto f = [&](double t) {  // t = X − ξ
      const double xi = x - t;
      const double q = qs[i] + (qs[i + 1] - qs[i]) * (xi - x0) / (x1 - x0);
      return q * kernel(b, t);
    };
    const double lo = x - x1, hi = x - x0;
    if (lo <= 0 && hi >= 0)
      s += graded(f, lo, hi, 0.0);
    else {
      const double c = lo > 0 ? lo : hi;  // the end nearer the singularity
      s += std::abs(c) < hi - lo ? graded(f, lo, hi, c)
                                 : gauss8(f, lo, 0.5 * (lo + hi)) + gauss8(f, 0.5 * (lo + hi), hi);
    }
  }
  return s / (std::numbers::pi * b.k);
}

/// Transient surface temperature rise at X, t after the uniform band q started from rest.
inline double transient_uniform(const Band& b, double q, double x, double t) {
  // s = w²: the 1/√s is gone; the erf differences turn on over w ~ |X ∓ l|/(2√k_d) and, behind
  // the band, where X ± l + V w² changes sign: panels shrinking towards w = 0, each cut in 16.
  const double sk = std::sqrt(b.kd);
  const auto f = [&](double w) {
    if (w == 0) return 0.0;
    const double s = w * w;
    return std::erf((x + b.l + b.v * s) / (2 * sk * w)) -
           std::erf((x - b.l + b.v * s) / (2 * sk * w));
  };
  const double rho_c = b.k / b.kd;
  return q / rho_c / (std::sqrt(std::numbers::pi) * sk) * graded(f, 0.0, std::sqrt(t), 0.0, 16);
}

}  // namespace tc::test::jaeger
