// The point and cell data of a body's .vtu (OutputWriter::write_fields), apart from the
// writer's files and summaries.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "tc/fem/element.hpp"
#include "tc/io/output/output.hpp"

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

/// The contact fields of the master surfaces of a body (output_fields.cpp, contact_fields):
/// each value at master node j the mortar's weighted mean of the slave's values,
///   f_j = Σ_k M_kj f_k / Σ_k M_kj,   M_kj = ∫ ψ_k φ_j^m dS (thesis §4.3),
/// the row-sum-lumped L² projection of the slave field Σ_k f_k ψ_k onto the master's shape
/// functions (Σ_k ψ_k = 1 on the overlap, so Σ_k M_kj = ∫ φ_j^m dS there): a uniform slave
/// field is carried over unchanged, and Σ_j (Σ_k M_kj) f_j = Σ_k D_kk f_k, the slave's
/// resultant. Vectors change sign (the traction on the master is the reaction, Newton's
/// third law; the slip velocity the master's relative to the slave); the pressure and the
/// conducted flux (out of the slave = into the master) do not. Summed over the pairs.
class MasterSide {
 public:
  explicit MasterSide(int n) : n_(n), weight_(static_cast<size_t>(n), 0.0) {}
  void add(const core::SparseMatrix& m, const std::vector<double>& p, const std::vector<double>& h,
           const std::vector<double>& t, const std::vector<double>& v) {
    const size_t nk = p.size();
    if (m.rows() != static_cast<PetscInt>(nk) || m.cols() != n_) return;
    const auto carry = [&](const std::vector<double>& f, size_t stride, size_t i) {
      std::vector<double> column(nk);
      for (size_t k = 0; k < nk; ++k) column[k] = f[stride * k + i];
      core::Vector y(n_);
      m.mult_transpose(core::Vector::from(column), y);
      return y.to_std();
    };
    const auto add_to = [](std::vector<double>& sum, const std::vector<double>& f) {
      if (sum.empty()) sum.assign(f.size(), 0.0);
      for (size_t j = 0; j < f.size(); ++j) sum[j] += f[j];
    };
    add_to(weight_, carry(std::vector<double>(nk, 1.0), 1, 0));
    add_to(p_, carry(p, 1, 0));
    add_to(h_, carry(h, 1, 0));
    for (size_t i = 0; i < 3; ++i) {
      add_to(t_[i], carry(t, 3, i));
      add_to(v_[i], carry(v, 3, i));
    }
  }
  /// Adds the means to the body's point fields (zero where no slave node reaches).
  void put(std::vector<double>& p, std::vector<double>& h, std::vector<double>& t,
           std::vector<double>& v) const {
    if (p_.empty()) return;
    for (size_t j = 0; j < static_cast<size_t>(n_); ++j) {
      const double w = weight_[j];
      if (!(w > 0)) continue;
      p[j] += p_[j] / w;
      h[j] += h_[j] / w;
      for (size_t i = 0; i < 3; ++i) {
        t[3 * j + i] -= t_[i][j] / w;
        v[3 * j + i] -= v_[i][j] / w;
      }
    }
  }

 private:
  int n_;
  std::vector<double> weight_, p_, h_, t_[3], v_[3];
};

}  // namespace

void body_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data,
                 std::vector<Field>& cell_data) {
  const auto& sys = sim.system(body);
  const auto& st = sim.state(body);
  const auto& m = sys.body().mesh;
  const auto& mat = sys.body().material;
  const int dim = sys.dim();
  const double theta0 = sim.problem().physics.reference_temperature;
  point_data.clear();  // moved in, not copied from an initializer list (as cell_data below)
  point_data.push_back(vector_field("displacement", st.u, dim));
  point_data.push_back(vector_field("velocity", st.v, dim));
  point_data.push_back(Field{"temperature", 1, st.theta.to_std()});

  const auto u = st.u.to_std();
  const auto& theta = point_data.back().values;
  const bool expansion = sim.problem().physics.thermal_expansion;
  Field vm{"von_mises_stress", 1, {}}, flux{"heat_flux", 3, {}}, sub{"subdomain", 1, {}};
  // The tensors as cell data at the cell centre, as von Mises: σ and ε of linear cells are
  // one value per cell on a regular mesh and discontinuous between cells, so nodal values
  // would be an average that no equation of the solver holds (docs/choices.md).
  Field stress{"stress", 9, {}}, strain{"strain", 9, {}};
  Field body_index{"body", 1, std::vector<double>(static_cast<size_t>(m.n_cells()), body)};
  Field group{"physical_group", 1, {}};
  const auto cells = static_cast<size_t>(m.n_cells());  // exact sizes: no growth by doubling
  for (auto* f : {&vm, &flux, &sub, &stress, &strain, &group})
    f->values.reserve(cells * static_cast<size_t>(f->components));
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto nodes = m.cell(c);
    const auto x = fem::cell_coords(m, c);
    Eigen::VectorXd ue(dim * nodes.size()), te(nodes.size()), dte(nodes.size());
    for (size_t a = 0; a < nodes.size(); ++a) {
      for (int k = 0; k < dim; ++k) ue[dim * a + k] = u[dim * nodes[a] + k];
      te[a] = theta[nodes[a]];
      dte[a] = mat.expansion_deviation(te[a], theta0);
    }
    const auto type = m.cell_type(c);
    // C of the cell as K_u holds it: E(θ), ν(θ) at the last re-assembly (BodySystem).
    const auto [young, poisson] = sys.cell_moduli(c);
    const double lambda = fem::lame_lambda(young, poisson), mu = fem::lame_mu(young, poisson);
    const double beta = expansion ? (3 * lambda + 2 * mu) * mat.thermal_expansion : 0.0;
    const auto sigma = fem::cell_stress(type, x, ue, dte, lambda, mu, beta);
    const auto eps = fem::cell_strain(type, x, ue);
    vm.values.push_back(fem::von_mises(sigma));
    for (int i = 0; i < 3; ++i)  // row-major, as VTK's 9-component tensors
      for (int j = 0; j < 3; ++j) {
        stress.values.push_back(sigma(i, j));
        strain.values.push_back(eps(i, j));
      }
    group.values.push_back(m.cell_group(c));
    // κ(θ) at the cell centre's temperature (the mean of the nodes' on a linear cell)
    const double kappa = mat.laws.thermal_conductivity.is_constant()
                             ? mat.thermal_conductivity
                             : mat.laws.thermal_conductivity(te.mean());
    const auto q = fem::cell_heat_flux(type, x, te, kappa);
    flux.values.insert(flux.values.end(), {q[0], q[1], q[2]});
    sub.values.push_back(sys.cell_subdomain()[static_cast<size_t>(c)]);
  }
  // Moved in one by one: an initializer list would copy every field (a list's elements are
  // const), twice the cell data at once.
  cell_data.clear();
  for (auto* f : {&vm, &flux, &sub, &stress, &strain, &body_index, &group})
    cell_data.push_back(std::move(*f));
  contact_fields(sim, body, point_data);
}

std::optional<PairNodeFields> pair_node_fields(const physics::Simulation& sim, int q) {
  // The pressure and the tangential traction Σ_l λ_τl τ_l (λ times the traction per
  // multiplier: ½ with the contact-stabilised Newmark), the slip velocity
  // Σ_l (B_τlΔu)_k/(w_k τ) τ_l and the conducted heat flux β_C λ_n [θ] out of the slave.
  const auto& contact = sim.contact();
  const auto* dual = sim.dual_solver();
  if (!dual || q >= contact.n_pairs() || q >= dual->n_pairs()) return std::nullopt;
  const auto& pr = contact.pair(q);
  const auto* pair = pr.mortar.get();
  if (!pair) return std::nullopt;
  const auto& rows = dual->pair_rows(q);
  const int dim = rows.dim;
  const auto lambda = contact.multipliers(q);
  const auto slip = contact.slip(q);
  const auto& flux = pr.heat_flux;
  const bool have_slip = slip.size() == lambda.size() && !lambda.empty();
  if (static_cast<PetscInt>(lambda.size()) != rows.n_rows() ||
      rows.nodes.size() != pair->contact_nodes().size())
    return std::nullopt;
  const double tau = sim.problem().time.step;
  const double unit = sim.traction_per_multiplier();
  const size_t nk = rows.nodes.size();
  PairNodeFields f;
  f.nodes = rows.nodes;
  f.weights = rows.weights;
  f.pressure.assign(nk, 0.0);
  f.heat_flux.assign(nk, 0.0);
  f.traction.assign(3 * nk, 0.0);
  f.slip_velocity.assign(3 * nk, 0.0);
  for (size_t k = 0; k < nk; ++k) {
    f.pressure[k] = unit * lambda[dim * k];
    if (flux.size() == nk) f.heat_flux[k] = flux[k];
    for (int l = 0; l + 1 < dim; ++l) {
      const auto& tl = pair->tangents(l)[k];
      const double lt = unit * lambda[dim * k + 1 + l];
      const double w = rows.weights[k];
      const double vl = have_slip && w > 0 ? slip[dim * k + 1 + l] / (w * tau) : 0.0;
      for (int i = 0; i < 3; ++i) {
        f.traction[3 * k + i] += lt * tl[i];
        f.slip_velocity[3 * k + i] += vl * tl[i];
      }
    }
  }
  return f;
}

void contact_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data) {
  // On the contact nodes of every pair whose slave is this body (the multipliers live there),
  // zero elsewhere (pair_node_fields); on the master nodes of every pair whose master it is,
  // the same fields carried through the mortar (MasterSide): the body may be both.
  const auto& contact = sim.contact();
  bool any = false;
  for (int q = 0; q < contact.n_pairs(); ++q)
    any = any || (contact.pair(q).mortar && (contact.pair(q).settings->slave_body == body ||
                                             contact.pair(q).settings->master_body == body));
  if (!sim.dual_solver() || !any) return;
  const int n = sim.system(body).body().mesh.n_nodes();
  Field pressure{"contact_pressure", 1, std::vector<double>(n, 0.0)};
  Field traction{"tangential_traction", 3, std::vector<double>(3 * n, 0.0)};
  Field slip_velocity{"slip_velocity", 3, std::vector<double>(3 * n, 0.0)};
  Field heat_flux{"contact_heat_flux", 1, std::vector<double>(n, 0.0)};
  MasterSide on_master(n);
  for (int q = 0; q < contact.n_pairs(); ++q) {
    const auto& pr = contact.pair(q);
    const bool is_slave = pr.settings->slave_body == body;
    const bool is_master = pr.settings->master_body == body;
    if (!is_slave && !is_master) continue;
    const auto f = pair_node_fields(sim, q);
    if (!f) continue;
    if (is_slave)
      for (size_t k = 0; k < f->nodes.size(); ++k) {
        const int a = f->nodes[k];
        pressure.values[a] += f->pressure[k];
        heat_flux.values[a] += f->heat_flux[k];
        for (int i = 0; i < 3; ++i) {
          traction.values[3 * a + i] += f->traction[3 * k + i];
          slip_velocity.values[3 * a + i] += f->slip_velocity[3 * k + i];
        }
      }
    if (is_master)
      on_master.add(pr.mortar->m_matrix(), f->pressure, f->heat_flux, f->traction,
                    f->slip_velocity);
  }
  on_master.put(pressure.values, heat_flux.values, traction.values, slip_velocity.values);
  point_data.push_back(std::move(pressure));
  point_data.push_back(std::move(traction));
  point_data.push_back(std::move(slip_velocity));
  point_data.push_back(std::move(heat_flux));
}

}  // namespace tc::io
