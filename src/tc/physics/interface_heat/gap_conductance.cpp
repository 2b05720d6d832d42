#include "tc/physics/interface_heat/gap_conductance.hpp"

#include <algorithm>

namespace tc::physics {

double gap_conductance(const GapConductance& law, double gap) {
  const double g = std::max(gap, 0.0);
  const double gas = law.gas_conductivity > 0 ? law.gas_conductivity / (g + law.gas_offset) : 0.0;
  return std::max(law.table(g), 0.0) + gas;
}

std::vector<double> nodal_gap_conductance(const GapConductance& law,
                                          const contact::ContactRows& rows) {
  std::vector<double> h(static_cast<size_t>(rows.n_nodes()), 0.0);
  for (size_t k = 0; k < h.size(); ++k)
    if (rows.weights[k] > 0) h[k] = gap_conductance(law, rows.gap[k] / rows.weights[k]);
  return h;
}

}  // namespace tc::physics
