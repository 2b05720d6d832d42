#pragma once
// One quasistatic contact solve of the two steel blocks (sliding_blocks.hpp), each cut into s³
// subdomains, by the two FETI forms: nested (physics::DualContactSolver, the contact dual on
// top of each body's FETI: F = B_c A⁻¹B_cᵀ by whole-body solves) and combined
// (feti::ContactFeti, one dual QP with gluing, Dirichlet and contact multipliers, SMALBE).
// Shared by bench/feti (`combined`) and the tests that compare the two.
//
// The solve: the slave's top pressed down `depth` and dragged `slide` along y in one step
// from the reference configuration, node-to-node rows on the matching faces (targets: the
// gap, zero slip), Tresca bound 𝔉 × the frictionless normal multipliers (a fixed bound, as in
// one iteration of the Coulomb fixed point).
#include <chrono>
#include <memory>

#include "matching_rows.hpp"
#include "sliding_blocks.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/feti/contact_feti.hpp"
#include "tc/mesh/box.hpp"
#include "tc/physics/body/body_system.hpp"

namespace tc::bench {

struct ContactSolution {
  core::Vector u_slave, u_master, lambda;
  double seconds = 0;
};

class TwoBlockFeti {
 public:
  /// n cells per block edge (H/h = n/s), s³ subdomains per body, FETI on `comm`.
  TwoBlockFeti(int n, int s, MPI_Comm comm, double feti_tolerance = 1e-10, double depth = 1e-3,
               double slide = 4e-4)
      : problem_(make_problem(n, s, depth, slide)),
        master_(problem_, 0),
        slave_(problem_, 1),
        master_solver_(make_feti(master_, comm, feti_tolerance)),
        slave_solver_(make_feti(slave_, comm, feti_tolerance)),
        rows_(matching_rows(slave_.body().mesh, master_.body().mesh)),
        b_slave_(slave_.n_u()),
        b_master_(master_.n_u()),
        x_slave_(slave_.n_u()),
        x_master_(master_.n_u()) {
    const double t = problem_.time.end;
    slave_.mechanical_load(t, b_slave_);
    master_.mechanical_load(t, b_master_);
    slave_.prescribe_u(t, x_slave_);
    master_.prescribe_u(t, x_master_);
    const int dim = rows_.dim;
    targets_.assign(static_cast<size_t>(rows_.n_rows()), 0.0);
    for (PetscInt k = 0; k < rows_.n_nodes(); ++k)
      targets_[static_cast<size_t>(dim * k)] = rows_.gap[static_cast<size_t>(k)];
    bound_.assign(static_cast<size_t>(rows_.n_nodes()), 0.0);
  }

  TwoBlockFeti(const TwoBlockFeti&) = delete;  // the systems point into problem_
  TwoBlockFeti& operator=(const TwoBlockFeti&) = delete;

  [[nodiscard]] const contact::ContactRows& rows() const { return rows_; }
  [[nodiscard]] const physics::ConstrainedSolver& slave_solver() const { return slave_solver_; }
  [[nodiscard]] const physics::ConstrainedSolver& master_solver() const { return master_solver_; }
  [[nodiscard]] const feti::Feti& slave_feti() const { return *slave_solver_.feti(); }
  [[nodiscard]] const feti::Feti& master_feti() const { return *master_solver_.feti(); }
  [[nodiscard]] const physics::BodySystem& slave_system() const { return slave_; }
  [[nodiscard]] const physics::BodySystem& master_system() const { return master_; }
  /// ‖K_i u_i + B_iᵀλ − f_i‖∞ over the free dofs of both bodies: the equilibrium of a
  /// solution, independent of the solver that produced it.
  [[nodiscard]] double equilibrium_residual(const ContactSolution& s) const {
    double worst = 0;
    const double t = problem_.time.end;
    for (int i = 0; i < 2; ++i) {
      const auto& sys = i == 0 ? slave_ : master_;
      const auto& u = i == 0 ? s.u_slave : s.u_master;
      core::Vector r(sys.n_u()), f(sys.n_u());
      sys.matrices().stiffness_u.mult(u, r);
      (i == 0 ? rows_.slave : rows_.master).mult_transpose_add(s.lambda, r);
      sys.mechanical_load(t, f);
      r.axpy(-1.0, f);
      auto rv = r.view();
      for (const PetscInt d : sys.u_dirichlet_dofs()) rv[d] = 0;
      for (PetscInt k = 0; k < sys.n_u(); ++k) worst = std::max(worst, std::abs(rv[k]));
    }
    return worst;
  }
  [[nodiscard]] PetscInt n_dofs() const { return slave_.n_u() + master_.n_u(); }
  /// The loads, prescribed values (the Dirichlet dofs of x) and contact targets of the solve.
  [[nodiscard]] const core::Vector& b_slave() const { return b_slave_; }
  [[nodiscard]] const core::Vector& b_master() const { return b_master_; }
  [[nodiscard]] const core::Vector& x_slave() const { return x_slave_; }
  [[nodiscard]] const core::Vector& x_master() const { return x_master_; }
  [[nodiscard]] const std::vector<double>& targets() const { return targets_; }
  /// The Tresca bound per contact node (0 on construction: frictionless).
  void set_friction_bound(std::vector<double> b) { bound_ = std::move(b); }
  [[nodiscard]] const std::vector<double>& friction_bound() const { return bound_; }

  /// The nested form with the solver's default settings (explicit F up to 1500 rows).
  ContactSolution nested(double qp_rtol, qp::QpResult& result,
                         physics::DualContactSettings settings = {}) const {
    const auto t0 = std::chrono::steady_clock::now();
    settings.qp.rtol = qp_rtol;
    settings.qp.max_iterations = 100000;
    physics::DualContactSolver dual(slave_solver_, master_solver_, slave_.n_u(), master_.n_u(),
                                    settings);
    dual.set_rows(copy_rows());
    core::Vector free_s = x_slave_.clone(), free_m = x_master_.clone();
    slave_solver_.solve(b_slave_, free_s);
    master_solver_.solve(b_master_, free_m);
    ContactSolution out{free_s.duplicate(), free_m.duplicate(), core::Vector(rows_.n_rows()), 0};
    result = dual.solve(free_s, free_m, targets_, bound_, out.lambda, out.u_slave, out.u_master);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }

  /// The combined form (the ContactFeti set-up — G and the contact rows on the subdomains —
  /// included in the time; the factorisations are the bodies' FETI's, as in `nested`).
  ContactSolution combined(const feti::ContactFetiOptions& options, qp::SmalbeResult& result,
                           int* applications = nullptr) const {
    const auto t0 = std::chrono::steady_clock::now();
    const feti::ContactFeti cf(slave_feti(), master_feti(), rows_.slave, rows_.master, rows_.dim);
    ContactSolution out{x_slave_.clone(), x_master_.clone(), core::Vector(rows_.n_rows()), 0};
    result = cf.solve(b_slave_, b_master_, targets_, bound_, out.u_slave, out.u_master, out.lambda,
                      options);
    if (applications) *applications = cf.statistics().applications;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }

 public:
  [[nodiscard]] contact::ContactRows copy_rows() const {  // DualContactSolver takes its own
    contact::ContactRows r;
    r.dim = rows_.dim;
    r.slave = rows_.slave.copy();
    r.master = rows_.master.copy();
    r.gap = rows_.gap;
    r.weights = rows_.weights;
    r.nodes = rows_.nodes;
    return r;
  }

 private:
  static physics::Problem make_problem(int n, int s, double depth, double slide) {
    auto p = two_steel_blocks(mesh::make_box(3, {0, 0, -1}, {1, 1, 0}, {n, n, n}),
                              mesh::make_box(3, {0, 0, 0}, {1, 1, 1}, {n, n, n}), 3, s * s * s);
    clamp_and_drag(p, 0.1, depth, p.time.end, slide);
    return p;
  }
  static physics::ConstrainedSolver make_feti(const physics::BodySystem& sys, MPI_Comm comm,
                                              double tolerance) {
    feti::FetiOptions o;
    o.comm = comm;
    o.tolerance = tolerance;
    o.max_iterations = 5000;
    o.preconditioner = feti::Preconditioner::dirichlet;
    return physics::ConstrainedSolver(std::make_unique<feti::Feti>(
        sys.subdomains(), sys.body().mesh.n_nodes(), sys.dim(), sys.u_dirichlet_dofs(),
        feti::Kernel::rigid, feti::Singular::yes,
        [&sys](int s) { return sys.subdomain_matrices(s).stiffness_u.copy(); }, o));
  }

  physics::Problem problem_;
  physics::BodySystem master_, slave_;
  physics::ConstrainedSolver master_solver_, slave_solver_;
  contact::ContactRows rows_;
  core::Vector b_slave_, b_master_, x_slave_, x_master_;
  std::vector<double> targets_, bound_;
};

}  // namespace tc::bench
