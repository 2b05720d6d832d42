// Hertz and Cattaneo–Mindlin in 2D plane strain (verification.md): the lower half of a steel
// cylinder of radius R (Gmsh mesh, refined towards the first point of contact) pressed onto a
// steel block, quasistatic, mortar contact on non-matching curved/flat surfaces.
//  - Hertz (frictionless): with the load P per unit length that the run transmits,
//    1/E* = 2(1 − ν²)/E, a = √(4PR/(πE*)), p(x) = p₀√(1 − x²/a²), p₀ = 2P/(πa).
//  - Cattaneo–Mindlin (friction 𝔉, elastically similar bodies, so the normal and tangential
//    problems uncouple): after the normal load, a tangential displacement of the cylinder's top
//    transmits Q < 𝔉P; the stick zone is |x| < c with c/a = √(1 − Q/(𝔉P)).
// The FE half-width and peak come from a least-squares fit of p² = p₀²(1 − x²/a²) to the
// nodal multipliers of the inner contact zone (p > p_max/4), so that they do not snap to the
// mesh: the check is on the pressure profile, not on where the last active node happens to be.
#include <gmsh.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "support/problems.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"
#include "tc/run/simulation.hpp"
#include "verification/hertz_gmsh.hpp"

namespace tc::test {
namespace {

namespace fs = std::filesystem;
constexpr double kRadius = 1.0;        // R [m]
constexpr double kHalfWidth = 0.0215;  // the a that kDelta gives (a ≪ R: Hertz applies)

fs::path temp_dir() {
  const auto d = fs::temp_directory_path() / ("tc_hertz_" + std::to_string(getpid()));
  fs::create_directories(d);
  return d;
}

/// Size h within 1.5 a of the point of first contact (0, 0), growing to `coarse` at 0.8 R.
void refine_towards_origin(int point, double h, double coarse) {
  hertz::size_towards(point, h, coarse, kHalfWidth, kRadius);
  gmsh::option::setNumber("Mesh.Algorithm", 6);  // 8 crashed in Gmsh 4.8.4 (verification.md)
  gmsh::option::setNumber("Mesh.RecombineAll", 1);
}

void named_group(int dim, const std::vector<int>& tags, const std::string& name) {
  gmsh::model::setPhysicalName(dim, gmsh::model::addPhysicalGroup(dim, tags), name);
}

/// Writes the cylinder (lower half disc, centre (0, R), boundaries "arc" and "top") and the
/// block ([−1.5R, 1.5R] × [−1.5R, 0], boundaries "top" and "bottom") and reads them back.
std::pair<mesh::Mesh, mesh::Mesh> hertz_meshes(double h) {
  const double coarse = 0.2 * kRadius, w = 1.5 * kRadius;
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
  refine_towards_origin(o, h, coarse);
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
  refine_towards_origin(p4, h, coarse);
  gmsh::model::mesh::generate(2);
  gmsh::write((dir / "block.msh").string());
  gmsh::finalize();
  auto cylinder = mesh::read_gmsh(dir / "cylinder.msh", 2);
  auto block = mesh::read_gmsh(dir / "block.msh", 2);
  fs::remove_all(dir);
  return {std::move(cylinder), std::move(block)};
}

physics::BoundaryCondition prescribe(int body, const std::string& where, core::TimeTable ux,
                                     core::TimeTable uy) {
  physics::BoundaryCondition bc;
  bc.body = body;
  bc.where = where;
  bc.displacement[0] = std::move(ux);
  bc.displacement[1] = std::move(uy);
  return bc;
}

/// The cylinder (slave) pressed down by δ in step 1, then moved sideways by s in step 2.
physics::Problem cylinder_on_block(double h, double delta, double shift, double friction) {
  physics::Problem p;
  p.dimension = 2;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = 1.0;
  p.time.end = shift != 0 ? 2.0 : 1.0;
  p.physics.thermal_expansion = false;
  p.physics.thermoelastic_heating = false;
  auto [cylinder, block] = hertz_meshes(h);
  for (int b = 0; b < 2; ++b) {
    physics::Body body;
    body.name = b == 0 ? "cylinder" : "block";
    body.material = steel();
    body.mesh = b == 0 ? std::move(cylinder) : std::move(block);
    body.initial_temperature = p.physics.reference_temperature;
    p.bodies.push_back(std::move(body));
  }
  // Step 1 presses (u_y = −δ, u_x = 0); step 2 holds δ and moves the top by s along x.
  const core::TimeTable ux({0.0, 1.0, 2.0}, {0.0, 0.0, shift});
  const core::TimeTable uy({0.0, 1.0}, {0.0, -delta});
  p.boundaries.push_back(prescribe(0, "top", ux, uy));
  p.boundaries.push_back(prescribe(1, "bottom", core::TimeTable(0.0), core::TimeTable(0.0)));
  auto c = contact_pair(0, "arc", 1, "top", friction);
  p.contacts = {c};
  p.solver.qp_tolerance = 1e-10;
  p.solver.coupling_tolerance = 1e-8;
  return p;
}

struct ContactProfile {
  std::vector<double> x, pn, pt;  // per contact node: position, λ_n, λ_τ
  double load = 0, tangential = 0;
  int coupling = 0;
};

struct Last : physics::Observer {
  int max_coupling = 0;
  void step(const physics::Simulation& sim) override {
    max_coupling = std::max(max_coupling, static_cast<int>(sim.history("coupling_iterations")));
  }
};

ContactProfile run(double h, double delta, double shift, double friction) {
  const auto p = cylinder_on_block(h, delta, shift, friction);
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  Last obs;
  const auto status = sim.run(obs);
  EXPECT_TRUE(status.completed) << status.message;
  ContactProfile prof;
  const auto lambda = sim.contact_multipliers();
  const auto& rows = sim.dual_solver()->rows();
  for (size_t k = 0; k < rows.nodes.size(); ++k) {
    prof.x.push_back(p.bodies[0].mesh.point(rows.nodes[k])[0]);
    prof.pn.push_back(lambda[2 * k]);
    prof.pt.push_back(lambda[2 * k + 1]);
  }
  prof.load = sim.history("contact_normal_force");
  prof.tangential = sim.history("contact_tangential_force");
  prof.coupling = obs.max_coupling;
  return prof;
}

/// p² = A − B x² by least squares over the nodes with p > p_max/4: a = √(A/B), p₀ = √A.
std::pair<double, double> fit_ellipse(const ContactProfile& prof) {
  double p_max = 0;
  for (const double p : prof.pn) p_max = std::max(p_max, p);
  std::vector<std::pair<double, double>> pts;
  for (size_t k = 0; k < prof.x.size(); ++k)
    if (prof.pn[k] > 0.25 * p_max) pts.push_back({prof.x[k] * prof.x[k], prof.pn[k] * prof.pn[k]});
  Eigen::MatrixXd a(pts.size(), 2);
  Eigen::VectorXd b(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    a(i, 0) = 1;
    a(i, 1) = -pts[i].first;
    b(i) = pts[i].second;
  }
  const Eigen::Vector2d c = a.colPivHouseholderQr().solve(b);
  return {std::sqrt(c(0) / c(1)), std::sqrt(c(0))};
}

double effective_modulus() {
  const auto m = steel();
  return m.young_modulus / (2 * (1 - m.poisson_ratio * m.poisson_ratio));
}

// δ = 1.1e-3 R gives a ≈ 0.0215 R with these bodies (measured; the closed form is then
// evaluated at the load the run actually transmits).
constexpr double kDelta = 1.1e-3;

/// RMS over the contact nodes of (p_k − p_Hertz(x_k))/p₀: the whole profile's error.
double profile_error(const ContactProfile& prof, double a, double p0) {
  double sum = 0;
  for (size_t k = 0; k < prof.x.size(); ++k) {
    const double r = prof.x[k] / a;
    const double exact = std::abs(r) < 1 ? p0 * std::sqrt(1 - r * r) : 0.0;
    sum += std::pow((prof.pn[k] - exact) / p0, 2);
  }
  return std::sqrt(sum / static_cast<double>(prof.x.size()));
}

TEST(Hertz2d, HalfWidthAndPeakPressureConvergeToTheClosedForm) {
  std::vector<double> err_a, err_profile;
  for (const double h : {kHalfWidth / 3, kHalfWidth / 6, kHalfWidth / 12, kHalfWidth / 24}) {
    const auto prof = run(h, kDelta, 0.0, 0.0);
    const double a = std::sqrt(4 * prof.load * kRadius / (std::numbers::pi * effective_modulus()));
    const double p0 = 2 * prof.load / (std::numbers::pi * a);
    const auto [a_fe, p0_fe] = fit_ellipse(prof);
    double p_peak = 0;
    for (const double p : prof.pn) p_peak = std::max(p_peak, p);
    err_a.push_back(std::abs(a_fe / a - 1));
    err_profile.push_back(profile_error(prof, a, p0));
    std::printf(
        "hertz h = a/%.0f: P = %.5e N/m, a = %.5f (FE %.5f, %.2f %%), p0 = %.5e (FE peak "
        "%.5e, %.2f %%), profile RMS %.2f %% of p0, %zu contact nodes\n",
        kHalfWidth / h, prof.load, a, a_fe, 100 * err_a.back(), p0, p_peak,
        100 * std::abs(p_peak / p0 - 1), 100 * err_profile.back(), prof.x.size());
    // The bound, 3 %, on the half-width and the peak at every mesh of the study.
    EXPECT_LT(err_a.back(), 0.03);
    EXPECT_LT(std::abs(p_peak / p0 - 1), 0.03);
    EXPECT_LE(prof.coupling, 10);
  }
  // Under refinement the half-width converges (measured 2.9 → 1.1 → 0.24 → 0.08 %). The peak
  // and the profile's RMS are already within 1 % on the coarsest mesh and then move at the
  // 0.2 % level with the unstructured mesh (where the nodes fall relative to x = 0 and ±a), so
  // they are bounded rather than required to fall monotonically.
  for (size_t i = 1; i < err_a.size(); ++i) EXPECT_LT(err_a[i], err_a[i - 1]) << "level " << i;
  for (const double e : err_profile) EXPECT_LT(e, 0.02);
}

TEST(CattaneoMindlin2d, StickZoneHalfWidth) {
  // Friction 𝔉 = 0.3; the top moves sideways by s after the normal load. Elastically similar
  // bodies: P stays what step 1 made it, and the stick zone is |x| < c = a√(1 − Q/(𝔉P)).
  // c_FE from the traction deficit 𝔉p − |q| = 𝔉p₀(c/a)√(1 − x²/c²) inside the stick zone,
  // fitted like the pressure (nodes where the deficit exceeds a quarter of its peak).
  const double friction = 0.3, h = kHalfWidth / 24;
  for (const double shift : {1.5e-4, 3.5e-4}) {
    const auto prof = run(h, kDelta, shift, friction);
    const double a = std::sqrt(4 * prof.load * kRadius / (std::numbers::pi * effective_modulus()));
    const double ratio = prof.tangential / (friction * prof.load);
    ASSERT_LT(ratio, 0.95) << "the shift made the cylinder slide: choose a smaller one";
    ASSERT_GT(ratio, 0.1);
    ContactProfile deficit;
    for (size_t k = 0; k < prof.x.size(); ++k)
      if (prof.pn[k] > 0) {
        deficit.x.push_back(prof.x[k]);
        deficit.pn.push_back(std::max(friction * prof.pn[k] - std::abs(prof.pt[k]), 0.0));
      }
    const auto [c_fe, q0] = fit_ellipse(deficit);
    const double c = a * std::sqrt(1 - ratio);
    std::printf(
        "cattaneo-mindlin s = %.1e m: Q/(F P) = %.4f, a = %.5f, c = %.5f (FE %.5f, %.2f "
        "%%), deficit peak %.4e (closed form %.4e)\n",
        shift, ratio, a, c, c_fe, 100 * std::abs(c_fe / c - 1), q0,
        friction * 2 * prof.load / (std::numbers::pi * a) * c / a);
    EXPECT_NEAR(c_fe, c, 0.05 * c);  // the bound
    EXPECT_LE(prof.coupling, 10);
  }
}

}  // namespace
}  // namespace tc::test
