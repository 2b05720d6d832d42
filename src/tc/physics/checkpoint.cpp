// Simulation::checkpoint and restore: each component's part of the restart record
// (checkpoint.hpp), copied out and back into the existing vectors.
#include "tc/physics/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "tc/core/error.hpp"
#include "tc/physics/simulation.hpp"

namespace tc::physics {

namespace {

/// Copies x into v (its layout stays); throws Error when the sizes differ. An absent vector
/// and an empty record match (a part the run does not use).
void restore_vector(core::Vector& v, const std::vector<double>& x, const char* what) {
  if (!v.get() && x.empty()) return;
  if (!v.get() || static_cast<size_t>(v.size()) != x.size())
    throw Error(fmt::format("checkpoint: {} has {} entries, this problem {}", what, x.size(),
                            v.get() ? v.size() : 0));
  auto view = v.view();
  std::copy(x.begin(), x.end(), view.span().begin());
}

}  // namespace

Checkpoint Simulation::checkpoint() const {
  Checkpoint c;
  c.step = step_;
  for (int b = 0; b < n_bodies(); ++b) {
    const auto& st = states_[b];
    const auto& g = solvers_[b]->g_free;
    c.bodies.push_back({st.u.to_std(), st.v.to_std(), st.a.to_std(), st.theta.to_std(),
                        forces_[b].to_std(), g.get() ? g.to_std() : std::vector<double>{}});
  }
  c.lambda = contact_multipliers();
  transfer_.save(c);
  const DualContactSolver* duals[2] = {dual_.get(), stabiliser_.get()};
  for (int d = 0; d < 2; ++d)
    if (duals[d])
      duals[d]->save_compliance(std::span<std::vector<int>, 4>(&c.compliance[4 * d], 4));
  c.slip = slip_;
  c.heat_flux = heat_flux_;
  c.row = history_.row();
  c.external_work = external_work_;
  c.total_coupling = total_coupling_;
  c.total_qp = total_qp_;
  c.total_applications = total_applications_;
  c.last_coupling = last_coupling_;
  c.feti_body_lambda.assign(feti_state_.body.data(),
                            feti_state_.body.data() + feti_state_.body.size());
  c.feti_mu.assign(feti_state_.mu.data(), feti_state_.mu.data() + feti_state_.mu.size());
  c.total_smalbe_outer = total_smalbe_outer_;
  c.contact = contact_stats_;
  c.heat = heat_coupling_.heat();
  c.boundary_heat = boundary_heat_;
  return c;
}

void Simulation::restore(const Checkpoint& c) {
  // Copies into the existing vectors (their layout stays): the same bits as the run that wrote
  // the checkpoint, so the steps after it repeat that run's arithmetic exactly.
  if (static_cast<int>(c.bodies.size()) != n_bodies())
    throw Error(fmt::format("checkpoint: {} bodies, this problem {}", c.bodies.size(), n_bodies()));
  if (c.step < 0 || c.step > problem_.time.n_steps())
    throw Error(fmt::format("checkpoint: step {} outside 0…{}", c.step, problem_.time.n_steps()));
  history_.restore(c.row);
  for (int b = 0; b < n_bodies(); ++b) {
    auto& st = states_[b];
    const auto& cb = c.bodies[b];
    restore_vector(st.u, cb.u, "u");
    restore_vector(st.v, cb.v, "u̇");
    restore_vector(st.a, cb.a, "ü");
    restore_vector(st.theta, cb.theta, "θ");
    restore_vector(forces_[b], cb.force, "the force");
    restore_vector(solvers_[b]->g_free, cb.g_free, "g");
  }
  if (c.lambda.size() != c.lambda_nodes.size() * static_cast<size_t>(problem_.dimension) &&
      !c.lambda_nodes.empty())
    throw Error("checkpoint: the multipliers do not match their contact nodes");
  lambda_ = c.lambda.empty() ? core::Vector() : core::Vector::from(c.lambda);
  transfer_.restore(c);
  DualContactSolver* duals[2] = {dual_.get(), stabiliser_.get()};
  for (int d = 0; d < 2; ++d)
    if (duals[d])
      duals[d]->replay_compliance(std::span<const std::vector<int>, 4>(&c.compliance[4 * d], 4));
  slip_ = c.slip;
  heat_flux_ = c.heat_flux;
  step_ = c.step;
  external_work_ = c.external_work;
  total_coupling_ = c.total_coupling;
  total_qp_ = c.total_qp;
  total_applications_ = c.total_applications;
  last_coupling_ = c.last_coupling;
  feti_state_.body = Eigen::Map<const Eigen::VectorXd>(
      c.feti_body_lambda.data(), static_cast<Eigen::Index>(c.feti_body_lambda.size()));
  feti_state_.mu = Eigen::Map<const Eigen::VectorXd>(c.feti_mu.data(),
                                                     static_cast<Eigen::Index>(c.feti_mu.size()));
  total_smalbe_outer_ = c.total_smalbe_outer;
  contact_stats_ = c.contact;
  heat_coupling_.heat() = c.heat;
  boundary_heat_ = c.boundary_heat;
}

}  // namespace tc::physics
