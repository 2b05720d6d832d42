#pragma once
// The 2D Hertz set-up of the rate study (contact_hertz_rates_test.cpp, _slow.cpp): the lower
// half of a steel cylinder of radius R pressed by δ onto a steel block, quasistatic,
// frictionless (contact_hertz_test.cpp's bodies), Gmsh meshes of size h within 1.5a of the
// point of first contact at order 1 or 2, and the error of the run's pressure profile
// (hertz_rates.hpp). With the load P per unit length the run transmits, 1/E* = 2(1 − ν²)/E,
// a = √(4PR/(πE*)), p(x) = p₀√(1 − x²/a²), p₀ = 2P/(πa).
#include <gmsh.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "support/problems.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"
#include "tc/run/simulation.hpp"
#include "verification/hertz_gmsh.hpp"
#include "verification/hertz_rates.hpp"

namespace tc::test::hertz2d {

namespace fs = std::filesystem;
constexpr double kRadius = 1.0;        // R [m]
constexpr double kHalfWidth = 0.0215;  // the a that kDelta gives (contact_hertz_test.cpp)
constexpr double kDelta = 1.1e-3;

struct Meshing {
  const char* name;
  int order;        // Gmsh Mesh.ElementOrder
  bool quads;       // Mesh.RecombineAll
  bool incomplete;  // Mesh.SecondOrderIncomplete (Quad8)
};

inline fs::path temp_dir() {
  const auto d = fs::temp_directory_path() / ("tc_hertz_rates_" + std::to_string(getpid()));
  fs::create_directories(d);
  return d;
}

inline void refine_towards(int point, double h, double coarse, const Meshing& k) {
  hertz::size_towards(point, h, coarse, kHalfWidth, kRadius);
  gmsh::option::setNumber("Mesh.Algorithm", 6);
  gmsh::option::setNumber("Mesh.RecombineAll", k.quads ? 1 : 0);
  gmsh::option::setNumber("Mesh.ElementOrder", k.order);
  gmsh::option::setNumber("Mesh.SecondOrderIncomplete", k.incomplete ? 1 : 0);
}

inline void named_group(int dim, const std::vector<int>& tags, const std::string& name) {
  gmsh::model::setPhysicalName(dim, gmsh::model::addPhysicalGroup(dim, tags), name);
}

/// contact_hertz_test.cpp's cylinder and block, at the order and cell kind of k. The
/// second-order nodes are placed on the geometry by Gmsh: the arc's mid-edge nodes on the
/// circle.
inline std::pair<mesh::Mesh, mesh::Mesh> meshes(double h, double coarse, const Meshing& k) {
  const double w = 1.5 * kRadius;
  const auto dir = temp_dir();
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  namespace geo = gmsh::model::geo;
  gmsh::model::add("cylinder");
  const int o = geo::addPoint(0, 0, 0), c = geo::addPoint(0, kRadius, 0);
  const int l = geo::addPoint(-kRadius, kRadius, 0), r = geo::addPoint(kRadius, kRadius, 0);
  const int a1 = geo::addCircleArc(l, c, o), a2 = geo::addCircleArc(o, c, r);
  const int t1 = geo::addLine(r, c), t2 = geo::addLine(c, l);
  const int s = geo::addPlaneSurface({geo::addCurveLoop({a1, a2, t1, t2})});
  geo::synchronize();
  named_group(1, {a1, a2}, "arc");
  named_group(1, {t1, t2}, "top");
  named_group(2, {s}, "cylinder");
  refine_towards(o, h, coarse, k);
  gmsh::model::mesh::generate(2);
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::write((dir / "cylinder.msh").string());
  gmsh::model::remove();

  gmsh::model::add("block");
  const int p1 = geo::addPoint(-w, -w, 0), p2 = geo::addPoint(w, -w, 0);
  const int p3 = geo::addPoint(w, 0, 0), p4 = geo::addPoint(0, 0, 0), p5 = geo::addPoint(-w, 0, 0);
  const int bottom = geo::addLine(p1, p2), right = geo::addLine(p2, p3);
  const int top1 = geo::addLine(p3, p4), top2 = geo::addLine(p4, p5), left = geo::addLine(p5, p1);
  const int sb = geo::addPlaneSurface({geo::addCurveLoop({bottom, right, top1, top2, left})});
  geo::synchronize();
  named_group(1, {top1, top2}, "top");
  named_group(1, {bottom}, "bottom");
  named_group(2, {sb}, "block");
  refine_towards(p4, h, coarse, k);
  gmsh::model::mesh::generate(2);
  gmsh::write((dir / "block.msh").string());
  gmsh::finalize();
  auto cylinder = mesh::read_gmsh(dir / "cylinder.msh", 2);
  auto block = mesh::read_gmsh(dir / "block.msh", 2);
  fs::remove_all(dir);
  return {std::move(cylinder), std::move(block)};
}

inline physics::BoundaryCondition prescribe(int body, const std::string& where, double uy) {
  physics::BoundaryCondition bc;
  bc.body = body;
  bc.where = where;
  bc.displacement[0] = core::TimeTable(0.0);
  bc.displacement[1] = core::TimeTable({0.0, 1.0}, {0.0, uy});
  return bc;
}

inline double effective_modulus() {
  const auto m = steel();
  return m.young_modulus / (2 * (1 - m.poisson_ratio * m.poisson_ratio));
}

/// One quasistatic step pressing the cylinder's top down by δ; the error of its pressure.
inline hertz::Level run(double h, double coarse, const Meshing& k) {
  physics::Problem p;
  p.dimension = 2;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = 1.0;
  p.time.end = 1.0;
  p.physics.thermal_expansion = false;
  p.physics.thermoelastic_heating = false;
  auto [cylinder, block] = meshes(h, coarse, k);
  hertz::Level level;
  level.h = h / kHalfWidth;
  level.dofs = 2L * (cylinder.n_nodes() + block.n_nodes());
  for (int b = 0; b < 2; ++b) {
    physics::Body body;
    body.name = b == 0 ? "cylinder" : "block";
    body.material = steel();
    body.mesh = b == 0 ? std::move(cylinder) : std::move(block);
    body.initial_temperature = p.physics.reference_temperature;
    p.bodies.push_back(std::move(body));
  }
  p.boundaries.push_back(prescribe(0, "top", -kDelta));
  p.boundaries.push_back(prescribe(1, "bottom", 0.0));
  p.contacts = {contact_pair(0, "arc", 1, "top")};
  p.solver.qp_tolerance = 1e-10;
  p.solver.coupling_tolerance = 1e-8;
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  physics::Observer none;
  const auto status = sim.run(none);
  EXPECT_TRUE(status.completed) << status.message;

  const auto& m = sim.problem().bodies[0].mesh;
  const auto lambda_rows = sim.contact_multipliers();
  const auto& rows = sim.dual_solver()->rows();
  std::map<int, double> lambda;
  double force = 0;
  for (size_t i = 0; i < rows.nodes.size(); ++i) {
    lambda[rows.nodes[i]] = lambda_rows[2 * i];
    force += rows.weights[i] * lambda_rows[2 * i];
  }
  const double load = sim.history("contact_normal_force");
  EXPECT_NEAR(force, load, 1e-6 * load);  // λ_k are tractions: Σ d_k λ_k is the force
  const double a = std::sqrt(4 * load * kRadius / (std::numbers::pi * effective_modulus()));
  const double p0 = 2 * load / (std::numbers::pi * a);
  const auto pressure = [&](const mesh::Point& x) {
    const double s = x[0] / a;
    return std::abs(s) < 1 ? p0 * std::sqrt(1 - s * s) : 0.0;
  };
  // ∫p φ̃_k ds on each facet of the arc: split at x = ±a (x is monotone along a facet) and
  // integrate each piece with ξ(t) = ξ₀ + (ξ₁ − ξ₀)(1 − cos πt)/2, whose dξ/dt vanishes at both
  // ends so that √(a − |x|) becomes smooth in t: 24 Gauss points leave a quadrature error far
  // below the discretisation's (the check on Σ d_k p̄_k = P below).
  std::vector<double> gt, gw;
  hertz::gauss01(24, gt, gw);
  hertz::Projection proj;
  for (const auto& f : m.boundary("arc")) {
    const auto x_at = [&](double xi) {
      const auto s = contact::facet_shape(f.type, {xi, 0});
      double x = 0;
      for (int b = 0; b < s.n; ++b) x += s.phi[b] * m.point(f.nodes[b])[0];
      return x;
    };
    std::vector<double> cuts{0.0};
    for (const double edge : {-a, a}) {
      double lo = 0, hi = 1;
      if ((x_at(lo) - edge) * (x_at(hi) - edge) >= 0) continue;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        ((x_at(lo) - edge) * (x_at(mid) - edge) <= 0 ? hi : lo) = mid;
      }
      cuts.push_back(0.5 * (lo + hi));
    }
    cuts.push_back(1.0);
    std::sort(cuts.begin(), cuts.end());
    for (size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double x0 = cuts[c], x1 = cuts[c + 1];
      for (size_t q = 0; q < gt.size(); ++q) {
        const double xi = x0 + (x1 - x0) * 0.5 * (1 - std::cos(std::numbers::pi * gt[q]));
        const double dxi = (x1 - x0) * 0.5 * std::numbers::pi * std::sin(std::numbers::pi * gt[q]);
        const auto s = contact::facet_shape(f.type, {xi, 0});
        double dx = 0, dy = 0;
        for (int b = 0; b < s.n; ++b) {
          dx += s.dphi[b][0] * m.point(f.nodes[b])[0];
          dy += s.dphi[b][0] * m.point(f.nodes[b])[1];
        }
        hertz::accumulate(m, f, {xi, 0}, gw[q] * dxi * std::hypot(dx, dy), pressure, proj);
      }
    }
  }
  level.e = hertz::errors(
      proj, lambda, [&](int node) { return std::abs(m.point(node)[0]); }, a);
  // The quadrature of p̄ saw the whole zone: Σ d_k p̄_k = ∫p = P to the arc's ds/dx − 1 ≤
  // a²/(2R²) (p is a density per unit of the arc's length, Hertz's per unit of x).
  EXPECT_NEAR(level.e.load_exact, load, 1e-3 * load);
  // The run's weights are the same d_k = ∫φ̃_k on the nodes fully in contact.
  for (size_t i = 0; i < rows.nodes.size(); ++i)
    if (std::abs(m.point(rows.nodes[i])[0]) < 0.8 * a) {
      EXPECT_NEAR(rows.weights[i], proj.weight.at(rows.nodes[i]), 1e-3 * rows.weights[i]);
    }
  std::printf("[ measure  ] %s h = a/%.0f: P = %.6e N/m, a = %.5f, %ld dofs, %zu contact nodes\n",
              k.name, kHalfWidth / h, load, a, level.dofs, rows.nodes.size());
  return level;
}

/// The levels h of hs; the far field's size is `coarse` or, when scale_far_field, 0.2R·h/h₀
/// (every cell halves with h, h₀ = hs[0]).
inline std::vector<hertz::Level> study(const Meshing& k, const std::vector<double>& hs,
                                       bool scale_far_field) {
  std::vector<hertz::Level> levels;
  for (const double h : hs)
    levels.push_back(run(h, scale_far_field ? 0.2 * kRadius * h / hs[0] : 0.2 * kRadius, k));
  hertz::print_table(k.name, levels);
  return levels;
}

}  // namespace tc::test::hertz2d
