// The explicit dual operator of DualContactSolver: F = Σ_i B_i A_i⁻¹ B_iᵀ formed by
// multi-right-hand-side solves, or from each body's compliance S_i on the rows' dofs (its
// threaded bands), the record of which dofs the compliance covered (restart), and the Jacobi
// scaling Σ F Σ (docs/theory.md, 6.9). dual_contact.cpp holds the rows, the QP and the
// recovery of u.
#include <Eigen/SparseCore>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

#include "tc/core/collective.hpp"
#include "tc/core/error.hpp"
#include "tc/core/threads.hpp"
#include "tc/core/verify.hpp"
#include "tc/dual/dual_contact.hpp"

namespace tc::physics {

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

/// The nonzeros of Ĉ_i = ±(C ⊗ I) stacked over the pairs, in the stacked rows of B_i (row
/// dim·k + c is node k's Cartesian component c): D for the pairs whose slave body i is, −M for
/// those whose master it is. Row by row, as nonzeros() gives B_i's.
std::vector<Eigen::Triplet<double, PetscInt>> node_nonzeros(std::span<const ContactRows> pairs,
                                                            std::span<const PairBodies> bodies,
                                                            std::span<const PetscInt> offsets,
                                                            int body) {
  std::vector<Eigen::Triplet<double, PetscInt>> out;
  for (size_t p = 0; p < pairs.size(); ++p) {
    const bool slave = bodies[p].slave == body, master = bodies[p].master == body;
    if (!slave && !master) continue;
    const auto& r = pairs[p];
    const core::SparseMatrix& c = slave ? r.d : r.m;
    const double sign = slave ? 1.0 : -1.0;  // B_s = V(D ⊗ I), B_m = −V(M ⊗ I)
    for (PetscInt k = 0; k < r.n_nodes(); ++k) {
      PetscInt nz = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* vals = nullptr;
      TC_PETSC(MatGetRow(c.get(), k, &nz, &cols, &vals));
      for (int comp = 0; comp < r.dim; ++comp)
        for (PetscInt q = 0; q < nz; ++q)
          if (vals[q] != 0.0)
            out.emplace_back(r.dim * (offsets[p] + k) + comp, r.dim * cols[q] + comp,
                             sign * vals[q]);
      TC_PETSC(MatRestoreRow(c.get(), k, &nz, &cols, &vals));
    }
  }
  return out;
}

/// F = V G Vᵀ in place, node block by node block: F_kl = V_k G_kl V_lᵀ (`v`: dim × dim per
/// node, row-major).
void rotate_blocks(double* f, PetscInt ld, PetscInt n_nodes, int dim, std::span<const double> v) {
  const auto d = static_cast<PetscInt>(dim);
  double g[9], h[9];
  for (PetscInt l = 0; l < n_nodes; ++l) {
    const double* vl = v.data() + l * d * d;
    for (PetscInt k = 0; k < n_nodes; ++k) {
      const double* vk = v.data() + k * d * d;
      double* blk = f + (d * l) * ld + d * k;  // G_kl(c, c') at blk[c' ld + c]
      for (PetscInt c2 = 0; c2 < d; ++c2)
        for (PetscInt c = 0; c < d; ++c) g[c * d + c2] = blk[c2 * ld + c];
      for (PetscInt r = 0; r < d; ++r)  // h = V_k G
        for (PetscInt c2 = 0; c2 < d; ++c2) {
          double sum = 0;
          for (PetscInt c = 0; c < d; ++c) sum += vk[r * d + c] * g[c * d + c2];
          h[r * d + c2] = sum;
        }
      for (PetscInt r = 0; r < d; ++r)  // F_kl = h V_lᵀ
        for (PetscInt s2 = 0; s2 < d; ++s2) {
          double sum = 0;
          for (PetscInt c2 = 0; c2 < d; ++c2) sum += h[r * d + c2] * vl[s2 * d + c2];
          blk[s2 * ld + r] = sum;
        }
    }
  }
}

}  // namespace

void DualContactSolver::form_scaled() {
  // Σ from the diagonal of F, node by node: σ_n = F_nn^{-1/2}, σ_τ = (mean of the tangent
  // diagonals)^{-1/2}. The diagonal of F spreads over the nodal weights squared (a corner node
  // of the dual basis carries a quarter of an inner node's area) and the normal/tangential
  // compliances; the fixed-step projected gradient moves of MPGP (ᾱ = 1.9/λ_max) crawl on the
  // small-diagonal nodes, which scaling removes. A zero diagonal (a row on constrained dofs
  // only) keeps σ = 1.
  const PetscInt m = n_rows();
  const int dim = dim_;
  const PetscScalar* f = nullptr;
  TC_PETSC(MatDenseGetArrayRead(f_dense_.get(), &f));
  PetscInt ld = m;
  TC_PETSC(MatDenseGetLDA(f_dense_.get(), &ld));
  sigma_.assign(static_cast<size_t>(m), 1.0);
  for (PetscInt k = 0; k < n_nodes(); ++k) {
    const PetscInt n = dim * k;
    if (f[n * ld + n] > 0) sigma_[n] = 1.0 / std::sqrt(f[n * ld + n]);
    double t = 0;
    for (int l = 1; l < dim; ++l) t += f[(n + l) * ld + n + l] / (dim - 1);
    for (int l = 1; l < dim; ++l)
      if (t > 0) sigma_[n + l] = 1.0 / std::sqrt(t);
  }
  TC_PETSC(MatDenseRestoreArrayRead(f_dense_.get(), &f));
  // Σ F Σ in F's place: the QP needs no other, and a second m × m matrix would be the dual's
  // largest structure again (F λ is Σ⁻¹(Σ F Σ)Σ⁻¹λ, constraint_values).
  PetscScalar* g = nullptr;
  TC_PETSC(MatDenseGetArray(f_dense_.get(), &g));
  for (PetscInt j = 0; j < m; ++j)
    for (PetscInt i = 0; i < m; ++i) g[j * ld + i] = sigma_[i] * g[j * ld + i] * sigma_[j];
  TC_PETSC(MatDenseRestoreArray(f_dense_.get(), &g));
  assemble(f_dense_.get());
}

void DualContactSolver::save_compliance(std::vector<std::vector<int>>& record) const {
  for (const auto& comp : compliance_) {
    record.emplace_back(comp.dofs().begin(), comp.dofs().end());
    record.emplace_back(comp.chunks().begin(), comp.chunks().end());
  }
}

void DualContactSolver::replay_compliance(std::span<const std::vector<int>> record) {
  if (record.size() != 2 * compliance_.size())
    throw Error("checkpoint: the compliance record does not match the contact bodies");
  for (size_t i = 0; i < compliance_.size(); ++i) {
    const auto& dofs = record[2 * i];
    const auto& chunks = record[2 * i + 1];
    compliance_[i].replay(std::vector<PetscInt>(dofs.begin(), dofs.end()),
                          std::vector<PetscInt>(chunks.begin(), chunks.end()));
  }
}

bool DualContactSolver::form_from_compliance() {
  // F = Σ_i B_i,T S_i B_i,Tᵀ: W = B_i,T S_i (nnz(B_i)·|T| flops), then W B_i,Tᵀ
  // (m · nnz(B_i)); no solve unless the rows reach new dofs.
  // With the rows' node structure (ContactRows::node_structured), B_i = V Ĉ_i, Ĉ_i = ±(C ⊗ I):
  // G = Σ_i Ĉ_i S_i Ĉ_iᵀ, then F = V G Vᵀ node block by node block. A row of Ĉ_i has a dim-th
  // of the entries of a row of B_i (each body node once, not once per direction), so both
  // products cost a dim-th; the rotation adds 2·dim flops per entry of F.
  const PetscInt m = n_rows();
  const int nb = n_bodies();
  const bool by_nodes = std::all_of(pairs_.begin(), pairs_.end(),
                                    [](const ContactRows& r) { return r.node_structured(); });
  std::vector<std::vector<Eigen::Triplet<double, PetscInt>>> entries(nb);
  std::vector<std::vector<PetscInt>> cols(nb);
  for (int i = 0; i < nb; ++i) {  // every body checked before any spends a solve
    entries[i] = by_nodes ? node_nonzeros(pairs_, pair_bodies_, offsets_, i) : nonzeros(b_[i]);
    cols[i].reserve(entries[i].size());
    for (const auto& e : entries[i]) cols[i].push_back(e.col());
    if (compliance_[i].size() + compliance_[i].missing(cols[i]) > settings_.compliance_limit)
      return false;
  }
  for (int i = 0; i < nb; ++i) setup_solves_ += static_cast<int>(compliance_[i].cover(cols[i]));
  // B_i,T (Ĉ_i,T on nodes) row by row, T-positions ascending: the order in which the sparse
  // products summed before (Eigen's setFromTriplets sorts them), so B's F keeps its bits.
  // Positions are then renumbered into U_i ⊆ T, the T-positions this step's rows reach: S
  // grows with every dof the rows have ever touched (a sliding pin's track), the products below
  // need only S_UU, and U's order is T's, so every sum runs over the same terms in the same
  // order.
  std::vector<RowsT> bt(nb);
  for (int i = 0; i < nb; ++i) {
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
    restrict_compliance(i, r.pos);
  }
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, m, m, nullptr, f_dense_.out()));
  PetscScalar* fv = nullptr;
  TC_PETSC(MatDenseGetArray(f_dense_.get(), &fv));
  PetscInt ldf = m;
  TC_PETSC(MatDenseGetLDA(f_dense_.get(), &ldf));
  form_bands(bt, fv, ldf);
  // Each rank's part of G from its rows of the S_i (DofCompliance::rows_spread), summed: the
  // same G on every rank.
  if (compliance_.front().rows_spread())
    core::sum_over_ranks(PETSC_COMM_WORLD, fv, static_cast<long>(ldf) * m, "the explicit F");
  if (by_nodes) {
    std::vector<double> v;
    v.reserve(static_cast<size_t>(dim_) * static_cast<size_t>(m));
    for (const auto& r : pairs_) v.insert(v.end(), r.directions.begin(), r.directions.end());
    rotate_blocks(fv, ldf, n_nodes(), dim_, v);
  }
  // F = ½(G + Gᵀ) in place by tiles: exactly symmetric, as dsymv reads one triangle
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

void DualContactSolver::form_bands(const std::vector<RowsT>& bt, double* fv, PetscInt ldf) const {
  // By bands of `band` rows r: the band of W_i = B_i,U S_i,UU, row r = Σ_q b(r, q) S(q, :) over
  // the few entries of row r (S's columns, contiguous: S is symmetric to the bit), stored q by
  // q; then G = F_s + F_m on the band, F_i(r, c) = Σ_q b_i(c, q) W_i(r, q), the band of W_i in
  // cache while every column c passes, straight into F's storage. The bands write disjoint
  // rows of F and are dealt to settings_.form_threads threads (by default the rank's BLAS
  // threads, its CPUs): every entry is the same sum in the same order whatever the threads.
  // With S's rows dealt over the ranks, q runs over this rank's rows of S only in W_i and in
  // F_i: each rank forms its part of G, which the caller sums.
  const PetscInt m = n_rows();
  const int nb = n_bodies();
  constexpr PetscInt band = 32;
  const PetscInt n_bands = (m + band - 1) / band;
  std::atomic<PetscInt> next{0};
  const auto work = [&] {
    std::vector<double> row_major;
    std::vector<std::vector<double>> w(static_cast<size_t>(nb));  // the band of W_i, q by q
    for (PetscInt b = next++; b < n_bands; b = next++) {
      const PetscInt r0 = b * band, nr = std::min(band, m - r0);
      for (int i = 0; i < nb; ++i) {
        // S_UU, or S itself where the rows reach all of T (no copy)
        const double* sm = s_used_[i].empty() ? compliance_[i].matrix().data() : s_used_[i].data();
        const auto t = static_cast<size_t>(s_used_rows_[i]);  // this rank's rows of S_UU
        const auto& r = bt[i];
        row_major.assign(static_cast<size_t>(nr) * t, 0.0);
        for (PetscInt k = 0; k < nr; ++k) {
          double* wr = row_major.data() + static_cast<size_t>(k) * t;
          for (PetscInt e = r.start[r0 + k]; e < r.start[r0 + k + 1]; ++e) {
            const double v = r.value[static_cast<size_t>(e)];
            const double* sp = sm + static_cast<size_t>(r.pos[static_cast<size_t>(e)]) * t;
            for (size_t q = 0; q < t; ++q) wr[q] += v * sp[q];
          }
        }
        auto& wi = w[static_cast<size_t>(i)];
        wi.resize(t * band);
        for (size_t q = 0; q < t; ++q)
          for (PetscInt k = 0; k < nr; ++k)
            wi[q * band + static_cast<size_t>(k)] = row_major[static_cast<size_t>(k) * t + q];
      }
      for (PetscInt c = 0; c < m; ++c) {
        double sum[band] = {};  // Σ_i F_i(r, c), summed body by body
        for (int i = 0; i < nb; ++i) {
          const auto& r = bt[i];
          const auto& row_of = used_row_[static_cast<size_t>(i)];
          double acc[band] = {};
          for (PetscInt e = r.start[c]; e < r.start[c + 1]; ++e) {
            const PetscInt q = row_of[static_cast<size_t>(r.pos[static_cast<size_t>(e)])];
            if (q < 0) continue;  // another rank's row of S
            const double v = r.value[static_cast<size_t>(e)];
            const double* wq = w[static_cast<size_t>(i)].data() + static_cast<size_t>(q) * band;
            for (PetscInt k = 0; k < nr; ++k) acc[k] += v * wq[k];
          }
          for (PetscInt k = 0; k < nr; ++k) sum[k] = i == 0 ? acc[k] : sum[k] + acc[k];
        }
        for (PetscInt k = 0; k < nr; ++k) fv[c * ldf + r0 + k] = sum[k];
      }
    }
  };
  // A band's buffers may fail to allocate: the first failure stops the dealing and is
  // rethrown here once every thread has stopped (an exception must not leave a thread). A
  // helper the system cannot start leaves its bands to the others.
  std::mutex failed;
  std::exception_ptr failure;
  const auto guarded = [&] {
    try {
      work();
    } catch (...) {
      const std::lock_guard lock(failed);
      if (!failure) failure = std::current_exception();
      next = n_bands;
    }
  };
  // 2·nnz(B_i)·(|U| + m) flops: by the policy's kernel threads (core/threads.hpp) when large.
  double flops = 0;
  for (int i = 0; i < nb; ++i)
    flops +=
        2.0 * static_cast<double>(bt[i].value.size()) * static_cast<double>(s_used_rows_[i] + m);
  const core::KernelThreads kernel(flops);
  const int threads = settings_.form_threads > 0 ? settings_.form_threads : kernel.threads();
  const PetscInt n_threads = std::clamp<PetscInt>(threads, 1, n_bands);
  {
    std::vector<std::jthread> helpers;
    try {
      for (PetscInt h = 1; h < n_threads; ++h) helpers.emplace_back(guarded);
    } catch (const std::system_error&) {
    }
    guarded();
  }  // the helpers joined
  if (failure) std::rethrow_exception(failure);
}

void DualContactSolver::restrict_compliance(int i, std::vector<PetscInt>& pos) {
  const auto& comp = compliance_[i];
  const auto& full = comp.matrix();  // this rank's rows of S (all of them unless spread)
  const auto t = static_cast<size_t>(comp.size());
  std::vector<PetscInt> at(t, -1);  // T-position → U-position
  for (const PetscInt q : pos) at[static_cast<size_t>(q)] = 0;
  std::vector<PetscInt> used;
  for (size_t q = 0; q < t; ++q)
    if (at[q] == 0) {
      at[q] = static_cast<PetscInt>(used.size());
      used.push_back(static_cast<PetscInt>(q));
    }
  const size_t u = used.size();
  // This rank's rows of S_UU: U-position → its row, or −1; the rows of S they are.
  auto& row_of = used_row_[static_cast<size_t>(i)];
  row_of.assign(u, -1);
  std::vector<PetscInt> kept;
  for (size_t b = 0; b < u; ++b)
    if (const PetscInt r = comp.row_of(used[b]); r >= 0) {
      row_of[b] = static_cast<PetscInt>(kept.size());
      kept.push_back(r);
    }
  s_used_rows_[i] = static_cast<PetscInt>(kept.size());
  auto& su = s_used_[i];
  if (u == t) {  // U = T: the positions stay, S is used as it is
    su.clear();
    su.shrink_to_fit();
    return;
  }
  for (auto& q : pos) q = at[static_cast<size_t>(q)];
  const size_t rows = kept.size();
  const auto ld = static_cast<size_t>(full.rows());
  su.resize(rows * u);
  for (size_t b = 0; b < u; ++b) {
    const double* col = full.data() + static_cast<size_t>(used[b]) * ld;
    for (size_t a = 0; a < rows; ++a) su[b * rows + a] = col[kept[a]];
  }
}

void DualContactSolver::form_by_solves() {
  // F = Σ_i B_i A_i⁻¹ B_iᵀ, `block` columns at a time: the rows of B_i as the columns of a
  // dense right-hand side, one multi-right-hand-side solve per body (level-3 BLAS in the
  // factorisation package, several times faster than as many single solves), then B_i times
  // the solutions. Blocks bound the dense work space to n × block per body.
  const PetscInt m = n_rows();
  constexpr PetscInt block = 64;
  f_dense_ = zero_dense(m, m);
  PetscScalar* f = nullptr;
  TC_PETSC(MatDenseGetArray(f_dense_.get(), &f));
  PetscInt ldf = m;
  TC_PETSC(MatDenseGetLDA(f_dense_.get(), &ldf));
  for (int i = 0; i < n_bodies(); ++i) {
    const core::SparseMatrix* b = &b_[i];
    const ConstrainedSolver* solver = bodies_[i];
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
  setup_solves_ = n_bodies() * m;  // right-hand sides solved (in blocks of `block`)
}

}  // namespace tc::physics
