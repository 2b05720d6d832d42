// contact_<step>.csv (output.contact_csv): every contact node of every pair at a written step,
// for scripts that want the interface without reading a .vtu; summary.json's "compliance" of
// the contact bodies.
#include <fmt/format.h>

#include <cmath>

#include "tc/io/files/files.hpp"
#include "tc/io/output/output.hpp"
#include "tc/linalg/compliance.hpp"
#include "tc/physics/interface_heat/contact_heat.hpp"

namespace tc::io {

namespace {

/// M x per master component (x interleaved, `components` per master node).
std::vector<double> m_times(const core::SparseMatrix& m, const std::vector<double>& x,
                            int components, int component) {
  std::vector<double> column(static_cast<size_t>(m.cols()));
  for (size_t j = 0; j < column.size(); ++j)
    column[j] = x[static_cast<size_t>(components) * j + static_cast<size_t>(component)];
  core::Vector y(m.rows());
  m.mult(core::Vector::from(column), y);
  return y.to_std();
}

}  // namespace

std::string contact_csv(const physics::Simulation& sim) {
  // Per contact node k of pair q (the slave's node): its current position x = X + u; the gap
  // of the current positions with the mortar of the step, g_k = n_k·((Σ_j M_kj x_j^m)/(D1)_k
  // − x_k) + s_k/(D1)_k, s the step's gap shift (the weighted gap of (2.6) linearised about the
  // predicted configuration, per unit weight: ≥ 0 open, < 0 penetrating); the
  // slave's fields (pair_node_fields); the slave's temperature and the master's at the node
  // as the conduction uses it, (Mθ_m)_k/(D1)_k (physics::master_at_nodes: the mortar
  // projection, which with the dual basis may leave the master's nodal range near the edge of
  // the contact, where ψ_k is negative).
  TextBuffer out;
  out.print(
      "pair,node,x,y,z,gap,pressure,traction_x,traction_y,traction_z,slip_velocity_x,"
      "slip_velocity_y,slip_velocity_z,heat_flux,slave_temperature,master_temperature\n");
  const auto& contact = sim.contact();
  for (int q = 0; q < contact.n_pairs(); ++q) {
    const auto f = pair_node_fields(sim, q);
    if (!f) continue;
    const auto& pr = contact.pair(q);
    const auto& pair = *pr.mortar;
    const int s = pr.settings->slave_body, mb = pr.settings->master_body;
    const int dim = sim.problem().dimension;
    const auto& ms = sim.system(s).body().mesh;
    const auto& mm = sim.system(mb).body().mesh;
    const auto us = sim.state(s).u.to_std(), um = sim.state(mb).u.to_std();
    const auto ts = sim.state(s).theta.to_std();
    std::vector<double> xm(3 * static_cast<size_t>(mm.n_nodes()), 0.0);
    for (int j = 0; j < mm.n_nodes(); ++j)
      for (int k = 0; k < dim; ++k)
        xm[3 * static_cast<size_t>(j) + static_cast<size_t>(k)] =
            mm.point(j)[static_cast<size_t>(k)] + um[static_cast<size_t>(dim * j + k)];
    const auto& m = pair.m_matrix();
    if (m.rows() != static_cast<PetscInt>(f->nodes.size()) || m.cols() != mm.n_nodes()) continue;
    const auto master = physics::master_at_nodes(pair, sim.state(mb).theta);
    const auto& row_sum = master.d_sum;
    std::array<std::vector<double>, 3> mx;
    for (int k = 0; k < 3; ++k) mx[static_cast<size_t>(k)] = m_times(m, xm, 3, k);
    for (size_t k = 0; k < f->nodes.size(); ++k) {
      const int a = f->nodes[k];
      std::array<double, 3> x{0, 0, 0};
      for (int i = 0; i < dim; ++i)
        x[static_cast<size_t>(i)] =
            ms.point(a)[static_cast<size_t>(i)] + us[static_cast<size_t>(dim * a + i)];
      const double w = row_sum[k];
      double gap = 0;
      for (size_t i = 0; i < 3; ++i)
        gap += pair.normals()[k][i] * (w > 0 ? mx[i][k] / w - x[i] : 0.0);
      if (w > 0 && k < pr.gap_shift.size()) gap += pr.gap_shift[k] / w;
      out.print("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", q, a, x[0], x[1], x[2], gap,
                f->pressure[k], f->traction[3 * k], f->traction[3 * k + 1], f->traction[3 * k + 2],
                f->slip_velocity[3 * k], f->slip_velocity[3 * k + 1], f->slip_velocity[3 * k + 2],
                f->heat_flux[k], ts[static_cast<size_t>(a)],
                w > 0 ? master.theta[k] : std::nan(""));
    }
  }
  return std::string(out.view());
}

/// Per contact body, how its compliances (A⁻¹)_TT were grown (linalg::Compliance::path): the
/// mechanical one of the contact dual, the thermal one of the interface heat step; "none" where
/// the run took no column (F by solves or matrix-free, no conductance yet).
std::string compliance_json(const physics::Simulation& sim) {
  const auto* dual = sim.dual_solver();
  const auto* heat =
      sim.contact().enabled() ? sim.contact().heat().interface_heat_solver() : nullptr;
  const auto path = [](const linalg::Compliance& c) {
    return json_string(c.size() > 0 ? c.path() : "none");
  };
  std::string out;
  const auto& members = sim.contact().members();
  for (size_t i = 0; dual && i < members.size(); ++i) {
    const int k = static_cast<int>(i);
    out += fmt::format("{}{}: {{\"mechanics\": {}, \"heat\": {}}}", out.empty() ? "" : ", ",
                       json_string(sim.problem().bodies[static_cast<size_t>(members[i])].name),
                       path(dual->compliance(k)),
                       heat ? path(heat->compliance(k)) : json_string("none"));
  }
  return out;
}

}  // namespace tc::io
