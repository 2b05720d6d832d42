#include "tc/physics/contact/step/contact_coupling.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "tc/core/error.hpp"
#include "tc/physics/contact/step/contact_loop.hpp"
#include "tc/physics/interface_heat/contact_heat.hpp"

namespace tc::physics {

namespace {
// A face counts as covered whole when its covered integral is within round-off of its area.
constexpr double kFullCover = 1e-9;
}  // namespace

void ContactCoupling::add_pairs() {
  group_ = ContactGroup(problem_);
  pairs_.clear();
  pairs_.resize(problem_.contacts.size());
  for (size_t q = 0; q < pairs_.size(); ++q) {
    auto& pr = pairs_[q];
    const auto& c = problem_.contacts[q];
    pr.settings = &c;
    pr.bodies = group_.pairs[q];
    pr.laws = InterfaceLaws(c);
    // Crosspoints: a node on the slave surfaces of two pairs would carry two multipliers on the
    // same dofs (F singular along their difference, docs/choices.md): the first pair keeps it.
    const auto& mesh = problem_.bodies[c.slave_body].mesh;
    pr.crosspoint.assign(static_cast<size_t>(mesh.n_nodes()), 0);
    for (size_t e = 0; e < q; ++e) {
      const auto& earlier = problem_.contacts[e];
      if (earlier.slave_body != c.slave_body) continue;
      std::vector<char> on(static_cast<size_t>(mesh.n_nodes()), 0);
      for (const int a : mesh.boundary_nodes(earlier.slave_where)) on[a] = 1;
      for (const int a : mesh.boundary_nodes(c.slave_where))
        if (on[a]) pr.crosspoint[a] = 1;
    }
  }
  heat_.set_pairs(pairs_.size());
  heat_.set_treatment(problem_.solver.conductance_treatment);
}

void ContactCoupling::enable(ContactRowsBuilder builder, DualContactSettings settings,
                             const int& step) {
  if (problem_.contacts.empty()) throw Error("enable_contact: the problem has no [contact]");
  if (problem_.contacts.size() != 1)
    throw Error("enable_contact: rows from a builder are for one contact pair");
  pairs_.front().rows = finite_rows(std::move(builder), step);
  method_ = choose_contact_method(problem_, bodies_, std::move(settings), timers_);
  mark_loaded();
}

void ContactCoupling::enable_mortar(DualContactSettings settings, contact::MortarOptions options,
                                    const int& step) {
  if (problem_.contacts.empty()) throw Error("enable_mortar_contact: the problem has no [contact]");
  for (auto& pr : pairs_) {
    const auto& c = *pr.settings;
    {
      auto t = timers_.scope("mortar");
      pr.mortar = std::make_unique<contact::MortarPair>(
          problem_.bodies[c.slave_body].mesh, c.slave_where, problem_.bodies[c.master_body].mesh,
          c.master_where, options);
    }
    auto* mortar = pr.mortar.get();
    pr.rows = finite_rows(
        [mortar](const core::Vector& u_slave, const core::Vector& u_master) {
          mortar->update(u_slave.to_std(), u_master.to_std());
          return mortar->rows();
        },
        step);
  }
  method_ = choose_contact_method(problem_, bodies_, std::move(settings), timers_);
  mark_loaded();
}

void ContactCoupling::mark_loaded() {
  // The case reader allows one loaded component among the contact bodies (a scalar root).
  loaded_ = -1;
  for (size_t i = 0; i < group_.members.size(); ++i)
    if (auto& f = *bodies_.fields[group_.members[i]]; f.coupling) {
      if (loaded_ >= 0 || f.coupling->size() != 1)
        throw Error("load control: one face with one loaded component among the contact bodies");
      if (method_.enforcement->qp_gives_displacements())
        throw Error("load control: not with the combined contact dual");
      f.coupling_in_contact = true;
      loaded_ = static_cast<int>(i);
    }
}

void ContactCoupling::solve_qp(const BodyGroup& g, const TrescaIteration& t,
                               std::span<const double> targets, double rtol, int step, int outer) {
  auto& enforcement = *method_.enforcement;
  if (loaded_ < 0) {
    enforcement.solve_qp(g, {targets, t.bound, rtol, step, outer}, lambda_, stats_);
    return;
  }
  // The face under load control moves by δ = w − w_written from where u_free was solved:
  // d(δ) = d₀ + δ g, g = BΦ, and its balance h = R_free + S δ + gᵀλ − F = 0 (rigid_coupling.hpp).
  // δ is eliminated by a proximal step (the augmented Lagrangian of the balance, the body's
  // stiffness S along Φ regularised by S_r around the last δ_j):
  //   S δ + gᵀλ − e = S_r (δ_j − δ),  e = F − R_free,
  // so each QP is that of F + ggᵀ/(S + S_r) and d₀ + g (e + S_r δ_j)/(S + S_r)
  // (DualContactSolver::set_rank_one), and its λ and δ_{j+1} = (e − gᵀλ + S_r δ_j)/(S + S_r)
  // leave h = S_r (δ_j − δ_{j+1}) exactly. The QP resolves the balance itself, weighted by
  // 1/(S + S_r): a black-box root of h(δ) over QPs stopped at ‖g^P‖ ≤ ε‖d‖ could not (in sliding
  // ‖d‖ is the slip, mm, where the normal rows carry µm: h came out a staircase in δ).
  // S_r = 0 where the body holds the face itself (S > 0, dynamic: one QP, exact); else
  // S_r = 1e-3 e_Dᵀ A e_D: the contraction S_r/(S + S_r + k_c) with the contact's stiffness k_c
  // seen by the face.
  auto& f = *g.fields[loaded_];
  auto& c = *f.coupling;
  auto& dual = enforcement.dual();
  const double time = step * problem_.time.step;
  const double force = c.face(0).force(time);
  const double r_free = c.free_resultant(f.u_prev, f.rhs_u)[0];
  const double e = force - r_free;
  const double s = std::max(c.stiffness()(0, 0), 0.0);  // ΦᵀAΦ ≥ 0 but for round-off
  const double held = 1e-3 * c.face_stiffness(0);
  double s_r = s >= held ? 0.0 : held;
  const auto& bphi = loaded_rows_;
  // To the QP's tolerance, at least 10 qp_tolerance (1e-7 by default), of the forces at play:
  // the final QP's λ resolves its contact force to ~1e-8 of them (examples/09).
  const double tol =
      std::max(rtol, 10 * problem_.solver.qp_tolerance) * (std::abs(force) + std::abs(r_free));
  double delta = c.w()[0] - c.written()[0];
  double h = 0;
  // A loose QP of the friction loop (rtol > qp_tolerance: its forcing terms) resolves λ, and
  // so the balance, no better than its tolerance; a few updates then, the final QP's balance
  // (at qp_tolerance) is the one that must be met.
  const bool final = rtol <= problem_.solver.qp_tolerance;
  const int max_updates = final ? 200 : 8;
  int j = 0;
  for (; j < max_updates; ++j) {
    dual.set_rank_one(bphi, 1.0 / (s + s_r), (e + s_r * delta) / (s + s_r));
    enforcement.solve_qp(g, {targets, t.bound, rtol, step, outer}, lambda_, stats_);
    double gl = 0;
    {
      const auto l = lambda_.read();
      for (size_t r = 0; r < bphi.size(); ++r) gl += bphi[r] * l[static_cast<PetscInt>(r)];
    }
    const double next = (e - gl + s_r * delta) / (s + s_r);
    const double last = h;
    h = s_r * (delta - next);
    delta = next;
    if (std::abs(h) <= tol) break;
    // The QP stops at ‖g^P‖ ≤ ε‖d‖ and sees the imbalance as ‖g‖|h|/(S + S_r): where that fell
    // below its tolerance λ stays and h stalls. A stiffer weight 1/(S + S_r) then (S_r/10):
    // the balance is resolved to S_r ε‖d‖/‖g‖.
    // Down to 1e-6 e_DᵀAe_D: the rank-one term then outweighs F by ~1e6, within what the
    // dense products resolve.
    if (j > 0 && std::abs(h) > 0.5 * std::abs(last)) s_r = std::max(0.1 * s_r, 1e-3 * held);
  }
  dual.clear_rank_one();
  if (j == max_updates && final)
    throw NumericalError(
        fmt::format("load control: the force {:.6g} N on face '{}' was not balanced in {} "
                    "contact QPs (is the body held by the contact in the loaded direction?)",
                    force, c.face(0).label, max_updates),
        step, outer, std::abs(h));
  c.w()[0] = c.written()[0] + delta;
}

void ContactCoupling::shift_loaded_face(const BodyGroup& g) {
  if (loaded_ < 0) return;
  auto& f = *g.fields[loaded_];
  f.coupling->shift_to_w(f.u_new);
}

BodyGroup ContactCoupling::group() {
  return bodies_.group(group_.members);
}

bool ContactCoupling::any_pair(bool (InterfaceLaws::*law)() const) const {
  return std::any_of(pairs_.begin(), pairs_.end(),
                     [&](const auto& pr) { return (pr.laws.*law)(); });
}

double ContactCoupling::traction_per_multiplier() const {
  return method_.scheme ? method_.scheme->traction_per_multiplier()
                        : physics::traction_per_multiplier(false);
}

std::vector<double> ContactCoupling::multipliers() const {
  return lambda_.get() ? lambda_.to_std() : std::vector<double>{};
}

std::vector<double> ContactCoupling::nodes_of(std::span<const double> v, int dim, PetscInt from,
                                              PetscInt to) {
  if (static_cast<PetscInt>(v.size()) < dim * to) return {};
  return {v.begin() + dim * from, v.begin() + dim * to};
}

std::vector<double> ContactCoupling::multipliers(int q) const {
  if (lambda_at_.size() < pairs_.size() + 1) return {};
  return nodes_of(multipliers(), problem_.dimension, lambda_at_[q], lambda_at_[q + 1]);
}

void ContactCoupling::add_multiplier_load(int body, core::Vector& r) const {
  if (!enabled()) return;
  const auto& dual = method_.enforcement->dual();
  const int dim = dual.dim();
  if (dual.n_pairs() == 0 || lambda_.size() != dual.n_rows()) return;  // before the first step
  const auto l = lambda_.to_std();
  const double unit = traction_per_multiplier();
  for (int q = 0; q < dual.n_pairs(); ++q) {
    const auto& rows = dual.pair_rows(q);
    const auto& pb = dual.pair_bodies()[static_cast<size_t>(q)];
    const bool slave = group_.members[static_cast<size_t>(pb.slave)] == body;
    const bool master = group_.members[static_cast<size_t>(pb.master)] == body;
    if (!slave && !master) continue;
    auto lq = core::Vector::from(nodes_of(l, dim, dual.pair_offset(q), dual.pair_offset(q + 1)));
    lq.scale(unit);
    (slave ? rows.slave : rows.master).mult_transpose_add(lq, r);
  }
}

std::vector<double> ContactCoupling::heat_flux() const {
  std::vector<double> all;
  for (const auto& pr : pairs_) all.insert(all.end(), pr.heat_flux.begin(), pr.heat_flux.end());
  return all;
}

std::vector<double> ContactCoupling::slip(int q) const {
  if (lambda_at_.size() < pairs_.size() + 1) return {};
  return nodes_of(slip_, problem_.dimension, lambda_at_[q], lambda_at_[q + 1]);
}

void ContactCoupling::interface_laws() {
  // 𝔉, β_C, δ_C at the interface temperature of the last iterate (θ^k at the first): fixed
  // for this coupling iteration's heat step and Tresca QPs (interface_laws.hpp).
  auto g = group();
  const auto& dual = method_.enforcement->dual();
  nodal_laws_ = {};
  for (int q = 0; q < n_pairs(); ++q) {
    auto& pr = pairs_[q];
    pr.nodal = pr.laws.at_interface(pr.mortar.get(), dual.pair_rows(q),
                                    g.fields[pr.bodies.slave]->theta_new,
                                    g.fields[pr.bodies.master]->theta_new);
    auto& all = nodal_laws_;
    for (auto [to, from] : {std::pair{&all.friction, &pr.nodal.friction},
                            {&all.beta_c, &pr.nodal.beta_c},
                            {&all.delta_c, &pr.nodal.delta_c}})
      to->insert(to->end(), from->begin(), from->end());
    all.frictional = all.frictional || pr.nodal.frictional;
    all.conducting = all.conducting || pr.nodal.conducting;
  }
}

void ContactCoupling::heat_step(int step, int iteration) {
  // (4.3) for the bodies of the contact pairs, backward Euler:
  //   (M_θ/τ + K_θ) θ + Σ L_θγ θ = rhs + Σ d_θγ(u̇)   (ContactHeatCoupling::heat_step),
  // rhs with the thermoelastic term of each body.
  auto scope = timers_.scope("heat_solve");
  auto g = group();
  const auto& dual = method_.enforcement->dual();
  for (const int b : group_.members) steps_.heat_rhs(b);
  const auto lambda = lambda_.to_std();
  const double unit = traction_per_multiplier();
  const int dim = dual.dim();
  std::vector<ContactIterate> iterates;
  for (int q = 0; q < n_pairs(); ++q) {
    const auto& pr = pairs_[q];
    const auto from = static_cast<size_t>(dim * dual.pair_offset(q));
    const auto to = static_cast<size_t>(dim * dual.pair_offset(q + 1));
    iterates.push_back({*pr.settings, pr.bodies, pr.mortar.get(), dual.pair_rows(q),
                        std::span(lambda).subspan(from, to - from), unit,
                        iterate_slip_.empty()
                            ? std::span<const double>()
                            : std::span<const double>(iterate_slip_).subspan(from, to - from),
                        pr.nodal});
  }
  heat_.heat_step(problem_, g, iterates, step * problem_.time.step, step, iteration);
  for (const auto* f : g.fields) require_finite(f->theta_new, "temperature", step, iteration);
}

double ContactCoupling::mech_step(TrescaIteration& t, std::span<const double> targets, int step,
                                  int outer, int max_updates) {
  // The mechanical half of (6.3) at the θ of this iteration: u_free is fixed, so each update
  // of γ costs one QP with the same F and no solve. Nested, the heat–mechanics iterations
  // are left with the thermal coupling alone (docs/choices.md, "friction loop").
  auto scope = timers_.scope("qp");
  const auto& s = problem_.solver;
  const auto g = group();
  auto& enforcement = *method_.enforcement;
  for (auto* f : g.fields) f->u_prev.copy_from(f->u_new);  // u_free, the QP's data
  const CoulombFixedPoint fp{.dim = enforcement.dual().dim(),
                             .friction = nodal_laws_.friction,
                             .frictional = nodal_laws_.frictional,
                             .tolerance = s.coupling_tolerance,
                             .qp_tolerance = s.qp_tolerance,
                             .qp_forcing = s.friction.qp_forcing,
                             .qp_forcing_cap = s.friction.qp_forcing_cap,
                             .loop_forcing = s.friction.loop_forcing,
                             .max_updates = max_updates,
                             .step = step,
                             .outer = outer};
  const double residual = coulomb_fixed_point(t, lambda_, fp, [&](double rtol) {
    solve_qp(g, t, targets, rtol, step, outer);
    require_finite(lambda_, "contact multiplier", step, outer);
  });
  enforcement.finish_qps(g, lambda_, t, iterate_slip_, step, outer);
  if (loaded_ >= 0) {
    auto& c = *g.fields[loaded_]->coupling;
    if (t.defer) {  // u_new stays u_free at the written w until the end of the step: B u moved
      const double dw = c.w()[0] - c.written()[0];  // by (w − written)BΦ
      for (size_t r = 0; r < iterate_slip_.size(); ++r) iterate_slip_[r] += dw * loaded_rows_[r];
    } else {
      shift_loaded_face(g);
    }
  }
  return residual;
}

std::vector<std::vector<double>> ContactCoupling::predicted_gaps(const BodyGroup& g) {
  // The gap length g_k/w_k of each slave node in the configuration u^k + τu̇^k the step is
  // heading for, where the master covers every face of the node there (NaN elsewhere); empty
  // for a pair at rest or with a test's rows. Leaves the mortar pair at u_p: pr.rows must come
  // after.
  const double tau = problem_.time.step;
  std::vector<std::vector<double>> gaps(pairs_.size());
  for (size_t q = 0; q < pairs_.size(); ++q) {
    auto& pr = pairs_[q];
    const auto* s = g.states[pr.bodies.slave];
    const auto* m = g.states[pr.bodies.master];
    if (!pr.mortar || (s->v.max_abs() == 0 && m->v.max_abs() == 0)) continue;
    auto us = s->u.clone(), um = m->u.clone();
    us.axpy(tau, s->v);
    um.axpy(tau, m->v);
    pr.mortar->update(us.to_std(), um.to_std());
    const auto& nodes = pr.mortar->contact_nodes();
    gaps[q].assign(static_cast<size_t>(problem_.bodies[pr.settings->slave_body].mesh.n_nodes()),
                   std::numeric_limits<double>::quiet_NaN());
    for (size_t k = 0; k < nodes.size(); ++k)
      if (pr.mortar->coverage()[k] >= 1 - kFullCover)
        gaps[q][static_cast<size_t>(nodes[k])] = pr.mortar->gap()[k] / pr.mortar->weights()[k];
  }
  return gaps;
}

void ContactCoupling::shift_to_prediction(const BodyGroup& g,
                                          const std::vector<std::vector<double>>& predicted) {
  // (2.6) linearised about u^k with the rows B(u^k), g(u) ≈ g(u^k) − B(u − u^k), keeps the
  // master points each slave node projects to at t^k: a slide s of the step along the master
  // reads as the gap change −w n_k·s wherever the slave's nodal normal n_k is not the master's.
  // Landing a node off the master by Vτ n_k·t turns the slave's surface there, which tilts the
  // normals of the next step: an explicit advection of the surface's shape with a Courant
  // number V τ/h_s of the slave's cell h_s, which grows once the slide of a step exceeds a slave
  // cell (docs/theory.md, "Sliding: the gap's linearisation"). Linearised instead about the
  // predicted u_p = u^k + τu̇^k with the gap measured there, g(u) ≈ w ĝ(u_p) − B(u − u_p):
  // c_n gains w_k ĝ_k(u_p) − g_k(u^k) + τ(B u̇^k)_n,k, and what is left is the slide's change
  // from the last step, n_k·(s − τ t·u̇^k).
  auto& dual = method_.enforcement->dual();
  const int dim = dual.dim();
  const double tau = problem_.time.step;
  std::vector<double> shift(static_cast<size_t>(dual.n_nodes()), 0.0);
  bool any = false;
  for (int q = 0; q < n_pairs(); ++q) {
    auto& pr = pairs_[q];
    const auto& rows = dual.pair_rows(q);
    pr.gap_shift.assign(rows.nodes.size(), 0.0);
    if (predicted[q].empty()) continue;
    core::Vector bv(rows.n_rows());
    rows.slave.mult(g.states[pr.bodies.slave]->v, bv);
    rows.master.mult_add(g.states[pr.bodies.master]->v, bv);
    const auto b = bv.to_std();
    for (size_t k = 0; k < rows.nodes.size(); ++k) {
      const double gp = predicted[q][static_cast<size_t>(rows.nodes[k])];
      // At the edge of the overlap (at u^k or u_p) ψ_k is built on the covered part and moves
      // with it: w_k ĝ_k(u_p) would weigh another part of the surface than the rows do (measured
      // on tests/cases/restart/sliding-2d.toml: 2.5 times the end-of-step gap of the rows' own
      // linearisation at the node the master slides off). There the rows' linearisation stays.
      if (!std::isfinite(gp) || pr.mortar->coverage()[k] < 1 - kFullCover) continue;
      pr.gap_shift[k] = rows.weights[k] * gp - rows.gap[k] + tau * b[dim * k];
      shift[static_cast<size_t>(dual.pair_offset(q)) + k] = pr.gap_shift[k];
      any = true;
    }
  }
  if (any) dual.shift_gaps(shift);
}

void ContactCoupling::set_rows(BodyGroup& g) {
  auto& enforcement = *method_.enforcement;
  {
    std::vector<ContactRows> rows;
    std::vector<std::vector<double>> predicted;
    {
      auto scope = timers_.scope("mortar");
      predicted = predicted_gaps(g);
      for (const auto& pr : pairs_)
        rows.push_back(pr.rows(g.states[pr.bodies.slave]->u, g.states[pr.bodies.master]->u));
    }
    auto scope = timers_.scope("dual_setup");  // F formed explicitly here when it is small
    enforcement.set_rows(std::move(rows), group_.pairs);
    shift_to_prediction(g, predicted);
  }
  auto& dual = enforcement.dual();
  const int dim = dual.dim();
  // λ of the last step on these rows, pair by pair (each pair's nodes where they were; one pair
  // without the last step's node counts, from a test's rows: all of λ, by position).
  const auto previous = multipliers();
  const bool known = lambda_at_.size() == pairs_.size() + 1;
  std::vector<double> next;
  for (int q = 0; q < n_pairs(); ++q) {
    auto& pr = pairs_[q];
    core::Vector lq;
    if (known)
      lq = core::Vector::from(nodes_of(previous, dim, lambda_at_[q], lambda_at_[q + 1]));
    else if (n_pairs() == 1 && !previous.empty())
      lq = core::Vector::from(previous);
    pr.transfer.warm_start(dual.pair_rows(q), pr.mortar.get(), lq);
    const auto v = lq.to_std();
    next.insert(next.end(), v.begin(), v.end());
  }
  lambda_ = core::Vector::from(next);
  lambda_at_.clear();
  for (int q = 0; q <= n_pairs(); ++q) lambda_at_.push_back(dual.pair_offset(q));
  // Crosspoints: a later pair's multipliers held at 0 (λ_n ∈ [0, 0], no friction) where an
  // earlier pair with the same slave body has the node too and their normals there are less than
  // 60° apart (docs/choices.md, "Crosspoints"): the two rows would be (nearly) dependent.
  std::vector<char> held(static_cast<size_t>(dual.n_nodes()), 0);
  bool any = false;
  for (int q = 1; q < n_pairs(); ++q) {
    const auto& pr = pairs_[q];
    const auto& nodes = dual.pair_rows(q).nodes;
    for (size_t k = 0; k < nodes.size(); ++k) {
      if (!pr.crosspoint[nodes[k]]) continue;
      bool hold = !pr.mortar;  // a test's rows: no normals to compare
      for (int e = 0; e < q && !hold; ++e) {
        const auto& earlier = pairs_[e];
        if (earlier.settings->slave_body != pr.settings->slave_body || !earlier.mortar) continue;
        const int at = earlier.mortar->contact_index(nodes[k]);
        if (at < 0) continue;
        const auto& a = earlier.mortar->normals()[at];
        const auto& b = pr.mortar->normals()[k];
        hold = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] >= 0.5;
      }
      if (hold) {
        held[static_cast<size_t>(dual.pair_offset(q)) + k] = 1;
        any = true;
      }
    }
  }
  if (any) {
    dual.hold_at_zero(std::move(held));
    auto lv = lambda_.view();
    for (PetscInt k = 0; k < dual.n_nodes(); ++k)
      if (dual.held_at_zero(k))
        for (int i = 0; i < dim; ++i) lv[dim * k + i] = 0;
  }
}

void ContactCoupling::refactorised(int body) {
  const auto& m = group_.members;
  const auto it = std::find(m.begin(), m.end(), body);
  if (it == m.end() || !enabled()) return;
  method_.enforcement->dual().refactorised(static_cast<int>(it - m.begin()));
}

int ContactCoupling::couple(int step) {
  step_of_last_couple_ = step;
  auto g = group();
  auto& enforcement = *method_.enforcement;
  stats_.qp_iterations = 0;
  stats_.operator_applications = 0;
  stats_.friction_iterations = 0;
  for (const auto* f : g.fields)  // the FETI misfit of this step's solves (check_laws)
    if (f->mech && f->mech->feti()) f->mech->feti()->clear_peak_residual();
  set_rows(g);
  auto& dual = enforcement.dual();
  const int dim = dual.dim();
  if (loaded_ >= 0) {  // BΦ of the loaded face on this step's rows
    // The root's first guess is the face's w of t^k, and its first slope the face's own
    // stiffness: both from the state, so a restarted run takes the same QPs.
    auto& c = *g.fields[loaded_]->coupling;
    c.w()[0] = g.states[loaded_]->u.read()[c.face(0).dofs.front()];
    std::vector<core::Vector> zero;
    std::vector<const core::Vector*> phi;
    for (int i = 0; i < g.size(); ++i) zero.emplace_back(g.systems[i]->n_u());
    for (int i = 0; i < g.size(); ++i)
      phi.push_back(i == loaded_ ? &g.fields[i]->coupling->lifting(0) : &zero[i]);
    loaded_rows_ = dual.row_values(phi);
  }
  method_.scheme->prepare(g, dual, lambda_, stats_, step);
  method_.scheme->slip_reference(g);  // into work_u
  const auto targets = dual.targets(g.state(&BodyState::u), g.field_in(&BodyField::work_u));

  ContactLoopPhysics physics{.qp_gives_displacements = enforcement.qp_gives_displacements(),
                             .frictional = any_pair(&InterfaceLaws::frictional),
                             .friction_varies = any_pair(&InterfaceLaws::friction_varies),
                             // θ iterates itself when the conductance is lagged or depends on θ
                             // (then the heat step with the final λ is not the last one needed).
                             .theta_iterates = heat_.treatment() == ConductanceTreatment::lagged ||
                                               any_pair(&InterfaceLaws::conductance_varies) ||
                                               any_pair(&InterfaceLaws::gap_radiates)};
  for (const auto* f : g.fields) {
    physics.heating = physics.heating || f->heating;
    physics.expansion = physics.expansion || f->expansion;
  }
  const auto policy = choose_contact_loop(problem_.solver, physics);
  const bool nested = policy.friction == FrictionPlacement::nested;
  TrescaIteration tresca;
  tresca.relaxation = policy.relaxation;
  tresca.defer = policy.feedback == DisplacementFeedback::deferred;
  tresca.cut_short = policy.cut_short;
  iterate_slip_.clear();
  if (tresca.defer) tresca.bu_old = dual.row_values(g.state(&BodyState::u));
  // An application of F is a solve per body: the set-up's solves in those units.
  stats_.operator_applications += dual.setup_solves() / g.size();
  core::Vector lambda_prev = lambda_.clone();
  const double tol = problem_.solver.coupling_tolerance;
  const auto norm = [&](core::Vector BodyField::*v) {  // ‖·‖ over the group, as one vector
    double sq = 0;
    for (const auto* f : g.fields) sq = std::hypot(sq, (f->*v).norm());
    return sq;
  };
  const auto mechanical_half = [&](int iteration) {  // u_free, then the Coulomb QPs: residual
    switch (policy.feedback) {
      case DisplacementFeedback::from_qp: {  // the loads only: the QP solves for u itself
        auto scope = timers_.scope("mechanical_solve");
        for (const int b : group_.members) steps_.mech_load(b, step);
        break;
      }
      case DisplacementFeedback::deferred:  // u_free = A⁻¹f with the Dirichlet data
        for (const int b : group_.members) steps_.mech_step(b, step, iteration);
        break;
      case DisplacementFeedback::per_iterate: {
        // The same, as a solve the recovery corrects (solve_free): finish_qps recovers u at once.
        auto scope = timers_.scope("mechanical_solve");
        for (int i = 0; i < g.size(); ++i) {
          steps_.mech_load(group_.members[static_cast<size_t>(i)], step);
          auto& f = *g.fields[i];
          enforcement.dual().solve_free(i, f.rhs_u, f.u_new, lambda_);
          require_finite(f.u_new, "displacement", step, iteration);
        }
        break;
      }
    }
    // Nested: γ = λ_n(γ) to convergence at this θ, Aitken restarted (the map changed with θ);
    // staggered: one update, the relaxation carried over the heat–mechanics iterations.
    if (nested || tresca.gamma.empty()) tresca.restart(lambda_, dim, nodal_laws_.friction);
    return mech_step(tresca, targets, step, iteration, policy.max_updates(problem_.solver));
  };
  const StaggeredSweep sweep{
      .begin =
          [&](SweepState& st) {
            lambda_prev.copy_from(lambda_);
            interface_laws();
            st.inner_converged = tresca.converged;  // of the last mechanical half
          },
      .heat =
          [&](SweepState& st) {  // θ^{p+1} and ‖θ^{p+1} − θ^p‖
            for (auto* f : g.fields) f->theta_prev.copy_from(f->theta_new);
            heat_step(step, st.iteration);
            for (auto* f : g.fields) f->theta_prev.axpy(-1.0, f->theta_new);
            st.theta = {norm(&BodyField::theta_prev), norm(&BodyField::theta_new)};
          },
      .mechanics =
          [&](SweepState& st) {
            st.residual.difference = mechanical_half(st.iteration);
            st.inner_converged = tresca.converged;
          },
      .end =
          [&](SweepState& st) {
            lambda_prev.axpy(-1.0, lambda_);
            st.primal = {lambda_prev.norm(), lambda_.norm()};
            st.residual.norm = st.primal.norm;  // the fixed point's residual is relative to ‖λ‖
          }};
  const auto result = policy.loop(problem_.solver).run(sweep);
  if (!result.converged)
    throw NumericalError(
        fmt::format("the staggered fixed point (6.3) with contact did not converge to {:.1e} in {} "
                    "iterations: raise [solver] max_coupling_iterations (now {})",
                    tol, problem_.solver.max_coupling_iterations,
                    problem_.solver.max_coupling_iterations),
        step, result.iterations, result.change);
  finish_step(g, tresca, targets, step, result.iterations);
  return result.iterations;
}

}  // namespace tc::physics
