#include "tc/physics/dual_contact.hpp"

#include <algorithm>
#include <cassert>
#include <utility>

namespace tc::physics {

const char* name(DualOperator k) {
  return k == DualOperator::explicit_schur ? "explicit" : "matrix-free";
}

DualContactSolver::DualContactSolver(const ConstrainedSolver& slave,
                                     const ConstrainedSolver& master, PetscInt n_u_slave,
                                     PetscInt n_u_master, DualContactSettings settings)
    : slave_(slave), master_(master), settings_(std::move(settings)) {
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
  assert(rows_.slave.rows() == rows_.n_rows() && rows_.master.rows() == rows_.n_rows());
  const PetscInt m = rows_.n_rows();
  kind_ = m > 0 && m <= settings_.explicit_limit ? DualOperator::explicit_schur
                                                 : DualOperator::matrix_free;
  setup_solves_ = 0;
  if (kind_ == DualOperator::explicit_schur) form_explicit();
  if (kind_ == DualOperator::explicit_schur || m != lambda_max_rows_) lambda_max_ = 0;
}

void DualContactSolver::form_explicit() {
  // F = Σ_i B_i A_i⁻¹ B_iᵀ, `block` columns at a time: the rows of B_i as the columns of a
  // dense right-hand side, one multi-right-hand-side solve per body (level-3 BLAS in the
  // factorisation package, several times faster than as many single solves), then B_i times
  // the solutions. Blocks bound the dense work space to n × block per body.
  using Dense = core::Handle<::Mat, MatDestroy>;
  const PetscInt m = rows_.n_rows();
  constexpr PetscInt block = 64;
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, m, m, nullptr, f_dense_.out()));
  PetscScalar* f = nullptr;
  TC_PETSC(MatDenseGetArray(f_dense_.get(), &f));
  PetscInt ldf = m;
  TC_PETSC(MatDenseGetLDA(f_dense_.get(), &ldf));
  for (PetscInt j = 0; j < m; ++j) std::fill(f + j * ldf, f + j * ldf + m, 0.0);
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
                                      core::Vector& u_slave, core::Vector& u_master) {
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

  qp::FeasibleSet set(d);
  for (PetscInt k = 0; k < rows_.n_nodes(); ++k) {
    set.set_interval(dim * k, {0.0, qp::infinity});  // λ_n ≥ 0
    const double r = std::max(friction_bound[k], 0.0);
    if (dim == 2)
      set.set_interval(dim * k + 1, {-r, r});  // |λ_τ| ≤ 𝔉γ
    else
      set.add_disc({dim * k + 1, dim * k + 2, {r}});  // ‖λ_τ‖ ≤ 𝔉γ
  }

  qp::QpOptions opt = settings_.qp;
  opt.max_eigenvalue = lambda_max_;
  qp::QpResult r;
  if (kind_ == DualOperator::explicit_schur) {
    qp::MatrixOperator f(f_dense_.get());
    r = qp::Mpgp(f, set, opt).solve(d, lambda);
  } else {
    qp::FunctionOperator f([this](const core::Vector& x, core::Vector& y) { apply_f(x, y); }, d);
    r = qp::Mpgp(f, set, opt).solve(d, lambda);
  }
  lambda_max_ = r.max_eigenvalue;
  lambda_max_rows_ = m;

  // u_i = u_free,i − A_i⁻¹ B_iᵀ λ.
  rows_.slave.mult_transpose(lambda, ws_);
  solve_homogeneous(slave_, ws_, zs_);
  u_slave.axpy(-1.0, zs_);
  rows_.master.mult_transpose(lambda, wm_);
  solve_homogeneous(master_, wm_, zm_);
  u_master.axpy(-1.0, zm_);
  return r;
}

}  // namespace tc::physics
