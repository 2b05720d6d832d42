#pragma once
// Internal to tc/feti: a subdomain of Feti (its copy of the body dofs, its rows of B, kernel
// and factorisations), shared by Feti and ContactFeti, which reuses the subdomains of two
// bodies in one dual problem.
#include <Eigen/Dense>
#include <span>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/feti/feti.hpp"
#include "tc/linalg/cholesky_solver.hpp"

namespace tc::feti {

struct Entry {  // one nonzero of B_s: row of B, local dof, value
  Eigen::Index row;
  PetscInt dof;
  double value;
};

/// A column-major Eigen block seen as a PETSc MATSEQDENSE (no copy), for multi-RHS solves.
class DenseView {
 public:
  explicit DenseView(Eigen::MatrixXd& m) {
    TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, static_cast<PetscInt>(m.rows()),
                               static_cast<PetscInt>(m.cols()), m.data(), mat_.out()));
  }
  [[nodiscard]] ::Mat get() const { return mat_.get(); }

 private:
  core::Handle<::Mat, MatDestroy> mat_;
};

struct Feti::Subdomain {
  std::vector<PetscInt> global_dof;  // local dof → body dof
  std::vector<Entry> b;              // B_s, sorted by row (rows of B, 0..m−1, on every rank)
  Eigen::MatrixXd r;                 // kernel basis, orthonormal columns (local dofs × k)
  Eigen::Index kernel_offset = 0;    // first row of G belonging to this subdomain
  bool owned = false;
  // Owned subdomains only:
  std::vector<Eigen::Index> leaf;  // per entry of b: its row's place in the rank's leaf block
  core::SparseMatrix a;
  std::vector<PetscInt> fixing;    // dofs set to zero in A⁺ (the fixing-node generalised inverse)
  linalg::CholeskySolver factor;   // of A with the fixing dofs eliminated
  std::vector<PetscInt> boundary;  // local dofs with a row of B (Dirichlet preconditioner)
  linalg::CholeskySolver interior;  // of A with the boundary dofs eliminated
  mutable Block w, z, t;            // work blocks, n × k

  [[nodiscard]] PetscInt n() const { return static_cast<PetscInt>(global_dof.size()); }

  /// The shared pieces of the dual operators Σ_s B_s X_s B_sᵀ of Feti and ContactFeti, for
  /// the nonzeros `entries` of B_s whose i-th row stands at row(i) of the dual blocks (Feti:
  /// the rank's leaf block, ContactFeti: the replicated dual vector).
  /// out = B_sᵀ x (out: n × k).
  template <class Row, class X>
  void scatter_transpose(std::span<const Entry> entries, Row row, const X& x, Block& out) const {
    out.setZero(n(), x.cols());
    for (size_t i = 0; i < entries.size(); ++i)
      out.row(entries[i].dof) += entries[i].value * x.row(row(i));
  }
  /// y += B_s in.
  template <class Row, class Y>
  void gather(std::span<const Entry> entries, Row row, const Block& in, Y& y) const {
    for (size_t i = 0; i < entries.size(); ++i)
      y.row(row(i)) += entries[i].value * in.row(entries[i].dof);
  }
  /// y += B_s X_s B_sᵀ x: w = B_sᵀ x, z = X_s w by `local` (A_s⁺ for F, A_s or the Schur
  /// complement for a preconditioner), y += B_s z.
  template <class Row, class X, class Y, class Local>
  void add_product(std::span<const Entry> entries, Row row, const X& x, Y& y, Local&& local) const {
    scatter_transpose(entries, row, x, w);
    local(*this);
    gather(entries, row, z, y);
  }
  /// The row of entry i in the rank's leaf block (DualDistribution).
  [[nodiscard]] auto leaf_row() const {
    return [this](size_t i) { return leaf[i]; };
  }
  void scatter_transpose_leaves(const Block& x, Block& out) const {
    scatter_transpose(b, leaf_row(), x, out);
  }
  void gather_leaves(const Block& in, Block& y) const { gather(b, leaf_row(), in, y); }
  /// out = A_s⁺ in, column by column through one multi-RHS solve (in is zeroed at the
  /// fixing dofs).
  void pseudo_solve(Block& in, Block& out) const {
    for (const PetscInt d : fixing) in.row(d).setZero();
    solve_with(factor, in, out);
  }
  void interior_solve(Block& in, Block& out) const { solve_with(interior, in, out); }
  /// One right-hand side through KSPSolve (KSPMatSolve costs several times more for one
  /// column), more through one multi-RHS solve.
  void solve_with(const linalg::CholeskySolver& c, Block& in, Block& out) const {
    out.resize(in.rows(), in.cols());
    if (in.cols() == 1) {
      core::Handle<::Vec, VecDestroy> x, y;
      TC_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n(), in.data(), x.out()));
      TC_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n(), out.data(), y.out()));
      c.solve_raw(x.get(), y.get());
      return;
    }
    const DenseView bi(in), xo(out);
    c.solve_many(bi.get(), xo.get());
  }
  void mult(Block& in, Block& out) const {  // out = A_s in
    out.resize(in.rows(), in.cols());
    core::Handle<::Vec, VecDestroy> x, y;
    TC_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n(), nullptr, x.out()));
    TC_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n(), nullptr, y.out()));
    for (Eigen::Index j = 0; j < in.cols(); ++j) {
      TC_PETSC(VecPlaceArray(x.get(), in.col(j).data()));
      TC_PETSC(VecPlaceArray(y.get(), out.col(j).data()));
      TC_PETSC(MatMult(a.get(), x.get(), y.get()));
      TC_PETSC(VecResetArray(x.get()));
      TC_PETSC(VecResetArray(y.get()));
    }
  }
};

}  // namespace tc::feti
