#include "tc/physics/dual_contact.hpp"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

#include "tc/core/error.hpp"

namespace tc::physics {

const char* name(DualOperator k) {
  return k == DualOperator::explicit_schur ? "explicit" : "matrix-free";
}

DualContactSolver::DualContactSolver(const ConstrainedSolver& slave,
                                     const ConstrainedSolver& master, PetscInt n_u_slave,
                                     PetscInt n_u_master, DualContactSettings settings)
    : slave_(slave),
      master_(master),
      settings_(std::move(settings)),
      compliance_{DofCompliance(slave, n_u_slave), DofCompliance(master, n_u_master)} {
  ws_ = core::Vector(n_u_slave);
  ys_ = core::Vector(n_u_slave);
  zs_ = core::Vector(n_u_slave);
  wm_ = core::Vector(n_u_master);
  ym_ = core::Vector(n_u_master);
  zm_ = core::Vector(n_u_master);
}

void DualContactSolver::solve_homogeneous(const ConstrainedSolver& s, const core::Vector& rhs,
                                          core::Vector& x) const {
  x.zero();  // zero Dirichlet values: A⁻¹ of the constrained operator
  s.solve(rhs, x);
}

void DualContactSolver::apply_f(const core::Vector& x, core::Vector& y) const {
  rows_.slave.mult_transpose(x, ws_);
  solve_homogeneous(slave_, ws_, ys_);
  rows_.master.mult_transpose(x, wm_);
  solve_homogeneous(master_, wm_, ym_);
  rows_.slave.mult(ys_, y);
  rows_.master.mult_add(ym_, y);
}

void DualContactSolver::set_rows(ContactRows rows) {
  rows_ = std::move(rows);
  normal_floor_.clear();
  assert(rows_.slave.rows() == rows_.n_rows() && rows_.master.rows() == rows_.n_rows());
  const PetscInt m = rows_.n_rows();
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

namespace {

using dense::assemble;
using dense::Dense;
using dense::zero_dense;

/// The nonzeros of a sparse matrix as (row, column, value).
std::vector<Eigen::Triplet<double, PetscInt>> nonzeros(const core::SparseMatrix& b) {
  std::vector<Eigen::Triplet<double, PetscInt>> out;
  for (PetscInt r = 0; r < b.rows(); ++r) {
    PetscInt nz = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    TC_PETSC(MatGetRow(b.get(), r, &nz, &cols, &vals));
    for (PetscInt q = 0; q < nz; ++q)
      if (vals[q] != 0.0) out.emplace_back(r, cols[q], vals[q]);
    TC_PETSC(MatRestoreRow(b.get(), r, &nz, &cols, &vals));
  }
  return out;
}

}  // namespace

void DualContactSolver::form_scaled() {
  // Σ from the diagonal of F, node by node: σ_n = F_nn^{-1/2}, σ_τ = (mean of the tangent
  // diagonals)^{-1/2}. The diagonal of F spreads over the nodal weights squared (a corner node
  // of the dual basis carries a quarter of an inner node's area) and the normal/tangential
  // compliances; the fixed-step projected gradient moves of MPGP (ᾱ = 1.9/λ_max) crawl on the
  // small-diagonal nodes, which scaling removes. A zero diagonal (a row on constrained dofs
  // only) keeps σ = 1.
  const PetscInt m = rows_.n_rows();
  const int dim = rows_.dim;
  const PetscScalar* f = nullptr;
  TC_PETSC(MatDenseGetArrayRead(f_dense_.get(), &f));
  PetscInt ld = m;
  TC_PETSC(MatDenseGetLDA(f_dense_.get(), &ld));
  sigma_.assign(static_cast<size_t>(m), 1.0);
  for (PetscInt k = 0; k < rows_.n_nodes(); ++k) {
    const PetscInt n = dim * k;
    if (f[n * ld + n] > 0) sigma_[n] = 1.0 / std::sqrt(f[n * ld + n]);
    double t = 0;
    for (int l = 1; l < dim; ++l) t += f[(n + l) * ld + n + l] / (dim - 1);
    for (int l = 1; l < dim; ++l)
      if (t > 0) sigma_[n + l] = 1.0 / std::sqrt(t);
  }
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, m, m, nullptr, f_scaled_.out()));
  PetscScalar* g = nullptr;
  TC_PETSC(MatDenseGetArray(f_scaled_.get(), &g));
  PetscInt ldg = m;
  TC_PETSC(MatDenseGetLDA(f_scaled_.get(), &ldg));
  for (PetscInt j = 0; j < m; ++j)
    for (PetscInt i = 0; i < m; ++i) g[j * ldg + i] = sigma_[i] * f[j * ld + i] * sigma_[j];
  TC_PETSC(MatDenseRestoreArray(f_scaled_.get(), &g));
  TC_PETSC(MatDenseRestoreArrayRead(f_dense_.get(), &f));
  assemble(f_scaled_.get());
}

void DualContactSolver::save_compliance(std::span<std::vector<int>, 4> record) const {
  for (int i = 0; i < 2; ++i) {
    const auto& comp = compliance_[i];
    record[2 * i].assign(comp.dofs().begin(), comp.dofs().end());
    record[2 * i + 1].assign(comp.chunks().begin(), comp.chunks().end());
  }
}

void DualContactSolver::replay_compliance(std::span<const std::vector<int>, 4> record) {
  for (int i = 0; i < 2; ++i) {
    const auto& dofs = record[2 * i];
    const auto& chunks = record[2 * i + 1];
    compliance_[i].replay(std::vector<PetscInt>(dofs.begin(), dofs.end()),
                          std::vector<PetscInt>(chunks.begin(), chunks.end()));
  }
}

bool DualContactSolver::form_from_compliance() {
  // F = Σ_i B_i,T S_i B_i,Tᵀ: W = B_i,T S_i (nnz(B_i)·|T| flops), then W B_i,Tᵀ
  // (m · nnz(B_i)); no solve unless the rows reach new dofs.
  const PetscInt m = rows_.n_rows();
  const core::SparseMatrix* b[2] = {&rows_.slave, &rows_.master};
  std::vector<Eigen::Triplet<double, PetscInt>> entries[2];
  std::vector<PetscInt> cols[2];
  for (int i = 0; i < 2; ++i) {  // both bodies checked before either spends a solve
    entries[i] = nonzeros(*b[i]);
    cols[i].reserve(entries[i].size());
    for (const auto& e : entries[i]) cols[i].push_back(e.col());
    if (compliance_[i].size() + compliance_[i].missing(cols[i]) > settings_.compliance_limit)
      return false;
  }
  for (int i = 0; i < 2; ++i) setup_solves_ += static_cast<int>(compliance_[i].cover(cols[i]));
  // B_i,T row by row, T-positions ascending: the order in which the sparse products summed
  // before (Eigen's setFromTriplets sorts them), which keeps every entry of F to the bit.
  struct RowsT {
    std::vector<PetscInt> start, pos;
    std::vector<double> value;
  } bt[2];
  for (int i = 0; i < 2; ++i) {
    const auto& s = compliance_[i];
    auto& r = bt[i];
    r.start.assign(static_cast<size_t>(m) + 1, 0);
    for (const auto& e : entries[i]) ++r.start[static_cast<size_t>(e.row()) + 1];
    for (PetscInt k = 0; k < m; ++k) r.start[k + 1] += r.start[k];
    std::vector<std::pair<PetscInt, double>> row;
    for (size_t e = 0; e < entries[i].size();) {  // entries come row by row (nonzeros())
      const PetscInt k = entries[i][e].row();
      row.clear();
      for (; e < entries[i].size() && entries[i][e].row() == k; ++e)
        row.emplace_back(s.index(entries[i][e].col()), entries[i][e].value());
      std::sort(row.begin(), row.end());
      for (const auto& [q, v] : row) {
        r.pos.push_back(q);
        r.value.push_back(v);
      }
    }
  }
  // By bands of `band` rows r: the band of W_i = B_i,T S_i, row r = Σ_p b(r, p) S(p, :) over
  // the few entries of row r (S's columns, contiguous: S is symmetric to the bit), stored q by
  // q; then G = F_s + F_m on the band, F_i(r, c) = Σ_q b_i(c, q) W_i(r, q), the band of W_i in
  // cache while every column c passes, straight into F's storage; then F = ½(G + Gᵀ) in place
  // by tiles. (Before: W_iᵀ and F_i formed whole, 28 MB each at 1 875 rows, then read
  // transposed: 0.2 s a step.)
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, m, m, nullptr, f_dense_.out()));
  PetscScalar* fv = nullptr;
  TC_PETSC(MatDenseGetArray(f_dense_.get(), &fv));
  PetscInt ldf = m;
  TC_PETSC(MatDenseGetLDA(f_dense_.get(), &ldf));
  constexpr PetscInt band = 32;
  std::vector<double> row_major;
  for (PetscInt r0 = 0; r0 < m; r0 += band) {
    const PetscInt nr = std::min(band, m - r0);
    for (int i = 0; i < 2; ++i) {
      const auto& sm = compliance_[i].matrix();
      const auto t = static_cast<size_t>(compliance_[i].size());
      const auto& r = bt[i];
      row_major.assign(static_cast<size_t>(nr) * t, 0.0);
      for (PetscInt k = 0; k < nr; ++k) {
        double* wr = row_major.data() + static_cast<size_t>(k) * t;
        for (PetscInt e = r.start[r0 + k]; e < r.start[r0 + k + 1]; ++e) {
          const double v = r.value[static_cast<size_t>(e)];
          const double* sp = sm.data() + static_cast<size_t>(r.pos[static_cast<size_t>(e)]) * t;
          for (size_t q = 0; q < t; ++q) wr[q] += v * sp[q];
        }
      }
      auto& w = w_[i];
      w.resize(t * band);
      for (size_t q = 0; q < t; ++q)
        for (PetscInt k = 0; k < nr; ++k)
          w[q * band + static_cast<size_t>(k)] = row_major[static_cast<size_t>(k) * t + q];
    }
    for (PetscInt c = 0; c < m; ++c) {
      double acc[2][band] = {};
      for (int i = 0; i < 2; ++i) {
        const auto& r = bt[i];
        for (PetscInt e = r.start[c]; e < r.start[c + 1]; ++e) {
          const double v = r.value[static_cast<size_t>(e)];
          const double* wq =
              w_[i].data() + static_cast<size_t>(r.pos[static_cast<size_t>(e)]) * band;
          for (PetscInt k = 0; k < nr; ++k) acc[i][k] += v * wq[k];
        }
      }
      for (PetscInt k = 0; k < nr; ++k) fv[c * ldf + r0 + k] = acc[0][k] + acc[1][k];
    }
  }
  constexpr PetscInt tile = 64;
  for (PetscInt j0 = 0; j0 < m; j0 += tile)
    for (PetscInt i0 = 0; i0 <= j0; i0 += tile)
      for (PetscInt j = j0; j < std::min(m, j0 + tile); ++j)
        for (PetscInt i = i0; i < std::min(m, i0 + tile) && i <= j; ++i) {
          const double v = 0.5 * (fv[j * ldf + i] + fv[i * ldf + j]);
          fv[j * ldf + i] = v;
          fv[i * ldf + j] = v;
        }
  TC_PETSC(MatDenseRestoreArray(f_dense_.get(), &fv));
  assemble(f_dense_.get());
  return true;
}

void DualContactSolver::form_by_solves() {
  // F = Σ_i B_i A_i⁻¹ B_iᵀ, `block` columns at a time: the rows of B_i as the columns of a
  // dense right-hand side, one multi-right-hand-side solve per body (level-3 BLAS in the
  // factorisation package, several times faster than as many single solves), then B_i times
  // the solutions. Blocks bound the dense work space to n × block per body.
  const PetscInt m = rows_.n_rows();
  constexpr PetscInt block = 64;
  f_dense_ = zero_dense(m, m);
  PetscScalar* f = nullptr;
  TC_PETSC(MatDenseGetArray(f_dense_.get(), &f));
  PetscInt ldf = m;
  TC_PETSC(MatDenseGetLDA(f_dense_.get(), &ldf));
  const std::pair<const core::SparseMatrix*, const ConstrainedSolver*> bodies[] = {
      {&rows_.slave, &slave_}, {&rows_.master, &master_}};
  for (const auto& [b, solver] : bodies) {
    const PetscInt n = b->cols();
    for (PetscInt j0 = 0; j0 < m; j0 += block) {
      const PetscInt k = std::min(block, m - j0);
      Dense rhs, sol, prod;
      TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, rhs.out()));
      TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, sol.out()));
      PetscScalar* r = nullptr;
      TC_PETSC(MatDenseGetArray(rhs.get(), &r));
      PetscInt ldr = n;
      TC_PETSC(MatDenseGetLDA(rhs.get(), &ldr));
      for (PetscInt c = 0; c < k; ++c) {
        std::fill(r + c * ldr, r + c * ldr + n, 0.0);
        PetscInt nz = 0;
        const PetscInt* cols = nullptr;
        const PetscScalar* vals = nullptr;
        TC_PETSC(MatGetRow(b->get(), j0 + c, &nz, &cols, &vals));
        for (PetscInt q = 0; q < nz; ++q) r[c * ldr + cols[q]] = vals[q];
        TC_PETSC(MatRestoreRow(b->get(), j0 + c, &nz, &cols, &vals));
      }
      TC_PETSC(MatDenseRestoreArray(rhs.get(), &r));
      for (::Mat x : {rhs.get(), sol.get()}) {
        TC_PETSC(MatAssemblyBegin(x, MAT_FINAL_ASSEMBLY));
        TC_PETSC(MatAssemblyEnd(x, MAT_FINAL_ASSEMBLY));
      }
      solver->solve_homogeneous_many(rhs.get(), sol.get());
      TC_PETSC(MatMatMult(b->get(), sol.get(), MAT_INITIAL_MATRIX, PETSC_DEFAULT, prod.out()));
      const PetscScalar* p = nullptr;
      TC_PETSC(MatDenseGetArrayRead(prod.get(), &p));
      PetscInt ldp = m;
      TC_PETSC(MatDenseGetLDA(prod.get(), &ldp));
      for (PetscInt c = 0; c < k; ++c)
        for (PetscInt i = 0; i < m; ++i) f[(j0 + c) * ldf + i] += p[c * ldp + i];
      TC_PETSC(MatDenseRestoreArrayRead(prod.get(), &p));
    }
  }
  TC_PETSC(MatDenseRestoreArray(f_dense_.get(), &f));
  TC_PETSC(MatAssemblyBegin(f_dense_.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(f_dense_.get(), MAT_FINAL_ASSEMBLY));
  setup_solves_ = 2 * m;  // right-hand sides solved (in 2⌈m/block⌉ block solves)
}

std::vector<double> DualContactSolver::targets(const core::Vector& ref_slave,
                                               const core::Vector& ref_master,
                                               const core::Vector& slip_slave,
                                               const core::Vector& slip_master) const {
  const PetscInt m = rows_.n_rows();
  core::Vector normal(m), slip(m);
  rows_.slave.mult(ref_slave, normal);
  rows_.master.mult_add(ref_master, normal);
  rows_.slave.mult(slip_slave, slip);
  rows_.master.mult_add(slip_master, slip);
  const auto nv = normal.read();
  const auto sv = slip.read();
  std::vector<double> c(static_cast<size_t>(m));
  const int dim = rows_.dim;
  for (PetscInt k = 0; k < rows_.n_nodes(); ++k) {
    c[dim * k] = rows_.gap[k] + nv[dim * k];
    for (int l = 1; l < dim; ++l) c[dim * k + l] = sv[dim * k + l];
  }
  return c;
}

qp::QpResult DualContactSolver::solve(const core::Vector& u_free_slave,
                                      const core::Vector& u_free_master, std::span<const double> c,
                                      std::span<const double> friction_bound, core::Vector& lambda,
                                      core::Vector& u_slave, core::Vector& u_master, bool recover,
                                      double rtol) {
  const PetscInt m = rows_.n_rows();
  const int dim = rows_.dim;
  u_slave.copy_from(u_free_slave);
  u_master.copy_from(u_free_master);
  if (m == 0) {
    qp::QpResult none;
    none.status = qp::QpStatus::converged;
    return none;
  }

  // d = B u_free − c.
  core::Vector d(m);
  rows_.slave.mult(u_free_slave, d);
  rows_.master.mult_add(u_free_master, d);
  {
    auto dv = d.view();
    for (PetscInt i = 0; i < m; ++i) dv[i] -= c[i];
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
  for (PetscInt k = 0; k < rows_.n_nodes(); ++k) {
    const double floor = normal_floor_.empty() ? 0.0 : normal_floor_[k] / sigma(dim * k);
    set.set_interval(dim * k, {floor, qp::infinity});  // λ_n ≥ 0 (or the release floor)
    const double r = std::max(friction_bound[k], 0.0) / sigma(dim * k + 1);
    if (dim == 2)
      set.set_interval(dim * k + 1, {-r, r});  // |λ_τ| ≤ 𝔉γ
    else
      set.add_disc({dim * k + 1, dim * k + 2, {r}});  // ‖λ_τ‖ ≤ 𝔉γ
  }

  qp::QpOptions opt = settings_.qp;
  opt.max_eigenvalue = lambda_max_;
  if (rtol > 0) opt.rtol = rtol;
  qp::QpResult r;
  if (kind_ == DualOperator::explicit_schur) {
    qp::MatrixOperator f(scaled ? f_scaled_.get() : f_dense_.get());
    r = qp::Mpgp(f, set, opt).solve(d, lambda);
  } else {
    qp::FunctionOperator f([this](const core::Vector& x, core::Vector& y) { apply_f(x, y); }, d);
    r = qp::Mpgp(f, set, opt).solve(d, lambda);
  }
  if (scaled) {
    auto lv = lambda.view();
    for (PetscInt i = 0; i < m; ++i) lv[i] *= sigma_[i];
  }
  lambda_max_ = r.max_eigenvalue;
  lambda_max_rows_ = m;

  if (recover) this->recover(lambda, u_slave, u_master);
  return r;
}

void DualContactSolver::recover(const core::Vector& lambda, core::Vector& u_slave,
                                core::Vector& u_master) const {
  if (rows_.n_rows() == 0) return;
  rows_.slave.mult_transpose(lambda, ws_);  // u_i −= A_i⁻¹ B_iᵀ λ
  solve_homogeneous(slave_, ws_, zs_);
  u_slave.axpy(-1.0, zs_);
  rows_.master.mult_transpose(lambda, wm_);
  solve_homogeneous(master_, wm_, zm_);
  u_master.axpy(-1.0, zm_);
}

void DualContactSolver::constraint_values(const core::Vector& u_free_slave,
                                          const core::Vector& u_free_master,
                                          const core::Vector& lambda, core::Vector& bu) const {
  const PetscInt m = rows_.n_rows();
  bu = core::Vector(m);
  if (m == 0) return;
  core::Vector f_lambda(m);
  if (kind_ == DualOperator::explicit_schur)
    TC_PETSC(MatMult(f_dense_.get(), lambda.get(), f_lambda.get()));
  else
    apply_f(lambda, f_lambda);
  rows_.slave.mult(u_free_slave, bu);
  rows_.master.mult_add(u_free_master, bu);
  bu.axpy(-1.0, f_lambda);
}

}  // namespace tc::physics
