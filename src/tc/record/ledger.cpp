#include "tc/record/ledger.hpp"

#include <array>
#include <cmath>

namespace tc::physics {

void ContactStatistics::record_step(const contact::ContactRows& rows,
                                    std::span<const double> lambda, std::span<const double> work,
                                    double unit, std::span<const double> bound,
                                    const contact::MortarPair* mortar) {
  const int dim = rows.dim;
  const auto& l = lambda;
  auto& cs = *this;
  cs.normal_force = cs.tangential_force = cs.tangential_force_sum = 0;
  cs.active_nodes = cs.slip_nodes = 0;
  for (const double w : work) cs.dissipation += unit * w;
  // The resultant Σ_k w_k Σ_l λ_τl,k t_l,k in space (the mortar pair's tangents; rows without
  // them have one tangent frame for all nodes, as the node-to-node rows of flat faces).
  const bool frames = mortar && mortar->tangents(0).size() == static_cast<size_t>(rows.n_nodes());
  std::array<double, 3> resultant{0, 0, 0};
  for (PetscInt k = 0; k < rows.n_nodes(); ++k) {
    const double w = rows.weights[k];
    const double ln = l[dim * k];
    double lt2 = 0;
    for (int i = 1; i < dim; ++i) {
      const double li = l[dim * k + i];
      lt2 += li * li;
      for (int x = 0; x < 3; ++x)
        resultant[x] += w * li * (frames ? mortar->tangents(i - 1)[k][x] : (x == i - 1 ? 1 : 0));
    }
    const double lt = std::sqrt(lt2);
    cs.normal_force += unit * w * ln;
    cs.tangential_force_sum += unit * w * lt;
    if (ln > 0) {
      ++cs.active_nodes;
      const double b = bound.empty() ? 0.0 : bound[k];
      if (b > 0 && lt >= b * (1 - slip_tolerance)) ++cs.slip_nodes;
    }
  }
  cs.tangential_force = unit * std::hypot(resultant[0], resultant[1], resultant[2]);
}

void ContactStatistics::register_history(History& h) const {
  h.add("qp_iterations", History::value_of(qp_iterations));
  h.add("operator_applications", History::value_of(operator_applications));
  h.add("contact_normal_force", History::value_of(normal_force));
  h.add("contact_tangential_force", History::value_of(tangential_force));
  h.add("frictional_dissipation", History::value_of(dissipation));
  h.add("active_nodes", History::value_of(active_nodes));
  h.add("slip_nodes", History::value_of(slip_nodes));
  h.add("friction_iterations", History::value_of(friction_iterations));
  h.add("contact_tangential_force_sum", History::value_of(tangential_force_sum));
}

void ContactStatistics::register_pair_history(History& h, const std::string& suffix) const {
  h.add("contact_normal_force" + suffix, History::value_of(normal_force));
  h.add("contact_tangential_force" + suffix, History::value_of(tangential_force));
  h.add("frictional_dissipation" + suffix, History::value_of(dissipation));
  h.add("active_nodes" + suffix, History::value_of(active_nodes));
  h.add("slip_nodes" + suffix, History::value_of(slip_nodes));
  h.add("contact_tangential_force_sum" + suffix, History::value_of(tangential_force_sum));
}

void ContactHeat::register_history(History& h, const std::string& suffix, bool gap) const {
  h.add("heat_generated" + suffix, History::value_of(generated));
  h.add("heat_to_slave" + suffix, History::value_of(to_slave));
  h.add("heat_to_master" + suffix, History::value_of(to_master));
  h.add("heat_conducted" + suffix, History::value_of(conducted));
  if (gap) h.add("heat_gap_conducted" + suffix, History::value_of(gap_conducted));
}

void BoundaryHeat::account_step(double film_power, double radiation_power, double tau) {
  film += tau * film_power;
  radiation += tau * radiation_power;
}

void BoundaryHeat::register_history(History& h) const {
  h.add("heat_film", History::value_of(film));
  h.add("heat_radiation", History::value_of(radiation));
}

}  // namespace tc::physics
