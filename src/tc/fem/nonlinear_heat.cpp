#include "tc/fem/nonlinear_heat.hpp"

#include "tc/fem/assembler.hpp"

namespace tc::fem {

namespace {

double law_or(const core::TemperatureTable& law, double constant, double theta) {
  return law.is_constant() ? constant : law(theta);
}

}  // namespace

NonlinearHeat::NonlinearHeat(const mesh::Mesh& m, const Material& mat, double theta0, bool lumped)
    : mat_(mat), theta0_(theta0), lumped_(lumped), dim_(m.dim()), volumes_(lumped_volumes(m)) {
  cells_.reserve(static_cast<size_t>(m.n_cells()));
  Eigen::Index largest = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto nodes = m.cell(c);
    cells_.push_back({std::vector<int>(nodes.begin(), nodes.end()),
                      cell_points(m.cell_type(c), cell_coords(m, c))});
    largest = std::max(largest, static_cast<Eigen::Index>(nodes.size()));
  }
  for (auto* v : {&te_, &xe_, &flux_}) v->resize(largest);
  for (auto* v : {&grad_, &gx_, &kg_}) v->resize(dim_);
}

double NonlinearHeat::enthalpy_density(double theta) const {
  const auto& c = mat_.laws.specific_heat;
  return mat_.density *
         (c.is_constant() ? mat_.specific_heat * (theta - theta0_) : c.integral(theta0_, theta));
}

template <class Visit>
void NonlinearHeat::for_each_point(std::span<const double> theta, Visit&& visit) const {
  for (const auto& cell : cells_) {
    const auto nn = static_cast<Eigen::Index>(cell.nodes.size());
    auto te = te_.head(nn);  // a view of the buffer: no allocation per cell or point
    for (Eigen::Index a = 0; a < nn; ++a)
      te[a] = theta[static_cast<size_t>(cell.nodes[static_cast<size_t>(a)])];
    for (const auto& p : cell.points) {
      grad_.noalias() = p.grad.transpose() * te;
      visit(cell, p, p.n.dot(te), grad_);
    }
  }
}

void NonlinearHeat::add_enthalpy(const core::Vector& theta, double s, core::Vector& y) const {
  const auto th = theta.read();
  auto yv = y.view();
  if (lumped_) {
    for (size_t a = 0; a < volumes_.size(); ++a)
      yv[static_cast<PetscInt>(a)] +=
          s * volumes_[a] * enthalpy_density(th[static_cast<PetscInt>(a)]);
    return;
  }
  for_each_point(th.span(), [&](const Cell& cell, const CellPoint& p, double t, const auto&) {
    const double e = s * p.jxw * enthalpy_density(t);
    for (size_t a = 0; a < cell.nodes.size(); ++a)
      yv[cell.nodes[a]] += e * p.n[static_cast<Eigen::Index>(a)];
  });
}

double NonlinearHeat::total_enthalpy(const core::Vector& theta) const {
  const auto th = theta.read();
  double sum = 0;
  if (lumped_) {
    for (size_t a = 0; a < volumes_.size(); ++a)
      sum += volumes_[a] * enthalpy_density(th[static_cast<PetscInt>(a)]);
    return sum;
  }
  // Σ_a N_a = 1 at every point: Σ_a H_a = Σ_points jxw h(θ_h).
  for_each_point(th.span(), [&](const Cell&, const CellPoint& p, double t, const auto&) {
    sum += p.jxw * enthalpy_density(t);
  });
  return sum;
}

void NonlinearHeat::add_nonlinear_part(const core::Vector& theta, double inv_tau,
                                       core::Vector& y) const {
  const auto th = theta.read();
  auto yv = y.view();
  const double c_ref = mat_.heat_capacity(), k_ref = mat_.thermal_conductivity;
  if (lumped_)
    for (size_t a = 0; a < volumes_.size(); ++a) {
      const double t = th[static_cast<PetscInt>(a)];
      yv[static_cast<PetscInt>(a)] += inv_tau * volumes_[a] * (enthalpy_density(t) - c_ref * t);
    }
  for_each_point(th.span(), [&](const Cell& cell, const CellPoint& p, double t, const auto& g) {
    const double e = lumped_ ? 0.0 : inv_tau * p.jxw * (enthalpy_density(t) - c_ref * t);
    const double k =
        p.jxw * (law_or(mat_.laws.thermal_conductivity, mat_.thermal_conductivity, t) - k_ref);
    auto flux = flux_.head(p.grad.rows());
    flux.noalias() = p.grad * g;  // ∇N_a·∇θ_h per node a
    for (size_t a = 0; a < cell.nodes.size(); ++a) {
      const auto i = static_cast<Eigen::Index>(a);
      yv[cell.nodes[a]] += e * p.n[i] + k * flux[i];
    }
  });
}

void NonlinearHeat::add_nonlinear_derivative(const core::Vector& theta, const core::Vector& x,
                                             double inv_tau, core::Vector& y) const {
  const auto th = theta.read();
  const auto xv = x.read();
  auto yv = y.view();
  const auto& cp = mat_.laws.specific_heat;
  const auto& kappa = mat_.laws.thermal_conductivity;
  const double c_ref = mat_.heat_capacity(), k_ref = mat_.thermal_conductivity;
  const auto capacity = [&](double t) {
    return mat_.density * law_or(cp, mat_.specific_heat, t) - c_ref;
  };
  if (lumped_)
    for (size_t a = 0; a < volumes_.size(); ++a) {
      const auto i = static_cast<PetscInt>(a);
      yv[i] += inv_tau * volumes_[a] * capacity(th[i]) * xv[i];
    }
  for_each_point(th.span(), [&](const Cell& cell, const CellPoint& p, double t, const auto& g) {
    const auto nn = static_cast<Eigen::Index>(cell.nodes.size());
    auto xe = xe_.head(nn);
    for (Eigen::Index a = 0; a < nn; ++a) xe[a] = xv[cell.nodes[static_cast<size_t>(a)]];
    const double xq = p.n.dot(xe);
    gx_.noalias() = p.grad.transpose() * xe;
    const double e = lumped_ ? 0.0 : inv_tau * p.jxw * capacity(t) * xq;
    const double k = p.jxw * (law_or(kappa, mat_.thermal_conductivity, t) - k_ref);
    const double dk = p.jxw * (kappa.is_constant() ? 0.0 : kappa.slope(t)) * xq;
    kg_.noalias() = k * gx_ + dk * g;
    auto flux = flux_.head(nn);
    flux.noalias() = p.grad * kg_;
    for (Eigen::Index a = 0; a < nn; ++a)
      yv[cell.nodes[static_cast<size_t>(a)]] += e * p.n[a] + flux[a];
  });
}

}  // namespace tc::fem
