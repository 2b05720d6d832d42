// The point and cell data of a body's .vtu (OutputWriter::write_fields), apart from the
// writer's files and summaries.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "tc/fem/element.hpp"
#include "tc/io/output.hpp"

namespace tc::io {

namespace {

Field vector_field(const std::string& name, const core::Vector& v, int dim) {
  const auto values = v.to_std();
  const size_t n = values.size() / dim;
  Field f{name, 3, std::vector<double>(3 * n, 0.0)};
  for (size_t a = 0; a < n; ++a)
    for (int k = 0; k < dim; ++k) f.values[3 * a + k] = values[dim * a + k];
  return f;
}

}  // namespace

void body_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data,
                 std::vector<Field>& cell_data) {
  const auto& sys = sim.system(body);
  const auto& st = sim.state(body);
  const auto& m = sys.body().mesh;
  const auto& mat = sys.body().material;
  const int dim = sys.dim();
  const double theta0 = sim.problem().physics.reference_temperature;
  point_data = {vector_field("displacement", st.u, dim), vector_field("velocity", st.v, dim),
                Field{"temperature", 1, st.theta.to_std()}};

  const auto u = st.u.to_std();
  const auto& theta = point_data.back().values;
  const double beta = sim.problem().physics.thermal_expansion ? mat.thermal_stress_modulus() : 0.0;
  Field vm{"von_mises_stress", 1, {}}, flux{"heat_flux", 3, {}}, sub{"subdomain", 1, {}};
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto nodes = m.cell(c);
    const auto x = fem::cell_coords(m, c);
    Eigen::VectorXd ue(dim * nodes.size()), te(nodes.size()), dte(nodes.size());
    for (size_t a = 0; a < nodes.size(); ++a) {
      for (int k = 0; k < dim; ++k) ue[dim * a + k] = u[dim * nodes[a] + k];
      te[a] = theta[nodes[a]];
      dte[a] = te[a] - theta0;
    }
    const auto type = m.cell_type(c);
    vm.values.push_back(
        fem::von_mises(fem::cell_stress(type, x, ue, dte, mat.lame_lambda(), mat.lame_mu(), beta)));
    const auto q = fem::cell_heat_flux(type, x, te, mat.thermal_conductivity);
    flux.values.insert(flux.values.end(), {q[0], q[1], q[2]});
    sub.values.push_back(sys.cell_subdomain()[static_cast<size_t>(c)]);
  }
  cell_data = {std::move(vm), std::move(flux), std::move(sub)};
  contact_fields(sim, body, point_data);
}

void contact_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data) {
  // On the contact nodes of every pair whose slave is this body (the multipliers live there),
  // zero elsewhere: the pressure and the tangential traction Σ_l λ_τl τ_l (λ times the traction
  // per multiplier: ½ with the contact-stabilised Newmark), the slip velocity
  // Σ_l (B_τlΔu)_k/(w_k τ) τ_l and the conducted heat flux β_C λ_n [θ] out of the slave.
  const auto& contact = sim.contact();
  const auto* dual = sim.dual_solver();
  bool slave = false;
  for (int q = 0; q < contact.n_pairs(); ++q)
    slave = slave || (contact.pair(q).mortar && contact.pair(q).settings->slave_body == body);
  if (!dual || !slave) return;
  const int n = sim.system(body).body().mesh.n_nodes();
  Field pressure{"contact_pressure", 1, std::vector<double>(n, 0.0)};
  Field traction{"tangential_traction", 3, std::vector<double>(3 * n, 0.0)};
  Field slip_velocity{"slip_velocity", 3, std::vector<double>(3 * n, 0.0)};
  Field heat_flux{"contact_heat_flux", 1, std::vector<double>(n, 0.0)};
  const double tau = sim.problem().time.step;
  const double unit = sim.traction_per_multiplier();
  for (int q = 0; q < contact.n_pairs() && q < dual->n_pairs(); ++q) {
    const auto& pr = contact.pair(q);
    const auto* pair = pr.mortar.get();
    if (!pair || pr.settings->slave_body != body) continue;
    const auto& rows = dual->pair_rows(q);
    const int dim = rows.dim;
    const auto lambda = contact.multipliers(q);
    const auto slip = contact.slip(q);
    const auto& flux = pr.heat_flux;
    const bool have_slip = slip.size() == lambda.size() && !lambda.empty();
    if (static_cast<PetscInt>(lambda.size()) != rows.n_rows() ||
        rows.nodes.size() != pair->contact_nodes().size())
      continue;
    for (size_t k = 0; k < rows.nodes.size(); ++k) {
      const int a = rows.nodes[k];
      pressure.values[a] += unit * lambda[dim * k];
      if (flux.size() == rows.nodes.size()) heat_flux.values[a] += flux[k];
      for (int l = 0; l + 1 < dim; ++l) {
        const auto& t = pair->tangents(l)[k];
        const double lt = unit * lambda[dim * k + 1 + l];
        const double w = rows.weights[k];
        const double v = have_slip && w > 0 ? slip[dim * k + 1 + l] / (w * tau) : 0.0;
        for (int i = 0; i < 3; ++i) {
          traction.values[3 * a + i] += lt * t[i];
          slip_velocity.values[3 * a + i] += v * t[i];
        }
      }
    }
  }
  point_data.push_back(std::move(pressure));
  point_data.push_back(std::move(traction));
  point_data.push_back(std::move(slip_velocity));
  point_data.push_back(std::move(heat_flux));
}

}  // namespace tc::io
