// Simulation::checkpoint and restore: the bodies' states and the run's ledger here, the
// contact's part by ContactCoupling (with its enforcement, time scheme and MultiplierTransfer).
#include "tc/record/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "tc/core/error.hpp"
#include "tc/run/simulation.hpp"

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
    const auto& st = bodies_.states[b];
    const auto& g = bodies_.fields[b]->g_free;
    c.bodies.push_back({st.u.to_std(), st.v.to_std(), st.a.to_std(), st.theta.to_std(),
                        energy_.force(b).to_std(), g.get() ? g.to_std() : std::vector<double>{}});
  }
  contact_.save(c);
  c.row = history_.row();
  c.external_work = energy_.external_work();
  c.total_coupling = total_coupling_;
  c.last_coupling = last_coupling_;
  c.boundary_heat = boundary_heat_;
  return c;
}

void Simulation::restore(const Checkpoint& c) {
  // Copies into the existing vectors (their layout stays): the same bits as the run that wrote
  // the checkpoint, so the steps after it repeat that run's arithmetic exactly.
  if (static_cast<int>(c.bodies.size()) != n_bodies())
    throw Error(fmt::format("checkpoint: {} bodies, this problem {}", c.bodies.size(), n_bodies()));
  if (c.step < 0) throw Error(fmt::format("checkpoint: step {} is negative", c.step));
  if (c.step > problem_.time.n_steps())  // time.end may change on a restart, not before it
    throw Error(fmt::format(
        "checkpoint: written after step {}, beyond the {} steps of time.end = {:g} s; expected "
        "time.end ≥ {:g} s (a restart may extend or shorten a run, not end it before its "
        "checkpoint)",
        c.step, problem_.time.n_steps(), problem_.time.end, c.step * problem_.time.step));
  history_.restore(c.row);
  for (int b = 0; b < n_bodies(); ++b) {
    auto& st = bodies_.states[b];
    const auto& cb = c.bodies[b];
    restore_vector(st.u, cb.u, "u");
    restore_vector(st.v, cb.v, "u̇");
    restore_vector(st.a, cb.a, "ü");
    restore_vector(st.theta, cb.theta, "θ");
    restore_vector(energy_.force(b), cb.force, "the force");
    restore_vector(bodies_.fields[b]->g_free, cb.g_free, "g");
  }
  contact_.restore(c);
  step_ = c.step;
  energy_.set_external_work(c.external_work);
  total_coupling_ = c.total_coupling;
  last_coupling_ = c.last_coupling;
  boundary_heat_ = c.boundary_heat;
}

}  // namespace tc::physics
