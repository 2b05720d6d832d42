// The explicit dual operator of DualContactSolver: F = Σ_i B_i A_i⁻¹ B_iᵀ formed by
// multi-right-hand-side solves, or from each body's compliance S_i on the rows' dofs (its
// threaded bands) and the Jacobi
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

#include "tc/core/error.hpp"
#include "tc/core/numeric/collective.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/core/verify.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/linalg/dense.hpp"

namespace tc::physics {

namespace {

using linalg::dense::assemble;
using linalg::dense::Dense;
using linalg::dense::zero_dense;

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
    if (compliance_[i]->size() + compliance_[i]->missing(cols[i]) > settings_.compliance_limit)
      return false;
  }
  for (int i = 0; i < nb; ++i) setup_solves_ += static_cast<int>(compliance_[i]->cover(cols[i]));
  // B_i,T (Ĉ_i,T on nodes) row by row, T-positions ascending: the order in which the sparse
  // products summed before (Eigen's setFromTriplets sorts them), so B's F keeps its bits.
  // Positions are then renumbered into U_i ⊆ T, the T-positions this step's rows reach: S
  // grows with every dof the rows have ever touched (a sliding pin's track), the products below
  // need only S_UU, and U's order is T's, so every sum runs over the same terms in the same
  // order.
  std::vector<RowsT> bt(nb);
  for (int i = 0; i < nb; ++i) {
    const auto& s = *compliance_[i];
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
  // Every entry of F is written below: the last step's storage serves when it has m rows
  // (24 MB at 1 743 rows, whose pages would be faulted in and zeroed again).
  PetscInt rows = -1, cols_f = -1;
  if (f_dense_.get()) TC_PETSC(MatGetSize(f_dense_.get(), &rows, &cols_f));
  if (rows != m || cols_f != m)
    TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, m, m, nullptr, f_dense_.out()));
  PetscScalar* fv = nullptr;
  TC_PETSC(MatDenseGetArray(f_dense_.get(), &fv));
  PetscInt ldf = m;
  TC_PETSC(MatDenseGetLDA(f_dense_.get(), &ldf));
  form_bands(bt, fv, ldf);
  // Each rank's part of G from its rows of the S_i (linalg::Compliance::rows_spread), summed: the
  // same G on every rank.
  if (compliance_.front()->rows_spread())
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

void DualContactSolver::form_bands(const std::vector<RowsT>& bt, double* fv, PetscInt ldf) {
  // G = Σ_i B_i,U S_i,UU B_i,Uᵀ in two passes, each entry the same sum in the same order as
  // row by row (so the same F to the bit, whatever the tiles and threads):
  // 1. W_i = B_i,U S_i,UU by tiles of columns of W_i (rows of S_UU): a tile of S_UU, every
  //    U-column on the tile's rows (S's columns, contiguous: S is symmetric to the bit), is
  //    gathered from S once and stays in cache while every row of B_i passes over it; row r of
  //    the tile is Σ_q b(r, q) S(tile, q) over the row's few entries, in registers. Read row by
  //    row, S_UU would stream from memory once per entry of B_i (32 190 × 3 948 doubles a step
  //    on the refined pin-on-plate), and copied out of S first. W_i is stored by bands of 32
  //    rows, q by q.
  // 2. By bands: F_i(r, c) = Σ_q b_i(c, q) W_i(r, q) with the band of W_i in cache while every
  //    column c passes, G = F_s + F_m straight into F's storage; the bands write disjoint rows.
  // Tiles and bands are dealt to settings_.form_threads threads (by default the policy's kernel
  // threads). With S's rows dealt over the ranks, W_i has this rank's rows of S_UU only (q runs
  // over them in F_i too): each rank forms its part of G, which the caller sums.
  const PetscInt m = n_rows();
  const int nb = n_bodies();
  const PetscInt n_bands = (m + kBand - 1) / kBand;
  std::vector<PetscInt> width(static_cast<size_t>(nb));  // W_i's columns: this rank's rows of S_UU
  std::vector<PetscInt> tile_of(static_cast<size_t>(nb) + 1, 0);  // body i's first tile
  for (int i = 0; i < nb; ++i) {
    const auto k = static_cast<size_t>(i);
    width[k] = static_cast<PetscInt>(kept_[k].size());
    w_bands_[k].resize(static_cast<size_t>(n_bands * width[k] * kBand));
    tile_of[k + 1] = tile_of[k] + (width[k] + kTile - 1) / kTile;
  }
  // 2·nnz(B_i)·(|U| + m) flops: by the policy's kernel threads (core/numeric/threads.hpp) when
  // large, one decision for both passes.
  double flops = 0;
  for (int i = 0; i < nb; ++i)
    flops += 2.0 * static_cast<double>(bt[static_cast<size_t>(i)].value.size()) *
             static_cast<double>(width[static_cast<size_t>(i)] + m);
  const core::KernelThreads kernel(flops);
  const int threads = settings_.form_threads > 0 ? settings_.form_threads : kernel.threads();
  const auto deal = [&](PetscInt n_items, auto&& item) {
    // A buffer may fail to allocate: the first failure stops the dealing and is rethrown here
    // once every thread has stopped (an exception must not leave a thread). A helper the system
    // cannot start leaves its items to the others.
    std::atomic<PetscInt> next{0};
    std::mutex failed;
    std::exception_ptr failure;
    const auto guarded = [&] {
      try {
        std::vector<double> buffer;
        for (PetscInt j = next++; j < n_items; j = next++) item(j, buffer);
      } catch (...) {
        const std::lock_guard lock(failed);
        if (!failure) failure = std::current_exception();
        next = n_items;
      }
    };
    const PetscInt n_threads = std::clamp<PetscInt>(threads, 1, std::max<PetscInt>(n_items, 1));
    {
      std::vector<std::jthread> helpers;
      try {
        for (PetscInt h = 1; h < n_threads; ++h) helpers.emplace_back(guarded);
      } catch (const std::system_error&) {
      }
      guarded();
    }  // the helpers joined
    if (failure) std::rethrow_exception(failure);
  };
  deal(tile_of.back(), [&](PetscInt j, std::vector<double>& tile) {
    const auto i = static_cast<size_t>(std::upper_bound(tile_of.begin(), tile_of.end(), j) -
                                       tile_of.begin() - 1);
    const auto& comp = *compliance_[i];
    const double* s = comp.matrix().data();  // this rank's rows of S, column-major
    const auto ld = static_cast<size_t>(comp.matrix().rows());
    const auto& used = used_[i];
    const auto& kept = kept_[i];
    const PetscInt a0 = (j - tile_of[i]) * kTile;
    const PetscInt valid = std::min(kTile, width[i] - a0);
    // the tile: S_UU(a0 + a, p) = S(kept[a0 + a], used[p]) at tile[p·kTile + a], zero past
    // W_i. S whole here is symmetric to the bit: read down its columns kept[a0 + a] (a stream
    // each, where reading along its rows would miss the cache at every U-column); S's rows
    // dealt over the ranks, along the rows this rank has.
    tile.assign(used.size() * static_cast<size_t>(kTile), 0.0);
    if (!comp.rows_spread()) {
      for (PetscInt a = 0; a < valid; ++a) {
        const double* col = s + static_cast<size_t>(kept[static_cast<size_t>(a0 + a)]) * ld;
        for (size_t p = 0; p < used.size(); ++p)
          tile[p * kTile + static_cast<size_t>(a)] = col[used[p]];
      }
    } else {
      for (size_t p = 0; p < used.size(); ++p) {
        const double* col = s + static_cast<size_t>(used[p]) * ld;
        for (PetscInt a = 0; a < valid; ++a)
          tile[p * kTile + static_cast<size_t>(a)] = col[kept[static_cast<size_t>(a0 + a)]];
      }
    }
    const auto& r = bt[i];
    const auto w_width = static_cast<size_t>(width[i]);
    for (PetscInt row = 0; row < m; ++row) {
      double acc[kTile] = {};
      for (PetscInt e = r.start[row]; e < r.start[row + 1]; ++e) {
        const double v = r.value[static_cast<size_t>(e)];
        const double* sp = tile.data() + static_cast<size_t>(r.pos[static_cast<size_t>(e)]) * kTile;
        for (PetscInt a = 0; a < kTile; ++a) acc[a] += v * sp[a];
      }
      double* w = w_bands_[i].data() + static_cast<size_t>(row / kBand) * w_width * kBand +
                  static_cast<size_t>(row % kBand);
      for (PetscInt a = 0; a < valid; ++a) w[static_cast<size_t>(a0 + a) * kBand] = acc[a];
    }
  });
  deal(n_bands, [&](PetscInt b, std::vector<double>&) {
    const PetscInt r0 = b * kBand, nr = std::min(kBand, m - r0);
    for (PetscInt c = 0; c < m; ++c) {
      double sum[kBand] = {};  // Σ_i F_i(r, c), summed body by body
      for (int i = 0; i < nb; ++i) {
        const auto k = static_cast<size_t>(i);
        const auto& r = bt[k];
        const auto& row_of = used_row_[k];
        const double* wb = w_bands_[k].data() + static_cast<size_t>(b * width[k] * kBand);
        double acc[kBand] = {};
        for (PetscInt e = r.start[c]; e < r.start[c + 1]; ++e) {
          const PetscInt q = row_of[static_cast<size_t>(r.pos[static_cast<size_t>(e)])];
          if (q < 0) continue;  // another rank's row of S
          const double v = r.value[static_cast<size_t>(e)];
          const double* wq = wb + static_cast<size_t>(q) * kBand;
          for (PetscInt l = 0; l < nr; ++l) acc[l] += v * wq[l];
        }
        for (PetscInt l = 0; l < nr; ++l) sum[l] = i == 0 ? acc[l] : sum[l] + acc[l];
      }
      for (PetscInt l = 0; l < nr; ++l) fv[c * ldf + r0 + l] = sum[l];
    }
  });
}

void DualContactSolver::restrict_compliance(int i, std::vector<PetscInt>& pos) {
  const auto k = static_cast<size_t>(i);
  const auto& comp = *compliance_[k];
  const auto t = static_cast<size_t>(comp.size());
  std::vector<PetscInt> at(t, -1);  // T-position → U-position
  for (const PetscInt q : pos) at[static_cast<size_t>(q)] = 0;
  auto& used = used_[k];
  used.clear();
  for (size_t q = 0; q < t; ++q)
    if (at[q] == 0) {
      at[q] = static_cast<PetscInt>(used.size());
      used.push_back(static_cast<PetscInt>(q));
    }
  // This rank's rows of S_UU: U-position → its row of W_i, or −1; the rows of S they are.
  auto& row_of = used_row_[k];
  auto& kept = kept_[k];
  row_of.assign(used.size(), -1);
  kept.clear();
  for (size_t b = 0; b < used.size(); ++b)
    if (const PetscInt r = comp.row_of(used[b]); r >= 0) {
      row_of[b] = static_cast<PetscInt>(kept.size());
      kept.push_back(r);
    }
  if (used.size() < t)
    for (auto& q : pos) q = at[static_cast<size_t>(q)];
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
