#pragma once
// Shared by the Hertz convergence-rate tests (contact_hertz_rates_test.cpp in 2D,
// contact_hertz_3d_rates_slow.cpp in 3D): the error of the nodal multipliers of a dual mortar
// against the closed-form pressure, and the table of observed rates.
//
// The norm. The coefficients of λ_h = Σ λ_k ψ_k on the dual basis ψ, biorthogonal to the
// (transformed) slave basis φ̃, are the quasi-projection of the traction onto span φ̃:
// λ_k = ∫λ_h φ̃_k / ∫φ̃_k (docs/theory.md, "Second-order slave faces", L_θγ). The exact
// pressure's counterpart is then p̄_k = ∫p φ̃_k / d_k with d_k = ∫φ̃_k, not the point value
// p(x_k): p̄_k − p(x_k) = O(h²) for either order (a weighted mean of a curved profile), which
// would cap every rate at 2 and hide what the quadratic space gains. The error is the discrete
// L2 norm of λ − p̄ weighted by d_k, relative to that of p̄:
//     e² = Σ_k d_k (λ_k − p̄_k)² / Σ_k d_k p̄_k²,
// i.e. the L2 norm of the quasi-projection's error, with Σ_k d_k λ_k = P = Σ_k d_k p̄_k (the load
// the run transmits, from which a and p₀ are computed): only the profile's shape is measured.
// It is taken over the whole slave surface (e_all) and over the nodes with |x_k| < 0.8a
// (e_in), where p is smooth: the pressure ~ √(a − |x|) at the edge of contact limits the whole
// zone's L2 rate to ~1 (the best approximation of x^½ on a uniform mesh is O(h^{1/2 + 1/2}) = O(h)
// in L2 for any polynomial degree), while inside the zone the rate is what the edge pollutes.
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <vector>

#include "tc/contact/geometry.hpp"
#include "tc/contact/integration.hpp"
#include "tc/mesh/mesh.hpp"

namespace tc::test::hertz {

/// Gauss–Legendre nodes and weights on [0, 1] (Golub–Welsch free: Newton on P_n).
inline void gauss01(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(n, 0);
  w.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[i] = 0.5 * (1 - z);
    w[i] = 1 / ((1 - z * z) * dp * dp);
  }
}

/// Per slave node: d_k = ∫φ̃_k and ∫p φ̃_k, accumulated over the facets.
struct Projection {
  std::map<int, double> weight, pressure;
};

/// Adds one facet's ∫φ̃_a dA and ∫p φ̃_a dA at the points (ξ, dA) the caller supplies; φ̃ with
/// the share α (MortarOptions::vertex_share; α = 0: the physical φ, whose ∫p φ_a are the
/// consistent nodal forces of p).
inline void accumulate(const mesh::Mesh& m, const mesh::Facet& f, const contact::Vec2& xi,
                       double da, const std::function<double(const mesh::Point&)>& p,
                       Projection& out, double alpha = contact::kVertexShare) {
  const auto s = contact::facet_shape(f.type, xi);
  const auto t = contact::basis_transformation(f.type, alpha);
  mesh::Point x{0, 0, 0};
  for (int b = 0; b < s.n; ++b)
    for (int c = 0; c < 3; ++c) x[c] += s.phi[b] * m.point(f.nodes[b])[c];
  const double pressure = p(x);
  for (int a = 0; a < s.n; ++a) {
    double phi = 0;
    for (int b = 0; b < s.n; ++b) phi += t.t[a][b] * s.phi[b];
    out.weight[f.nodes[a]] += phi * da;
    out.pressure[f.nodes[a]] += phi * pressure * da;
  }
}

struct Errors {
  double all = 0, inner = 0;
  double load_exact = 0;  // Σ d_k p̄_k = ∫p, the check that the quadrature saw the whole zone
};

/// e_all and e_in of the header's comment: λ by slave node, r(x) the distance from the centre
/// of contact, a the closed-form radius.
inline Errors errors(const Projection& proj, const std::map<int, double>& lambda,
                     const std::function<double(int)>& r, double a) {
  double num = 0, den = 0, num_in = 0, den_in = 0;
  Errors e;
  for (const auto& [node, d] : proj.weight) {
    const double pbar = proj.pressure.at(node) / d;
    const auto it = lambda.find(node);
    const double l = it == lambda.end() ? 0.0 : it->second;
    num += d * (l - pbar) * (l - pbar);
    den += d * pbar * pbar;
    e.load_exact += d * pbar;
    if (r(node) < 0.8 * a) {
      num_in += d * (l - pbar) * (l - pbar);
      den_in += d * pbar * pbar;
    }
  }
  e.all = std::sqrt(num / den);
  e.inner = std::sqrt(num_in / den_in);
  return e;
}

/// The nodal forces' error, a norm that does not depend on the multiplier basis (so that
/// bases can be compared): f_j = Σ_k D_kj λ_k = ∫λ_h φ_j (the contact force on slave node j)
/// against the consistent f̂_j = ∫p φ_j (`exact`: accumulate with α = 0), relative ℓ2 over the
/// slave nodes, all and |x_j| < 0.8a.
inline Errors force_errors(const Projection& exact, const std::map<int, double>& force,
                           const std::function<double(int)>& r, double a) {
  double num = 0, den = 0, num_in = 0, den_in = 0;
  Errors e;
  for (const auto& [node, fhat] : exact.pressure) {
    const auto it = force.find(node);
    const double f = it == force.end() ? 0.0 : it->second;
    num += (f - fhat) * (f - fhat);
    den += fhat * fhat;
    e.load_exact += fhat;
    if (r(node) < 0.8 * a) {
      num_in += (f - fhat) * (f - fhat);
      den_in += fhat * fhat;
    }
  }
  e.all = std::sqrt(num / den);
  e.inner = std::sqrt(num_in / den_in);
  return e;
}

struct Level {
  double h = 0;
  long dofs = 0;
  Errors e;
  Errors force;  // force_errors (where the test computes them)
  Errors point;  // λ_k against p(x_k), relative RMS over the contact nodes (likewise)
  long qp_iterations = 0, applications = 0;  // of the dual QP over the run
};

/// Observed rate between levels i − 1 and i in h.
inline double rate(const std::vector<Level>& l, size_t i, bool inner) {
  const double e0 = inner ? l[i - 1].e.inner : l[i - 1].e.all;
  const double e1 = inner ? l[i].e.inner : l[i].e.all;
  return std::log(e0 / e1) / std::log(l[i - 1].h / l[i].h);
}

/// The least-squares slope of log e against log h over every level.
inline double fitted_rate(const std::vector<Level>& l, bool inner) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(l.size());
  for (const auto& v : l) {
    const double x = std::log(v.h), y = std::log(inner ? v.e.inner : v.e.all);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

inline void print_table(const char* what, const std::vector<Level>& l) {
  std::printf("[ measure  ] Hertz %s: level, h/a, dofs, e_all, rate, e_in (|x| < 0.8a), rate\n",
              what);
  for (size_t i = 0; i < l.size(); ++i) {
    if (i == 0)
      std::printf("[ measure  ]   %zu  %.5f  %7ld  %.4e    -    %.4e    -\n", i, l[i].h, l[i].dofs,
                  l[i].e.all, l[i].e.inner);
    else
      std::printf("[ measure  ]   %zu  %.5f  %7ld  %.4e  %.2f  %.4e  %.2f\n", i, l[i].h, l[i].dofs,
                  l[i].e.all, rate(l, i, false), l[i].e.inner, rate(l, i, true));
  }
  std::printf("[ measure  ]   least-squares rate: e_all %.2f, e_in %.2f\n", fitted_rate(l, false),
              fitted_rate(l, true));
}

}  // namespace tc::test::hertz
