#pragma once
// Barber's thermoelastic rod (issue 38; docs/theory.md, "Barber's rod"): the linear stability of
// the steady state of a rod 0 < x < L held at x = 0 (u = 0, θ = θ₀) whose end x = L touches a
// rigid plane tool at θ_w > θ₀ through the pressure-dependent conductance h = β_C p of (2.13).
// The expansion sets the pressure, p = (E/L)(α∫(θ − θ₀)dx − g₀), so more heat in means more
// pressure and still more heat in: the loop that makes the steady state unstable beyond
//
//   G = 2(1 + Bi),   Bi = β_C p̄ L/κ,   G = β_C E α (θ_w − θ̄_L) L/κ,   δ = G/(2(1 + Bi)) = 1.
//
// A perturbation θ' = Θ(x)e^{st} solves κΘ'' = ρc_p sΘ, Θ(0) = 0, and the linearised flux
// balance at x = L, κΘ'(L) = −β_C p̄ Θ(L) + β_C(θ_w − θ̄_L) p', p' = (Eα/L)∫Θ dx. With
// ξ = x/L, z = sL²ρc_p/κ and Θ = ξ S(zξ²), S(z) = sinh√z/√z (sin√−z/√−z for z < 0):
//
//   F(z) = C(z) + Bi S(z) − G E(z) = 0,   C(z) = cosh√z,   E(z) = (C(z) − 1)/z,
//
// F entire and real in z. The Chebfun example "Stability of a thermoelastic rod" (Driscoll
// 2011, after Barber) is this problem at Bi = 1 with G = 4δ: Θ'(1) + Θ(1) = 4δ∫Θ.
// The coefficients of F's power series, Σ z^n [(2n+2)(2n+1) + Bi(2n+2) − G]/(2n+2)!, change
// sign once (the bracket grows with n) when G > 2(1 + Bi) and never below: exactly one
// positive root above the threshold, none below (Descartes' rule of signs).
//
// The run: a 2D strip [0, L]×[0, H] of N × 1 Quad4 cells (or a 3D bar [0, L]×[0, H]² of N × 1 × 1
// Hex8), ν = 0 and the long sides held normal to themselves, so that σ_xx = E(u' − α(θ − θ₀))
// exactly (uniaxial, no bending of the end face by a lateral expansion that varies along x);
// quasistatic (the rod's wave transit time L/√(E/ρ) ≈ 2e-5 s is eight orders below its diffusion
// time L²ρc_p/κ ≈ 700 s); no thermoelastic heating (not in Barber's model). With ν > 0 the held
// sides make it uniaxial strain, E and α replaced by E′ and α′ (modulus(), expansion()). It
// starts from the steady state plus ε times the mode of the root it measures.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "support/problems.hpp"
#include "tc/mesh/box.hpp"
#include "tc/model/rigid_tool.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test::barber {

/// S(z) = sinh√z/√z, sin√−z/√−z for z < 0 (entire; its series near 0).
inline double sinhc(double z) {
  if (std::abs(z) < 1e-4) return 1 + z / 6 + z * z / 120;  // next term z³/5040 < 2e-16
  if (z > 0) return std::sinh(std::sqrt(z)) / std::sqrt(z);
  return std::sin(std::sqrt(-z)) / std::sqrt(-z);
}
/// C(z) = cosh√z, cos√−z for z < 0.
inline double coshc(double z) {
  return z >= 0 ? std::cosh(std::sqrt(z)) : std::cos(std::sqrt(-z));
}
/// E(z) = (cosh√z − 1)/z = S(z/4)²/2 (cosh x − 1 = 2 sinh²(x/2)), without cancellation.
inline double coshm1c(double z) {
  const double s = sinhc(z / 4);
  return s * s / 2;
}
/// The eigenvalue function F(z) of the header: zero at z = sL²ρc_p/κ of a mode.
inline double eigen_function(double z, double bi, double g) {
  return coshc(z) + bi * sinhc(z) - g * coshm1c(z);
}

/// The roots z of F from the largest down (the leading one first: the growth or the slowest
/// decay), found independently of the FE run: F > 0 for z ≥ G (F ≥ C(1 − G/z), E < C/z), and
/// below 0 the roots lie near −(nπ)², ≥ ~π² apart (cos√−z), so a scan down from G in steps of
/// 1e-2 meets them in order, one sign change each; bisection then to round-off.
inline std::vector<double> roots(double bi, double g, int count) {
  constexpr double kPi = 3.14159265358979324;
  const double step = 1e-2, bottom = -(count + 2) * (count + 2) * kPi * kPi;
  std::vector<double> out;
  double hi = std::max(g, 1.0);
  double fhi = eigen_function(hi, bi, g);
  for (double lo = hi - step; lo > bottom && static_cast<int>(out.size()) < count; lo -= step) {
    const double flo = eigen_function(lo, bi, g);
    if ((flo <= 0) != (fhi <= 0)) {
      double a = lo, b = hi;
      for (int i = 0; i < 200 && b - a > 1e-15 * std::max(1.0, std::abs(a)); ++i) {
        const double m = (a + b) / 2;
        if ((eigen_function(m, bi, g) <= 0) == (flo <= 0))
          a = m;
        else
          b = m;
      }
      out.push_back((a + b) / 2);
    }
    hi = lo;
    fhi = flo;
  }
  if (static_cast<int>(out.size()) < count)
    throw std::logic_error("barber: fewer roots of F than asked above the scan's bottom");
  return out;
}
inline double leading_root(double bi, double g) {
  return roots(bi, g, 1)[0];
}

/// The mode of root z, Θ(ξ) = ξ S(zξ²) (sinh(√z ξ)/√z, sin(√−z ξ)/√−z), scaled to a largest
/// |Θ| of 1 over ξ ∈ [0, 1].
inline double mode(double z, double xi) {
  double largest = 0;
  for (int i = 1; i <= 200; ++i) {
    const double e = i / 200.0;
    largest = std::max(largest, std::abs(e * sinhc(z * e * e)));
  }
  return xi * sinhc(z * xi * xi) / largest;
}

/// A rod's case: the dimensionless groups and the discretisation.
struct Rod {
  double bi = 1;      // β_C p̄ L/κ
  double delta = 1;   // G/(2(1 + Bi)): 1 at the threshold
  int cells = 20;     // along x (one across)
  int dim = 2;        // a strip of Quad4 or (3) a bar of Hex8 cells
  double nu = 0;      // ν; > 0: the held sides make it uniaxial strain (modulus(), expansion())
  double tau = 0.01;  // the step in units of the diffusion time L²ρc_p/κ
  int steps = 60;     // the run; the rate is measured over its second half
  // The perturbation of θ at the tool, relative to θ_w − θ̄_L. Its square is what the linear
  // theory leaves out: the products p'θ' of the flux move the measured rate by ~εG/T over a
  // window T (ε = 1e-4: 3e-3 relative near δ = 1, measured), so 1e-6 (~1e-5); the loop's and
  // the QP's 1e-12 of ‖θ‖ ≈ 2e3 K is 2e-9 K against ε w ≈ 7e-5 K.
  double eps = 1e-6;
  int mode = 0;    // which root's mode is seeded and measured (0: the leading one)
  int window = 0;  // the rate over steps [window, steps]; 0: [steps/2, steps]

  [[nodiscard]] double g() const { return 2 * (1 + bi) * delta; }
};

// Steel-like constants (ν: Rod::nu). L = 0.1 m, H = 0.01 m.
constexpr double kL = 0.1, kH = 0.01, kTheta0 = 293.15;
constexpr double kRho = 7850, kCp = 450, kKappa = 50, kE = 2.0e11, kAlpha = 1.2e-5;
/// The tool's excess θ_w − θ₀ at the threshold: β_C is set from it (below), so that every case
/// has temperatures of ~100 K, far above the fixed point's and the QP's tolerances.
constexpr double kExcessAtThreshold = 150;

/// The rod's modulus and expansion along x: E and α at ν = 0; with ν > 0 and the sides held
/// (uniaxial strain, also ε_zz = 0 in plane strain) σ_xx = (λ + 2μ)u′ − (3λ + 2μ)α(θ − θ₀),
/// so E′ = λ + 2μ = E(1 − ν)/((1 + ν)(1 − 2ν)) and α′ = α(3λ + 2μ)/(λ + 2μ) = α(1 + ν)/(1 − ν).
inline double modulus(const Rod& r) {
  return kE * (1 - r.nu) / ((1 + r.nu) * (1 - 2 * r.nu));
}
inline double expansion(const Rod& r) {
  return kAlpha * (1 + r.nu) / (1 - r.nu);
}

/// The diffusion time L²ρc_p/κ [s].
inline double diffusion_time() {
  return kL * kL * kRho * kCp / kKappa;
}

/// The steady state of a case: θ̄_L − θ₀ = φ = Bi·w, w = θ_w − θ̄_L = Gκ/(β_C E α L) (the flux
/// κφ/L = β_C p̄ w), p̄ = Bi κ/(β_C L), and the gap g₀ = L(αφ/2 − p̄/E) that makes that p̄ the
/// pressure of the expansion α∫(θ̄ − θ₀) = αφL/2 (E′, α′ for ν > 0).
struct Steady {
  double beta = 0, w = 0, phi = 0, pressure = 0, gap = 0;
};
inline Steady steady_state(const Rod& r) {
  Steady s;
  // θ_w − θ₀ = φ + w = (1 + Bi) G κ/(β_C E α L); at δ = 1 that is kExcessAtThreshold.
  const double e = modulus(r), alpha = expansion(r);
  s.beta = 2 * (1 + r.bi) * (1 + r.bi) * kKappa / (e * alpha * kL * kExcessAtThreshold);
  s.w = r.g() * kKappa / (s.beta * e * alpha * kL);
  s.phi = r.bi * s.w;
  s.pressure = r.bi * kKappa / (s.beta * kL);
  s.gap = kL * (alpha * s.phi / 2 - s.pressure / e);
  return s;
}

inline physics::Problem rod_problem(const Rod& r) {
  const Steady s = steady_state(r);
  fem::Material m;
  m.density = kRho;
  m.young_modulus = kE;
  m.poisson_ratio = r.nu;
  m.thermal_expansion = kAlpha;
  m.specific_heat = kCp;
  m.thermal_conductivity = kKappa;
  const double tau = r.tau * diffusion_time();
  physics::Problem p;
  p.dimension = r.dim;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = tau;
  p.time.end = tau * r.steps;
  p.physics.reference_temperature = kTheta0;
  p.physics.thermoelastic_heating = false;
  physics::Body b;
  b.name = "rod";
  b.material = m;
  b.mesh = mesh::make_box(r.dim, {0, 0, 0}, {kL, kH, r.dim == 3 ? kH : 0.0}, {r.cells, 1, 1});
  b.initial_temperature = kTheta0;
  p.bodies.push_back(std::move(b));
  p.boundaries.push_back(displacement_bc(0, "xmin", {{0, 0.0}}));
  p.boundaries.push_back(temperature_bc(0, "xmin", kTheta0));
  p.boundaries.push_back(displacement_bc(0, "ymin", {{1, 0.0}}));
  p.boundaries.push_back(displacement_bc(0, "ymax", {{1, 0.0}}));
  if (r.dim == 3) {
    p.boundaries.push_back(displacement_bc(0, "zmin", {{2, 0.0}}));
    p.boundaries.push_back(displacement_bc(0, "zmax", {{2, 0.0}}));
  }
  physics::RigidTool tool;
  tool.point = {kL + s.gap, 0, 0};
  tool.normal = {-1, 0, 0};  // out of the tool, towards the rod
  tool.temperature = core::TimeTable(kTheta0 + s.phi + s.w);
  physics::ContactSettings c;
  c.slave_body = 0;
  c.slave_where = "xmax";
  c.master_body = -1;
  c.rigid_master = tool;
  c.friction = 0;
  c.frictional_heating = false;
  c.conductance_slave = c.conductance_master = 2 * s.beta;  // β_C = γγ/(γ + γ) = β
  p.contacts = {c};
  // The QP and the fixed point far below the perturbation (Rod::eps).
  p.solver.qp_tolerance = 1e-12;
  p.solver.coupling_tolerance = 1e-12;
  p.solver.max_coupling_iterations = 50;
  physics::place_rigid_tools(p);
  return p;
}

/// What a run measured.
struct Measured {
  double root = 0;         // z of F (the theory)
  double rate = 0;         // z_h: the FE system's eigenvalue, backward Euler's map inverted
  double raw = 0;          // ln(growth per step)/τ in units of the diffusion time
  double first_half = 0;   // z_h over the first and the second half of the window (pure
  double second_half = 0;  // exponential: equal)
  int max_coupling = 0;    // the most coupling iterations a step took
  int cut_backs = 0;
  double seconds = 0;
};

/// Runs case r from θ̄ + ε w Θ(ξ) and measures the perturbation's rate at the tool node: the
/// deviation d_k = θ_L^k − θ̄_L over the window's steps [J, K] gives the factor per step
/// ζ = (d_K/d_J)^{1/(K−J)}; backward Euler's map ζ = 1/(1 − s_h τ) of a mode of the
/// semi-discrete system gives s_h = (1 − 1/ζ)/τ.
inline Measured run(const Rod& r) {
  const auto start = std::chrono::steady_clock::now();
  const Steady s = steady_state(r);
  const auto p = rod_problem(r);
  Measured out;
  out.root = roots(r.bi, r.g(), r.mode + 1)[r.mode];
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  auto c = sim.checkpoint();
  const auto& mesh = p.bodies[0].mesh;
  int tip = -1;  // the node at (L, 0, 0)
  for (int a = 0; a < mesh.n_nodes(); ++a) {
    const auto x = mesh.point(a);
    const double xi = x[0] / kL;
    c.bodies[0].theta[a] = kTheta0 + s.phi * xi + r.eps * s.w * mode(out.root, xi);
    if (std::abs(xi - 1) < 1e-12 && std::abs(x[1]) + std::abs(x[2]) < 1e-12) tip = a;
  }
  sim.restore(c);
  const double theta_l = kTheta0 + s.phi;
  std::vector<double> d;
  for (int k = 0; k < r.steps; ++k) {
    sim.advance();
    out.max_coupling =
        std::max(out.max_coupling, static_cast<int>(sim.history("coupling_iterations")));
    d.push_back(sim.state(0).theta.to_std()[tip] - theta_l);
  }
  out.cut_backs = sim.cut_back_steps();
  const auto factor = [&](int j, int k) { return std::pow(d[k - 1] / d[j - 1], 1.0 / (k - j)); };
  const auto eigen = [&](double zeta) { return (1 - 1 / zeta) / r.tau; };
  const int j = r.window > 0 ? r.window : r.steps / 2, k = r.steps, m = (j + k) / 2;
  out.rate = eigen(factor(j, k));
  out.raw = std::log(factor(j, k)) / r.tau;
  out.first_half = eigen(factor(j, m));
  out.second_half = eigen(factor(m, k));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace tc::test::barber
