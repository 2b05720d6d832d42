#include "tc/physics/interface_heat/gap_conductance.hpp"

#include <algorithm>

#include "tc/physics/interface_heat/contact_heat.hpp"

namespace tc::physics {

double gap_conductance(const GapConductance& law, double gap) {
  const double g = std::max(gap, 0.0);
  const double gas = law.gas_conductivity > 0 ? law.gas_conductivity / (g + law.gas_offset) : 0.0;
  return std::max(law.table(g), 0.0) + gas;
}

double gap_radiation(double emissivity, double theta_s, double theta_m) {
  return kStefanBoltzmann * emissivity * (theta_s * theta_s + theta_m * theta_m) *
         (theta_s + theta_m);
}

GapFaces gap_faces(const contact::MortarPair& mortar, const core::Vector& theta_slave,
                   const core::Vector& theta_master) {
  auto master = master_at_nodes(mortar, theta_master);
  const auto ts = theta_slave.to_std();
  GapFaces f;
  f.master = std::move(master.theta);
  for (size_t k = 0; k < f.master.size(); ++k) {
    f.slave.push_back(ts[static_cast<size_t>(mortar.contact_nodes()[k])]);
    f.covered.push_back(master.d_sum[k] > 0 ? 1 : 0);
  }
  return f;
}

std::vector<double> nodal_gap_conductance(const GapConductance& law,
                                          const contact::ContactRows& rows, const GapFaces* faces) {
  std::vector<double> h(static_cast<size_t>(rows.n_nodes()), 0.0);
  const double eps = law.effective_emissivity();
  for (size_t k = 0; k < h.size(); ++k) {
    if (rows.weights[k] > 0) h[k] = gap_conductance(law, rows.gap[k] / rows.weights[k]);
    if (faces && eps > 0 && faces->covered[k])
      h[k] += gap_radiation(eps, faces->slave[k], faces->master[k]);
  }
  return h;
}

}  // namespace tc::physics
