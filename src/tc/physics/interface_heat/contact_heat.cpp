#include "tc/physics/interface_heat/contact_heat.hpp"

#include <algorithm>

namespace tc::physics {

double traction_per_multiplier(bool stabilised) {
  return stabilised ? 0.5 : 1.0;
}

std::vector<double> friction_work(const contact::ContactRows& rows, std::span<const double> lambda,
                                  std::span<const double> slip) {
  const int dim = rows.dim;
  std::vector<double> work(static_cast<size_t>(rows.n_nodes()), 0.0);
  for (PetscInt k = 0; k < rows.n_nodes(); ++k)
    for (int l = 1; l < dim; ++l) work[k] += lambda[dim * k + l] * slip[dim * k + l];
  return work;
}

std::vector<double> step_slip(const contact::ContactRows& rows, const core::Vector& du_slave,
                              const core::Vector& du_master) {
  core::Vector inc(rows.n_rows());
  rows.slave.mult(du_slave, inc);
  rows.master.mult_add(du_master, inc);
  return inc.to_std();
}

std::vector<double> distribute(std::span<const double> power, std::span<const double> share,
                               const core::SparseMatrix& x) {
  std::vector<double> out(static_cast<size_t>(x.cols()), 0.0);
  for (PetscInt k = 0; k < x.rows(); ++k) {
    PetscInt nz = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    TC_PETSC(MatGetRow(x.get(), k, &nz, &cols, &vals));
    double sum = 0;
    for (PetscInt q = 0; q < nz; ++q) sum += std::max(vals[q], 0.0);
    if (sum > 0)
      for (PetscInt q = 0; q < nz; ++q)
        out[cols[q]] += share[k] * power[k] * std::max(vals[q], 0.0) / sum;
    TC_PETSC(MatRestoreRow(x.get(), k, &nz, &cols, &vals));
  }
  return out;
}

std::vector<double> nonnegative_heat(std::vector<double> work) {
  double total = 0, positive = 0;
  for (const double w : work) {
    total += w;
    positive += std::max(w, 0.0);
  }
  if (total > 0 && positive > total)
    for (double& w : work) w = std::max(w, 0.0) * (total / positive);
  return work;
}

MasterAtNodes master_at_nodes(const contact::MortarPair& mortar, const core::Vector& theta_master) {
  const auto& d = mortar.d_matrix();
  core::Vector ones(d.cols()), dsum(d.rows()), mth(d.rows());
  ones.fill(1.0);
  d.mult(ones, dsum);
  mortar.m_matrix().mult(theta_master, mth);
  MasterAtNodes out{mth.to_std(), dsum.to_std()};
  for (size_t k = 0; k < out.theta.size(); ++k)
    if (out.d_sum[k] > 0) out.theta[k] /= out.d_sum[k];
  return out;
}

std::vector<double> conduction_flux(const contact::MortarPair& mortar,
                                    const contact::ContactRows& rows,
                                    std::span<const double> lambda, std::span<const double> scale,
                                    const core::Vector& theta_slave,
                                    const core::Vector& theta_master,
                                    std::span<const double> open) {
  const int dim = rows.dim;
  std::vector<double> flux(static_cast<size_t>(rows.n_nodes()), 0.0);
  const auto master = master_at_nodes(mortar, theta_master);
  const auto ts = theta_slave.to_std();
  for (PetscInt k = 0; k < rows.n_nodes(); ++k) {
    if (master.d_sum[k] <= 0) continue;
    const double jump = ts[mortar.contact_nodes()[k]] - master.theta[k];
    const double h = open.empty() ? 0.0 : open[static_cast<size_t>(k)];
    flux[k] = (scale[k] * std::max(lambda[dim * k], 0.0) + h) * jump;
  }
  return flux;
}

}  // namespace tc::physics
