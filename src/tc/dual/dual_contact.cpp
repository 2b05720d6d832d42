#include "tc/dual/dual_contact.hpp"

#include <algorithm>
#include <utility>

#include "tc/core/error.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/core/verify.hpp"

namespace tc::physics {

const char* name(DualOperator k) {
  return k == DualOperator::explicit_schur ? "explicit" : "matrix-free";
}

DualContactSolver::DualContactSolver(std::vector<const ConstrainedSolver*> bodies,
                                     std::vector<PetscInt> n_u, DualContactSettings settings)
    : bodies_(std::move(bodies)), settings_(std::move(settings)) {
  TC_VERIFY(bodies_.size() == n_u.size(), "one dof count per body");
  // S's rows dealt over the ranks when every body's factor is (all or none: F is then summed
  // over the ranks, each rank's part from its rows of every S).
  const bool over_ranks = std::all_of(bodies_.begin(), bodies_.end(),
                                      [](const auto* b) { return b->unit_rows_at_once(); });
  for (int i = 0; i < n_bodies(); ++i) {
    compliance_.push_back(bodies_[i]->compliance(n_u[i], over_ranks));
    w_in_.emplace_back(n_u[i]);
    y_.emplace_back(n_u[i]);
  }
  corrected_.resize(bodies_.size());
  used_.resize(bodies_.size());
  kept_.resize(bodies_.size());
  used_row_.resize(bodies_.size());
  w_bands_.resize(bodies_.size());
}

DualContactSolver::DualContactSolver(const ConstrainedSolver& slave,
                                     const ConstrainedSolver& master, PetscInt n_u_slave,
                                     PetscInt n_u_master, DualContactSettings settings)
    : DualContactSolver({&slave, &master}, {n_u_slave, n_u_master}, std::move(settings)) {}

void DualContactSolver::refactorised(int i) {
  const bool over_ranks = std::all_of(bodies_.begin(), bodies_.end(),
                                      [](const auto* b) { return b->unit_rows_at_once(); });
  const auto k = static_cast<size_t>(i);
  const PetscInt n = compliance_[k]->n_dofs();
  compliance_[k].reset();
  compliance_[k] = bodies_[k]->compliance(n, over_ranks);
  corrected_[k] = {};
}

void DualContactSolver::apply_f(const core::Vector& x, core::Vector& y) const {
  for (int i = 0; i < n_bodies(); ++i) {
    b_[i].mult_transpose(x, w_in_[i]);
    y_[i].zero();  // zero Dirichlet values: A⁻¹ of the constrained operator
    bodies_[i]->solve(w_in_[i], y_[i]);
    if (i == 0)
      b_[i].mult(y_[i], y);
    else
      b_[i].mult_add(y_[i], y);
  }
}

void DualContactSolver::set_rows(ContactRows rows) {
  std::vector<ContactRows> one;
  one.push_back(std::move(rows));
  set_rows(std::move(one), {{0, 1}});
}

void DualContactSolver::set_rows(std::vector<ContactRows> pairs, std::vector<PairBodies> bodies) {
  TC_VERIFY(pairs.size() == bodies.size() && !pairs.empty(), "one body pair per row block");
  pairs_ = std::move(pairs);
  pair_bodies_ = std::move(bodies);
  clear_rank_one();
  stack_rows();
  held_.clear();
  const PetscInt m = n_rows();
  setup_solves_ = 0;
  kind_ = DualOperator::matrix_free;
  // Explicit up to explicit_limit rows (from the compliance, else by solves), and up to
  // covered_limit while the compliance covers the rows.
  const bool small = m > 0 && m <= settings_.explicit_limit;
  if (small || (m > 0 && settings_.explicit_limit > 0 && m <= settings_.covered_limit)) {
    if (settings_.compliance_limit > 0 && form_from_compliance())
      kind_ = DualOperator::explicit_schur;
    else if (small) {
      form_by_solves();
      kind_ = DualOperator::explicit_schur;
    }
    if (kind_ == DualOperator::explicit_schur && settings_.scale) form_scaled();
  }
  if (kind_ == DualOperator::explicit_schur || m != lambda_max_rows_) lambda_max_ = 0;
}

void DualContactSolver::stack_rows() {
  // B_i = the rows of every pair stacked, with pair p's slave (master) columns in B_i when body
  // i is its slave (master) and zero rows otherwise. One pair: B_s and B_m themselves (shared,
  // not copied), so the single-pair arithmetic is what it was.
  dim_ = pairs_.front().dim;
  offsets_.assign(1, 0);
  gap_.clear();
  for (const auto& r : pairs_) {
    TC_VERIFY(r.dim == dim_ && r.slave.rows() == r.n_rows() && r.master.rows() == r.n_rows(),
              "the pair's rows have the solver's dimension");
    offsets_.push_back(offsets_.back() + r.n_nodes());
    gap_.insert(gap_.end(), r.gap.begin(), r.gap.end());
  }
  b_.clear();
  b_.resize(bodies_.size());
  std::vector<std::vector<std::pair<int, const core::SparseMatrix*>>> parts(bodies_.size());
  for (int p = 0; p < n_pairs(); ++p) {
    parts[pair_bodies_[p].slave].emplace_back(p, &pairs_[p].slave);
    parts[pair_bodies_[p].master].emplace_back(p, &pairs_[p].master);
  }
  const PetscInt m = n_rows();
  for (int i = 0; i < n_bodies(); ++i) {
    if (parts[i].size() == 1 && m == parts[i].front().second->rows()) {
      b_[i] = parts[i].front().second->share();
      continue;
    }
    const PetscInt n = compliance_[i]->n_dofs();
    std::vector<PetscInt> nnz(static_cast<size_t>(m), 0);
    for (const auto& [p, part] : parts[i])
      for (PetscInt r = 0; r < part->rows(); ++r) {
        PetscInt nz = 0;
        TC_PETSC(MatGetRow(part->get(), r, &nz, nullptr, nullptr));
        nnz[static_cast<size_t>(dim_ * offsets_[p] + r)] = nz;
        TC_PETSC(MatRestoreRow(part->get(), r, &nz, nullptr, nullptr));
      }
    b_[i] = core::SparseMatrix(m, n, nnz);
    for (const auto& [p, part] : parts[i])
      for (PetscInt r = 0; r < part->rows(); ++r) {
        PetscInt nz = 0;
        const PetscInt* cols = nullptr;
        const PetscScalar* vals = nullptr;
        TC_PETSC(MatGetRow(part->get(), r, &nz, &cols, &vals));
        const PetscInt row = dim_ * offsets_[p] + r;
        b_[i].add_values(std::span(&row, 1), std::span(cols, static_cast<size_t>(nz)), vals);
        TC_PETSC(MatRestoreRow(part->get(), r, &nz, &cols, &vals));
      }
    b_[i].assemble();
  }
}

std::vector<double> DualContactSolver::row_values(BodyVectors u) const {
  core::Vector bu(n_rows());
  for (int i = 0; i < n_bodies(); ++i)
    if (i == 0)
      b_[i].mult(*u[i], bu);
    else
      b_[i].mult_add(*u[i], bu);
  return bu.to_std();
}

std::vector<double> DualContactSolver::targets(BodyVectors ref, BodyVectors slip) const {
  const auto nv = row_values(ref);
  const auto sv = row_values(slip);
  std::vector<double> c(static_cast<size_t>(n_rows()));
  const int dim = dim_;
  for (PetscInt k = 0; k < n_nodes(); ++k) {
    c[dim * k] = gap_[k] + nv[dim * k];
    for (int l = 1; l < dim; ++l) c[dim * k + l] = sv[dim * k + l];
  }
  return c;
}

void DualContactSolver::shift_gaps(std::span<const double> shift) {
  TC_VERIFY(shift.size() == gap_.size(), "one gap shift per contact node");
  for (size_t k = 0; k < gap_.size(); ++k) gap_[k] += shift[k];
}

qp::QpResult DualContactSolver::solve(BodyVectors u_free, std::span<const double> c,
                                      std::span<const double> friction_bound, core::Vector& lambda,
                                      BodyVectorsOut u, bool recover, double rtol) {
  const PetscInt m = n_rows();
  const int dim = dim_;
  for (int i = 0; i < n_bodies(); ++i) u[i]->copy_from(*u_free[i]);
  if (m == 0) {
    qp::QpResult none;
    none.status = qp::QpStatus::converged;
    return none;
  }

  // d = B u_free − c.
  core::Vector d(m);
  for (int i = 0; i < n_bodies(); ++i)
    if (i == 0)
      b_[i].mult(*u_free[i], d);
    else
      b_[i].mult_add(*u_free[i], d);
  const bool rank_one = !rank_one_g_.empty();
  {
    auto dv = d.view();
    for (PetscInt i = 0; i < m; ++i) dv[i] -= c[i];
    if (rank_one)
      for (PetscInt i = 0; i < m; ++i) dv[i] += rank_one_shift_ * rank_one_g_[i];
  }
  // With Σ: the QP in μ = Σ⁻¹λ, min ½μᵀ(ΣFΣ)μ − μᵀΣd over μ_n ≥ 0, ‖μ_τ‖ ≤ 𝔉γ/σ_τ.
  const bool scaled = kind_ == DualOperator::explicit_schur && settings_.scale;
  const auto sigma = [&](PetscInt i) { return scaled ? sigma_[i] : 1.0; };
  if (scaled) {
    auto dv = d.view();
    auto lv = lambda.view();
    for (PetscInt i = 0; i < m; ++i) {
      dv[i] *= sigma_[i];
      lv[i] /= sigma_[i];
    }
  }
  qp::FeasibleSet set(d);
  for (PetscInt k = 0; k < n_nodes(); ++k) {
    const bool held = held_at_zero(k);
    set.set_interval(dim * k, {0.0, held ? 0.0 : qp::infinity});  // λ_n ≥ 0; 0 at a crosspoint
    const double r = held ? 0.0 : std::max(friction_bound[k], 0.0) / sigma(dim * k + 1);
    if (dim == 2)
      set.set_interval(dim * k + 1, {-r, r});  // |λ_τ| ≤ 𝔉γ
    else
      set.add_disc({dim * k + 1, dim * k + 2, {r}});  // ‖λ_τ‖ ≤ 𝔉γ
  }

  qp::QpOptions opt = settings_.qp;
  // The rank-one term moves λ_max(F): estimated afresh, and not kept for the next QPs.
  opt.max_eigenvalue = rank_one ? 0.0 : lambda_max_;
  if (rtol > 0) opt.rtol = rtol;
  // The normal rows are also held to their own size (QpOptions::row_groups, group 1): in a
  // slide d_τ is the slip of the step, orders above d_n, the indentation.
  opt.row_groups.resize(static_cast<size_t>(m));
  for (PetscInt i = 0; i < m; ++i) opt.row_groups[static_cast<size_t>(i)] = i % dim == 0 ? 1 : 0;
  qp::QpResult r;
  std::vector<double> g_scaled;  // Σg: the rank-one term of Σ F Σ
  if (rank_one)
    for (PetscInt i = 0; i < m; ++i) g_scaled.push_back(sigma(i) * rank_one_g_[i]);
  const auto add_rank_one = [&](const core::Vector& x, core::Vector& y) {
    const auto xv = x.read();
    double dot = 0;
    for (PetscInt i = 0; i < m; ++i) dot += g_scaled[i] * xv[i];
    auto yv = y.view();
    for (PetscInt i = 0; i < m; ++i) yv[i] += rank_one_weight_ * dot * g_scaled[i];
  };
  if (kind_ == DualOperator::explicit_schur) {
    qp::SymmetricDenseOperator f(f_dense_.get());  // Σ F Σ when scaled
    // 2m² flops per product, some tens of products per QP: dsymv on a large F is a kernel
    // that gains from threads (core/numeric/threads.hpp); a small one stays on one.
    const core::KernelThreads threads(50 * 2.0 * static_cast<double>(m) * static_cast<double>(m));
    if (rank_one) {
      qp::FunctionOperator fr(
          [&](const core::Vector& x, core::Vector& y) {
            f.apply(x, y);
            add_rank_one(x, y);
          },
          d);
      r = qp::Mpgp(fr, set, opt).solve(d, lambda);
    } else {
      r = qp::Mpgp(f, set, opt).solve(d, lambda);
    }
  } else {
    qp::FunctionOperator f(
        [&](const core::Vector& x, core::Vector& y) {
          apply_f(x, y);
          if (rank_one) add_rank_one(x, y);
        },
        d);
    r = qp::Mpgp(f, set, opt).solve(d, lambda);
  }
  if (scaled) {
    auto lv = lambda.view();
    for (PetscInt i = 0; i < m; ++i) lv[i] *= sigma_[i];
  }
  if (!rank_one) {
    lambda_max_ = r.max_eigenvalue;
    lambda_max_rows_ = m;
  }
  last_tolerance_ = r.tolerance;
  if (scaled)
    last_sigma_ = sigma_;
  else
    last_sigma_.clear();

  if (recover) this->recover(lambda, u);
  return r;
}

void DualContactSolver::solve_free(int i, const core::Vector& b, core::Vector& u,
                                   const core::Vector& lambda) {
  const auto k = static_cast<size_t>(i);
  corrected_[k].cancel();
  if (n_rows() > 0) {
    b_[k].mult_transpose(lambda, w_in_[k]);
    // Unloaded (before the first touch) recover() has no solve to share.
    if (w_in_[k].max_abs() != 0.0 && compliance_[k]->begin_corrected(b, u, corrected_[k])) return;
  }
  bodies_[k]->solve(b, u);
}

void DualContactSolver::recover(const core::Vector& lambda, BodyVectorsOut u) const {
  for (int i = 0; i < n_bodies(); ++i) {  // u_i −= A_i⁻¹ B_iᵀ λ
    const auto k = static_cast<size_t>(i);
    if (n_rows() > 0)
      b_[i].mult_transpose(lambda, w_in_[i]);
    else
      w_in_[i].zero();
    // u_i = A_i⁻¹(b_i − B_iᵀλ): the corrected solve solve_free began
    if (compliance_[k]->finish_corrected(corrected_[k], w_in_[i], *u[i])) continue;
    // No contact force on the body (every step before the first touch): A⁻¹0 = 0 exactly,
    // and the solve would cost as much as the step's own.
    if (w_in_[i].max_abs() == 0.0) continue;
    // B_iᵀλ lives on T: the compliance may have a cheaper A⁻¹ of it than a solve (CHOLMOD's
    // kept forward columns: half a solve).
    if (!compliance_[i]->apply(w_in_[i], y_[i])) {
      y_[i].zero();
      bodies_[i]->solve(w_in_[i], y_[i]);
    }
    u[i]->axpy(-1.0, y_[i]);
  }
}

void DualContactSolver::constraint_values(BodyVectors u_free, const core::Vector& lambda,
                                          core::Vector& bu) const {
  const PetscInt m = n_rows();
  bu = core::Vector(m);
  if (m == 0) return;
  core::Vector f_lambda(m);
  if (kind_ == DualOperator::explicit_schur && settings_.scale) {  // Σ⁻¹(Σ F Σ)(Σ⁻¹λ)
    core::Vector x = lambda.clone();
    {
      auto xv = x.view();
      for (PetscInt i = 0; i < m; ++i) xv[i] /= sigma_[i];
    }
    TC_PETSC(MatMult(f_dense_.get(), x.get(), f_lambda.get()));
    auto fv = f_lambda.view();
    for (PetscInt i = 0; i < m; ++i) fv[i] /= sigma_[i];
  } else if (kind_ == DualOperator::explicit_schur) {
    TC_PETSC(MatMult(f_dense_.get(), lambda.get(), f_lambda.get()));
  } else {
    apply_f(lambda, f_lambda);
  }
  for (int i = 0; i < n_bodies(); ++i)
    if (i == 0)
      b_[i].mult(*u_free[i], bu);
    else
      b_[i].mult_add(*u_free[i], bu);
  bu.axpy(-1.0, f_lambda);
}

}  // namespace tc::physics
