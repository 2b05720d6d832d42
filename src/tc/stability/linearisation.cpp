#include "tc/stability/linearisation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "tc/core/error.hpp"
#include "tc/model/rigid_tool.hpp"
#include "tc/run/simulation.hpp"

namespace tc::stability {

namespace {

/// The rows of a matrix being built, each a sorted map column → value (summed).
class Triplets {
 public:
  explicit Triplets(PetscInt n) : rows_(static_cast<size_t>(n)) {}
  void add(PetscInt r, PetscInt c, double v) { rows_[static_cast<size_t>(r)][c] += v; }
  [[nodiscard]] core::SparseMatrix matrix() const {
    const auto n = static_cast<PetscInt>(rows_.size());
    std::vector<PetscInt> nnz;
    for (const auto& r : rows_)
      nnz.push_back(std::max<PetscInt>(1, static_cast<PetscInt>(r.size())));
    core::SparseMatrix m(n, n, nnz);
    for (PetscInt i = 0; i < n; ++i)
      for (const auto& [c, v] : rows_[static_cast<size_t>(i)]) {
        const PetscInt row[] = {i}, col[] = {c};
        m.add_values(row, col, &v);
      }
    m.assemble();
    return m;
  }

 private:
  std::vector<std::map<PetscInt, double>> rows_;
};

/// Calls f(column, value) for every stored entry of row r of a sequential matrix.
template <class F>
void for_row(const core::SparseMatrix& a, PetscInt r, F&& f) {
  PetscInt nz = 0;
  const PetscInt* cols = nullptr;
  const PetscScalar* vals = nullptr;
  TC_PETSC(MatGetRow(a.get(), r, &nz, &cols, &vals));
  for (PetscInt q = 0; q < nz; ++q) f(cols[q], vals[q]);
  TC_PETSC(MatRestoreRow(a.get(), r, &nz, &cols, &vals));
}

/// Index of each dof among the free ones (−1: prescribed), and the free dofs in order.
std::vector<PetscInt> free_index(PetscInt n, const std::vector<PetscInt>& prescribed,
                                 std::vector<PetscInt>& free) {
  std::vector<PetscInt> index(static_cast<size_t>(n), 0);
  for (const auto d : prescribed) index[static_cast<size_t>(d)] = -1;
  for (PetscInt d = 0; d < n; ++d)
    if (index[static_cast<size_t>(d)] == 0) {
      index[static_cast<size_t>(d)] = static_cast<PetscInt>(free.size());
      free.push_back(d);
    }
  return index;
}

/// The mean |entry| of the rows [begin, end) of a in the columns [cbegin, cend).
double mean_entry(const core::SparseMatrix& a, PetscInt begin, PetscInt end, PetscInt cbegin,
                  PetscInt cend, bool diagonal) {
  double sum = 0;
  long count = 0;
  for (PetscInt r = begin; r < end; ++r)
    for_row(a, r, [&](PetscInt c, double v) {
      if (c < cbegin || c >= cend || (diagonal && c != r) || v == 0) return;
      sum += std::abs(v);
      ++count;
    });
  return count > 0 ? sum / static_cast<double>(count) : 1.0;
}

/// Scales the unknowns and the rows alike, S A S x̂ = b S M S x̂ with x = S x̂ (the eigenvalues
/// unchanged): each block to entries of order 1 — u by 1/√⟨K_u,ii⟩, θ by 1/√⟨K_θ,ii⟩, λ_n so
/// that S_u B_n S_λ is of order 1, w so that S_λ g_w S_w is. Unscaled, the mechanics rows (~E h)
/// and the heat rows (~k) differ by 10⁹ and more, and with the thermoelastic block of M
/// shift-and-invert returned spurious eigenpairs whose backward error, measured against ‖A‖,
/// looked small (docs/choices.md).
void scale(Linearisation& lin) {
  const auto& x = lin.x;
  const PetscInt ot = x.theta_offset(), ol = x.lambda_offset();
  const PetscInt nl = static_cast<PetscInt>(x.contact.size()), n = x.size();
  const double su = 1 / std::sqrt(mean_entry(lin.a0, 0, ot, 0, ot, true));
  const double st = 1 / std::sqrt(mean_entry(lin.a0, ot, ol, ot, ol, true));
  const double sl = 1 / (su * mean_entry(lin.a0, ol, ol + nl, 0, ot, false));
  const double sw = x.tool_free ? 1 / (sl * mean_entry(lin.a0, n - 1, n, ol, ol + nl, false)) : 1;
  lin.scale.assign(static_cast<size_t>(n), su);
  for (PetscInt i = ot; i < n; ++i)
    lin.scale[static_cast<size_t>(i)] = i < ol ? st : i < ol + nl ? sl : sw;
  auto d = core::Vector::from(lin.scale);
  for (auto* m : {&lin.a0, &lin.a1, &lin.mass})
    TC_PETSC(MatDiagonalScale(m->get(), d.get(), d.get()));
}

}  // namespace

Linearisation linearise(const physics::Simulation& sim,
                        physics::StabilitySettings::NormalControl normal, bool friction_shear) {
  const auto& p = sim.problem();
  const auto& pair = p.contacts.at(0);
  const int dim = p.dimension;
  if (!pair.rigid_master) throw Error("stability: the contact pair's master is not a rigid tool");
  const auto* mortar = sim.mortar();
  if (!mortar) throw Error("stability: the contact pair has no mortar rows");
  Linearisation lin;
  lin.body = pair.slave_body;
  const auto& sys = sim.system(pair.slave_body);
  const auto& mats = sys.matrices();
  const auto& mat = sys.body().material;

  // The tool's sliding from the state on (the slope of its motion after t^k).
  const auto v = physics::sliding_velocity(*pair.rigid_master, dim, sim.time());
  lin.speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(lin.speed > 0))
    throw Error(
        fmt::format("stability: the rigid tool does not slide after t = {:g} s (its "
                    "velocity along its plane is 0)",
                    sim.time()));
  for (int c = 0; c < 3; ++c) lin.direction[c] = v[c] / lin.speed;

  // The rows of the state's step and its multipliers (node-major [λ_n, λ_τ…]).
  const auto rows = mortar->rows();
  const auto lambda = sim.contact_multipliers();
  const auto& laws = sim.nodal_laws();
  const PetscInt n_nodes = rows.n_nodes();
  if (static_cast<PetscInt>(lambda.size()) != rows.n_rows())
    throw Error("stability: the multipliers do not match the contact rows of the state");

  // The relative slip per unit speed at each contact node, B_m ê (the slave is at rest in the
  // steady state: its part of the slip is the perturbation's, left out as in the theory).
  const auto& tool_sys = sim.system(pair.master_body);
  core::Vector e(tool_sys.n_u()), slip(rows.n_rows()), en(tool_sys.n_u()), gn(rows.n_rows());
  const auto tool_normal = physics::unit_normal(pair.rigid_master->normal, dim);
  {
    auto ev = e.view();
    auto nv = en.view();
    for (PetscInt j = 0; j < tool_sys.n_u() / dim; ++j)
      for (int c = 0; c < dim; ++c) {
        ev[dim * j + c] = lin.direction[c];
        nv[dim * j + c] = tool_normal[c];
      }
  }
  rows.master.mult(e, slip);
  rows.master.mult(en, gn);
  const auto slip_rows = slip.to_std();
  const auto normal_rows = gn.to_std();

  // Unknowns: free u, free θ, the active contact nodes (λ_n > 0 at the state).
  auto& x = lin.x;
  x.tool_free = normal == physics::StabilitySettings::NormalControl::force;
  const auto u_index = free_index(sys.n_u(), sys.u_dirichlet_dofs(), x.u);
  const auto t_index = free_index(sys.n_theta(), sys.theta_dirichlet_dofs(), x.theta);
  double lambda_max = 0;
  for (PetscInt k = 0; k < n_nodes; ++k) lambda_max = std::max(lambda_max, lambda[dim * k]);
  for (PetscInt k = 0; k < n_nodes; ++k) {
    if (lambda[dim * k] > 1e-12 * lambda_max)
      x.contact.push_back(static_cast<int>(k));
    else
      ++lin.open_nodes;
  }
  if (x.contact.empty())
    throw Error(fmt::format("stability: no contact node is pressed at t = {:g} s", sim.time()));

  const PetscInt n = x.size(), ot = x.theta_offset(), ol = x.lambda_offset();
  Triplets a0(n), a1(n), mass(n);
  // Mechanics rows: K_u u + K_uθ θ + Gᵀ λ_n.
  for (size_t i = 0; i < x.u.size(); ++i) {
    const auto r = static_cast<PetscInt>(i);
    for_row(mats.stiffness_u, x.u[i], [&](PetscInt c, double val) {
      if (u_index[c] >= 0) a0.add(r, u_index[c], val);
    });
    if (p.physics.thermal_expansion)
      for_row(mats.coupling_u_theta, x.u[i], [&](PetscInt c, double val) {
        if (t_index[c] >= 0) a0.add(r, ot + t_index[c], val);
      });
  }
  // Heat rows: −K_θ θ (with a constant film's h), and M: M_θ, −θ₀ K_uθᵀ.
  const bool heating = p.physics.thermoelastic_heating && p.physics.thermal_expansion;
  const double theta0 = p.physics.reference_temperature;
  for (size_t i = 0; i < x.theta.size(); ++i) {
    const auto r = ot + static_cast<PetscInt>(i);
    for_row(mats.stiffness_theta, x.theta[i], [&](PetscInt c, double val) {
      if (t_index[c] >= 0) a0.add(r, ot + t_index[c], -val);
    });
    if (const auto* film = sys.constant_film())
      for_row(*film, x.theta[i], [&](PetscInt c, double val) {
        if (t_index[c] >= 0) a0.add(r, ot + t_index[c], -val);
      });
    for_row(mats.mass_theta, x.theta[i], [&](PetscInt c, double val) {
      if (t_index[c] >= 0) mass.add(r, ot + t_index[c], val);
    });
  }
  if (heating)
    for (size_t i = 0; i < x.u.size(); ++i)
      for_row(mats.coupling_u_theta, x.u[i], [&](PetscInt c, double val) {
        if (t_index[c] >= 0) mass.add(ot + t_index[c], static_cast<PetscInt>(i), -theta0 * val);
      });

  // Contact: G = B_n + 𝔉 s B_τ in the u rows (columns λ_n), B_n in the constraint rows, the
  // frictional heat 𝔉 |ṡ| λ_n shared to the slave nodes as `distribute` does (δ_C by D's
  // positive row entries).
  double friction_sum = 0;
  for (size_t a = 0; a < x.contact.size(); ++a) {
    const PetscInt k = x.contact[a];
    const PetscInt col = ol + static_cast<PetscInt>(a);
    const double f = laws.friction.empty() ? 0.0 : laws.friction[static_cast<size_t>(k)];
    const double share = laws.delta_c.empty() ? 1.0 : laws.delta_c[static_cast<size_t>(k)];
    friction_sum += f;
    double rate = 0;
    for (int l = 1; l < dim; ++l) rate += slip_rows[dim * k + l] * slip_rows[dim * k + l];
    rate = std::sqrt(rate);
    std::array<double, 3> s{};  // the slip direction in the rows' tangents (friction work > 0)
    for (int l = 1; l < dim; ++l) s[l] = rate > 0 ? slip_rows[dim * k + l] / rate : 0.0;
    for_row(rows.slave, dim * k, [&](PetscInt c, double val) {
      if (u_index[c] < 0) return;
      a0.add(u_index[c], col, val);
      a0.add(col, u_index[c], val);
    });
    for (int l = 1; l < dim && friction_shear; ++l)
      if (s[l] != 0)
        for_row(rows.slave, dim * k + l, [&](PetscInt c, double val) {
          if (u_index[c] >= 0) a0.add(u_index[c], col, f * s[l] * val);
        });
    if (x.tool_free) {
      a0.add(col, n - 1, normal_rows[dim * k]);
      a0.add(n - 1, col, normal_rows[dim * k]);
    }
    if (!pair.frictional_heating || rate == 0) continue;
    double positive = 0;
    for_row(mortar->d_matrix(), k, [&](PetscInt, double val) { positive += std::max(val, 0.0); });
    if (positive > 0)
      for_row(mortar->d_matrix(), k, [&](PetscInt c, double val) {
        if (t_index[c] >= 0 && val > 0)
          a1.add(ot + t_index[c], col, share * f * rate * val / positive);
      });
  }
  lin.friction = friction_sum / static_cast<double>(x.contact.size());
  lin.a0 = a0.matrix();
  lin.a1 = a1.matrix();
  lin.mass = mass.matrix();
  scale(lin);
  lin.diffusivity = mat.thermal_conductivity / mat.heat_capacity();
  lin.heating_wavenumber = lin.friction * mat.young_modulus * mat.thermal_expansion /
                           (mat.thermal_conductivity * (1 - mat.poisson_ratio));
  return lin;
}

}  // namespace tc::stability
