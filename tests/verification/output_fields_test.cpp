// The fields of the .vtu (io::body_fields, io::contact_fields) against closed forms:
// - the stress and strain tensors of a patch test under uniform uniaxial stress, on a mesh
//   with moved interior nodes (linear elements reproduce the linear displacement exactly);
// - the contact fields on the master side of the pressed blocks of thermal_contact_test
//   (uniform pressure and conducted flux, carried through the mortar onto a non-matching
//   master mesh).
#include <gtest/gtest.h>

#include <cmath>

#include "support/problems.hpp"
#include "tc/io/output/output.hpp"
#include "tc/run/simulation.hpp"

using namespace tc;
using namespace tc::test;

namespace {

/// A copy of m with every node strictly inside the box moved by a fixed pattern (up to a fifth
/// of a cell): the cells are no longer parallelepipeds, the boundary faces stay plane.
mesh::Mesh distorted(const mesh::Mesh& m, const mesh::Point& lo, const mesh::Point& hi, double h) {
  mesh::Mesh d(m.dim());
  for (int a = 0; a < m.n_nodes(); ++a) {
    auto p = m.point(a);
    bool inside = true;
    for (int k = 0; k < m.dim(); ++k)
      inside = inside && p[k] > lo[k] + 1e-12 && p[k] < hi[k] - 1e-12;
    if (inside)
      for (int k = 0; k < m.dim(); ++k) p[k] += 0.2 * h * std::sin(1.7 * a + 2.3 * k);
    d.add_point(p);
  }
  for (int c = 0; c < m.n_cells(); ++c) d.add_cell(m.cell_type(c), m.cell(c));
  for (const auto& name : m.boundary_names())
    for (const auto& f : m.boundary(name)) d.add_facet(name, f);
  return d;
}

const io::Field& find(const std::vector<io::Field>& fields, const std::string& name) {
  for (const auto& f : fields)
    if (f.name == name) return f;
  ADD_FAILURE() << "no field " << name;
  static const io::Field none;
  return none;
}

struct NullObserver : physics::Observer {};

/// A box on rollers (xmin, ymin, zmin held normal; in 2D xmin and ymin) pulled by a traction p
/// on its top, ΔT = 50 K warmer than θ₀ throughout (no thermoelastic heating, insulated: θ
/// stays uniform): σ = p e_top ⊗ e_top, ε = (p/E)(e e − ν(I − e e)) + αΔT I in 3D; in plane
/// strain (ε_zz = 0) σ_zz = νp − EαΔT, ε_xx = −ν(1 + ν)p/E + (1 + ν)αΔT,
/// ε_yy = (1 − ν²)p/E + (1 + ν)αΔT.
void expect_uniaxial(int dim) {
  const double p = 7.5e7, dt = 50.0;
  const mesh::Point size{2.0, 1.0, 1.5};
  auto prob = box_problem(dim, size, {4, 3, 3}, steel(), physics::Scheme::quasistatic, 1.0, 1);
  prob.physics.thermoelastic_heating = false;
  auto& body = prob.bodies[0];
  body.initial_temperature = prob.physics.reference_temperature + dt;
  body.mesh = distorted(body.mesh, {0, 0, 0}, size, 0.33);
  const std::string top = dim == 3 ? "zmax" : "ymax";
  prob.boundaries.push_back(hold("xmin", {0}));
  prob.boundaries.push_back(hold("ymin", {1}));
  if (dim == 3) prob.boundaries.push_back(hold("zmin", {2}));
  physics::BoundaryCondition pull;
  pull.where = top;
  pull.traction[dim - 1] = core::TimeTable(p);
  prob.boundaries.push_back(pull);
  physics::Simulation sim(prob);
  sim.advance();
  std::vector<io::Field> point, cell;
  io::body_fields(sim, 0, point, cell);
  const double e = body.material.young_modulus, nu = body.material.poisson_ratio;
  const double alpha = body.material.thermal_expansion;
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero(), eps = Eigen::Matrix3d::Zero();
  const int t = dim - 1;  // the loaded axis
  sigma(t, t) = p;
  if (dim == 3) {
    eps.diagonal().setConstant(-nu * p / e + alpha * dt);
    eps(t, t) = p / e + alpha * dt;
  } else {
    sigma(2, 2) = nu * p - e * alpha * dt;
    eps(0, 0) = -nu * (1 + nu) * p / e + (1 + nu) * alpha * dt;
    eps(1, 1) = (1 - nu * nu) * p / e + (1 + nu) * alpha * dt;
  }
  // A direct solve of a well-conditioned system: the error is round-off, ~1e-14 of p and of
  // p/E (and of EαΔT = 1.2e8 Pa, of the size of p); 1e-10 leaves room for the mesh's
  // conditioning.
  const auto& s = find(cell, "stress");
  const auto& g = find(cell, "strain");
  ASSERT_EQ(s.components, 9);
  ASSERT_EQ(s.values.size(), 9u * static_cast<size_t>(body.mesh.n_cells()));
  for (int c = 0; c < body.mesh.n_cells(); ++c)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const auto at = static_cast<size_t>(9 * c + 3 * i + j);
        EXPECT_NEAR(s.values[at], sigma(i, j), 1e-10 * p) << "cell " << c << " σ" << i << j;
        EXPECT_NEAR(g.values[at], eps(i, j), 1e-10 * p / e) << "cell " << c << " ε" << i << j;
      }
  // The body index and the physical group (none: a box mesh).
  for (const double v : find(cell, "body").values) EXPECT_EQ(v, 0.0);
  for (const double v : find(cell, "physical_group").values) EXPECT_EQ(v, -1.0);
}

TEST(OutputFields, StressAndStrainTensorsOfAUniaxialPatchTest3d) {
  expect_uniaxial(3);
}
TEST(OutputFields, StressAndStrainTensorsOfAUniaxialPatchTest2d) {
  expect_uniaxial(2);
}

// The pressed blocks of thermal_contact_test: the lower block's top (slave, 3 × 3 faces) under
// the upper's bottom (master, 2 × 2), E = 4000, ν = 0, pushed 0.015: p = Eδ/(L₁ + L₂) = 30
// uniform; the steady flux through the series resistance 1/κ + 1/h + 1/κ, h = β_C p.
TEST(OutputFields, ContactFieldsOnTheMasterSideOfAPatchTestAreUniform) {
  const double theta0 = 293.15, low = theta0 + 20, high = theta0 + 40, kappa = 52, push = 0.015;
  auto p = pressed_conduction_blocks(theta0, kappa, push, 3);
  p.boundaries.push_back(temperature_bc(0, "zmin", low));
  p.boundaries.push_back(temperature_bc(1, "zmax", high));
  auto c = contact_pair(0, "zmax", 1, "zmin");
  c.conductance_slave = c.conductance_master = 10.0;  // β_C = 5
  p.contacts = {c};
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  for (int s = 0; s < 3; ++s) sim.advance();
  const double pressure = 30, h = 5 * pressure;
  const double q = (high - low) / (1 / kappa + 1 / h + 1 / kappa);
  // The slave's pressure is uniform to the QP and coupling tolerances (1e-12) and round-off
  // (thermal_contact_test); the master's values are Σ_k M_kj f_k / Σ_k M_kj, exact for a
  // uniform f and otherwise off by at most Σ_k |M_kj| / Σ_k M_kj (≤ 3 here, the dual basis'
  // negative lobes) times the slave's spread: 1e-8 relative is far above both.
  const double tol = 1e-8;
  for (const int b : {0, 1}) {
    std::vector<io::Field> point, cell;
    io::body_fields(sim, b, point, cell);
    const auto& m = p.bodies[b].mesh;
    const auto surface = m.boundary_nodes(b == 0 ? "zmax" : "zmin");
    ASSERT_EQ(surface.size(), b == 0 ? 16u : 9u);
    const auto& pr = find(point, "contact_pressure");
    const auto& flux = find(point, "contact_heat_flux");
    const auto& traction = find(point, "tangential_traction");
    const auto& slip = find(point, "slip_velocity");
    std::vector<char> on(static_cast<size_t>(m.n_nodes()), 0);
    for (const int a : surface) {
      on[static_cast<size_t>(a)] = 1;
      EXPECT_NEAR(pr.values[a], pressure, tol * pressure) << "body " << b << " node " << a;
      // The upper block (master) is the warmer: the heat flows into the slave, −q.
      EXPECT_NEAR(flux.values[a], -q, tol * q) << "body " << b << " node " << a;
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(traction.values[3 * a + i], 0.0, tol * pressure);
        EXPECT_NEAR(slip.values[3 * a + i], 0.0, 1e-12);
      }
    }
    for (int a = 0; a < m.n_nodes(); ++a) {  // zero off the contact surface
      if (!on[static_cast<size_t>(a)]) {
        EXPECT_EQ(pr.values[a], 0.0) << "body " << b;
      }
    }
    // The master's interface temperature (4C's 31.4772727 above θ₀) is its own temperature
    // field there: the point data the fields sit beside.
    if (b == 1) {
      for (const int a : surface) {
        EXPECT_NEAR(find(point, "temperature").values[a] - theta0, high - q / kappa - theta0, 1e-7);
      }
    }
    for (const double v : find(cell, "body").values) EXPECT_EQ(v, b);
  }
}

// A sliding contact: the master's tangential traction is the reaction of the slave's, its
// resultant over the master surface equal and opposite (Σ_j w_j t_j = −Σ_k D_kk t_k).
TEST(OutputFields, MasterTractionIsTheReactionOfTheSlaves) {
  auto p = slider_on_base(steel(), 1e-3, 0.2, 2, 293.15, 293.15, 0.3);
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  for (int s = 0; s < 3; ++s) sim.advance();
  const auto* pair = sim.contact().pair(0).mortar.get();
  ASSERT_NE(pair, nullptr);
  std::vector<io::Field> sp, sc, mp, mc;
  io::body_fields(sim, 0, sp, sc);
  io::body_fields(sim, 1, mp, mc);
  const auto& ts = find(sp, "tangential_traction").values;
  const auto& tm = find(mp, "tangential_traction").values;
  // Weights: the slave's ∫ψ_k (D's diagonal, the dual basis); the master's Σ_k M_kj.
  const auto& nodes = pair->contact_nodes();
  const auto& w = pair->weights();
  std::array<double, 3> slave{0, 0, 0}, master{0, 0, 0};
  for (size_t k = 0; k < nodes.size(); ++k)
    for (int i = 0; i < 3; ++i) slave[i] += w[k] * ts[3 * nodes[k] + i];
  core::Vector ones = core::Vector::from(std::vector<double>(nodes.size(), 1.0));
  core::Vector wm(pair->m_matrix().cols());
  pair->m_matrix().mult_transpose(ones, wm);
  const auto wmj = wm.to_std();
  for (size_t j = 0; j < wmj.size(); ++j)
    for (int i = 0; i < 3; ++i) master[i] += wmj[j] * tm[3 * j + i];
  const double scale = std::abs(slave[0]) + std::abs(slave[1]);
  ASSERT_GT(scale, 0.0) << "the slider does not slide";
  // Σ_j (Σ_k M_kj) t_j = −Σ_k (Σ_j M_kj) t_k and Σ_j M_kj = D_kk: round-off only.
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(master[i], -slave[i], 1e-12 * scale) << i;
}

}  // namespace
