#include "tc/physics/interface_heat/interface_laws.hpp"

#include <algorithm>
#include <set>

#include "tc/core/error.hpp"

namespace tc::physics {

InterfaceLaws::InterfaceLaws(const ContactSettings& c)
    : friction_(c.friction),
      gamma_slave_(c.conductance_slave),
      gamma_master_(c.conductance_master),
      conducting_(conducts_somewhere()),
      radiates_(c.heat_conduction && c.gap_conductance &&
                c.gap_conductance->effective_emissivity() > 0) {}

double InterfaceLaws::beta_c(double theta) const {
  const double gs = gamma_slave_(theta), gm = gamma_master_(theta);
  return gs + gm > 0 ? gs * gm / (gs + gm) : 0.0;  // (2.13)
}

double InterfaceLaws::delta_c(double theta) const {
  const double gs = gamma_slave_(theta), gm = gamma_master_(theta);
  return gs + gm > 0 ? gs / (gs + gm) : 0.5;
}

bool InterfaceLaws::conducts_somewhere() const {
  // Both conductances are linear between the union of their table points and constant beyond:
  // both are > 0 somewhere iff they are at one of those points or halfway between two (two
  // linear functions ≥ 0 may each vanish at one end of an interval and both be > 0 inside).
  std::set<double> points(gamma_slave_.temperatures().begin(), gamma_slave_.temperatures().end());
  points.insert(gamma_master_.temperatures().begin(), gamma_master_.temperatures().end());
  std::vector<double> at(points.begin(), points.end());
  if (at.empty()) at.push_back(0.0);  // both constant
  for (size_t i = 0, n = at.size(); i + 1 < n; ++i) at.push_back(0.5 * (at[i] + at[i + 1]));
  return std::any_of(at.begin(), at.end(), [&](double t) { return beta_c(t) > 0; });
}

NodalLaws InterfaceLaws::at(std::span<const double> theta) const {
  NodalLaws out;
  out.frictional = frictional();
  out.conducting = conducting();
  out.friction.reserve(theta.size());
  out.beta_c.reserve(theta.size());
  out.delta_c.reserve(theta.size());
  for (const double t : theta) {
    out.friction.push_back(friction(t));
    out.beta_c.push_back(beta_c(t));
    out.delta_c.push_back(delta_c(t));
  }
  return out;
}

NodalLaws InterfaceLaws::at_interface(const contact::MortarPair* mortar,
                                      const contact::ContactRows& rows,
                                      const core::Vector& theta_slave,
                                      const core::Vector& theta_master) const {
  const auto n = static_cast<size_t>(rows.n_nodes());
  if (!friction_varies() && !conductance_varies())
    return at(std::vector<double>(n, 0.0));  // constants: the temperature plays no part
  if (!mortar || mortar->contact_nodes().size() != n)
    throw Error(
        "interface laws in θ: the interface temperature needs the mortar pair's contact nodes");
  return at(interface_temperature(*mortar, theta_slave, theta_master));
}

std::vector<double> interface_temperature(const contact::MortarPair& mortar,
                                          const core::Vector& theta_slave,
                                          const core::Vector& theta_master) {
  const auto master = master_at_nodes(mortar, theta_master);
  const auto ts = theta_slave.read();
  const auto& nodes = mortar.contact_nodes();
  std::vector<double> theta(nodes.size());
  for (size_t k = 0; k < nodes.size(); ++k) {
    const double s = ts[static_cast<PetscInt>(nodes[k])];
    theta[k] = master.d_sum[k] > 0 ? 0.5 * (s + master.theta[k]) : s;
  }
  return theta;
}

}  // namespace tc::physics
