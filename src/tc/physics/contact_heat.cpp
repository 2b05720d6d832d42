#include "tc/physics/contact_heat.hpp"

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

std::vector<double> distribute(std::span<const double> power, double share,
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
        out[cols[q]] += share * power[k] * std::max(vals[q], 0.0) / sum;
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

std::vector<double> conduction_flux(const contact::MortarPair& mortar,
                                    const contact::ContactRows& rows,
                                    std::span<const double> lambda, double scale,
                                    const core::Vector& theta_slave,
                                    const core::Vector& theta_master) {
  const int dim = rows.dim;
  std::vector<double> flux(static_cast<size_t>(rows.n_nodes()), 0.0);
  core::Vector ones(theta_slave.size()), dsum(rows.n_nodes()), mth(rows.n_nodes());
  ones.fill(1.0);
  mortar.d_matrix().mult(ones, dsum);
  mortar.m_matrix().mult(theta_master, mth);
  const auto ds = dsum.to_std(), mt = mth.to_std(), ts = theta_slave.to_std();
  for (PetscInt k = 0; k < rows.n_nodes(); ++k) {
    if (ds[k] <= 0) continue;
    const double jump = ts[mortar.contact_nodes()[k]] - mt[k] / ds[k];
    flux[k] = scale * std::max(lambda[dim * k], 0.0) * jump;
  }
  return flux;
}

}  // namespace tc::physics
