// Columns of A⁻¹ on a few rows, for unit right-hand sides, from CHOLMOD's supernodal factor
// (CholeskySolver::unit_solve_rows), and (A⁻¹)_TT by forward solves alone
// (CholeskySolver::forward_compliance). PETSc keeps the factor inside its CHOLMOD matrix type,
// whose layout is private: it is reached through the PETSc 3.14–3.18 layout and every field
// used is checked against the matrix before use; anything unexpected returns false and the
// caller solves with the dense right-hand sides instead.
#include <petsc/private/matimpl.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "tc/core/blas.hpp"  // the BLAS that CHOLMOD calls: the same kernels, the same bits
#include "tc/core/petsc.hpp"

#if defined(TC_CHOLMOD_COLUMNS)  // cholmod.h found (CMakeLists.txt)
#include <cholmod.h>
#define TC_HAVE_CHOLMOD 1
#endif

namespace tc::core {

// PETSc's private layout is assumed for 3.14–3.18 only (run and tested here on 3.18.5); other
// versions compile the fallback.
#if defined(TC_HAVE_CHOLMOD) && !defined(PETSC_USE_64BIT_INDICES) && \
    !defined(PETSC_USE_COMPLEX) && PETSC_VERSION_GE(3, 14, 0) && PETSC_VERSION_LT(3, 19, 0)

namespace {

// PETSc's Mat_CHOLMOD (src/mat/impls/sbaij/seq/cholmod/cholmodimpl.h, 3.14–3.18): only the
// leading fields, up to the factor.
struct PetscCholmod {
  void* wrap;
  cholmod_sparse* matrix;
  cholmod_factor* factor;
};

bool plausible(const cholmod_factor* f, PetscInt n) {
  return f != nullptr && f->n == static_cast<size_t>(n) && f->itype == CHOLMOD_INT &&
         f->xtype == CHOLMOD_REAL && f->dtype == CHOLMOD_DOUBLE && f->is_super && f->is_ll &&
         f->nsuper > 0 && f->super && f->pi && f->px && f->s && f->x && f->Perm;
}

}  // namespace

/// The supernodal structure the restricted solves need, built on first use.
struct CholeskyColumns {
  cholmod_factor* factor = nullptr;
  std::vector<int> pinv;      // dof → permuted row
  std::vector<int> super_of;  // permuted row → supernode
  std::vector<int> parent;    // supernode → parent supernode, −1 at a root
  std::vector<char> mark;     // per supernode, work
  std::vector<double> y, e;   // n × k solution, maxesize × k update
};

namespace {

CholeskyColumns* columns_of(::Mat f, std::shared_ptr<CholeskyColumns>& cache) {
  if (cache) return cache->factor ? cache.get() : nullptr;
  cache = std::make_shared<CholeskyColumns>();
  if (!f) return nullptr;
  MatSolverType type = nullptr;
  if (MatFactorGetSolverType(f, &type) || !type || std::strcmp(type, MATSOLVERCHOLMOD) != 0)
    return nullptr;
  PetscInt n = 0, n2 = 0;
  if (MatGetSize(f, &n, &n2) || n != n2) return nullptr;
  cholmod_factor* l = nullptr;
  for (void* p : {f->data, f->spptr})
    if (p && plausible(static_cast<PetscCholmod*>(p)->factor, n)) {
      l = static_cast<PetscCholmod*>(p)->factor;
      break;
    }
  if (!l) return nullptr;
  auto& c = *cache;
  const auto* perm = static_cast<const int*>(l->Perm);
  const auto* super = static_cast<const int*>(l->super);
  const auto* lpi = static_cast<const int*>(l->pi);
  const auto* ls = static_cast<const int*>(l->s);
  const auto ns = static_cast<int>(l->nsuper);
  c.pinv.assign(static_cast<size_t>(n), -1);
  for (int k = 0; k < n; ++k) {
    if (perm[k] < 0 || perm[k] >= n || c.pinv[static_cast<size_t>(perm[k])] >= 0) return nullptr;
    c.pinv[static_cast<size_t>(perm[k])] = k;
  }
  if (super[0] != 0 || super[ns] != n) return nullptr;
  c.super_of.assign(static_cast<size_t>(n), -1);
  for (int s = 0; s < ns; ++s)
    for (int k = super[s]; k < super[s + 1]; ++k) c.super_of[static_cast<size_t>(k)] = s;
  c.parent.assign(static_cast<size_t>(ns), -1);
  for (int s = 0; s < ns; ++s) {  // the first row below the diagonal block names the parent
    const int nscol = super[s + 1] - super[s];
    if (lpi[s + 1] - lpi[s] > nscol) {
      const int p = c.super_of[static_cast<size_t>(ls[lpi[s] + nscol])];
      if (p <= s) return nullptr;  // not in topological order: leave it to CHOLMOD
      c.parent[static_cast<size_t>(s)] = p;
    }
  }
  c.mark.assign(static_cast<size_t>(ns), 0);
  c.factor = l;
  return cache.get();
}

/// Supernode s of the factor: its first column k1 and nscol columns, the diagonal block L_11
/// at l1 (leading dimension nsrow) with L_21 below it, and the nsrow2 rows below the block
/// (ls[ps2 + ii]: its ancestors' rows).
struct Supernode {
  const double* l1;
  const int* ls;
  int k1, nscol, nsrow, nsrow2, ps2;
  Supernode(const cholmod_factor& l, int s)
      : l1(static_cast<const double*>(l.x) + static_cast<const int*>(l.px)[s]),
        ls(static_cast<const int*>(l.s)) {
    const auto* super = static_cast<const int*>(l.super);
    const auto* lpi = static_cast<const int*>(l.pi);
    k1 = super[s];
    nscol = super[s + 1] - k1;
    nsrow = lpi[s + 1] - lpi[s];
    nsrow2 = nsrow - nscol;
    ps2 = lpi[s] + nscol;
  }
};

/// Supernode s's step of the backward solve y ← L⁻ᵀy for one right-hand side (permuted), with
/// CHOLMOD's calls: E = y below the diagonal block (the ancestors' rows), y_s −= L_21ᵀE, then
/// y_s ← L_11⁻ᵀ y_s. `e` holds at least the factor's maxesize entries.
void backward_one(const cholmod_factor& l, int s, double* y, double* e) {
  const Supernode n(l, s);
  const double one = 1.0, minus_one = -1.0;
  const int inc = 1;
  for (int ii = 0; ii < n.nsrow2; ++ii) e[ii] = y[n.ls[n.ps2 + ii]];
  dgemv_("C", &n.nsrow2, &n.nscol, &minus_one, n.l1 + n.nscol, &n.nsrow, e, &inc, &one, y + n.k1,
         &inc);
  dtrsv_("L", "C", "N", &n.nscol, n.l1, &n.nsrow, y + n.k1, &inc);
}

/// Supernode s's step of the forward solve y ← L⁻¹y for one right-hand side (permuted), with
/// CHOLMOD's calls: y_s ← L_11⁻¹ y_s, then E = y below the diagonal block, E −= L_21 y_s, and
/// E back into y. `e` holds at least the factor's maxesize entries.
void forward_one(const cholmod_factor& l, int s, double* y, double* e) {
  const Supernode n(l, s);
  const double one = 1.0, minus_one = -1.0;
  const int inc = 1;
  for (int ii = 0; ii < n.nsrow2; ++ii) e[ii] = y[n.ls[n.ps2 + ii]];
  dtrsv_("L", "N", "N", &n.nscol, n.l1, &n.nsrow, y + n.k1, &inc);
  dgemv_("N", &n.nsrow2, &n.nscol, &minus_one, n.l1 + n.nscol, &n.nsrow, y + n.k1, &inc, &one, e,
         &inc);
  for (int ii = 0; ii < n.nsrow2; ++ii) y[n.ls[n.ps2 + ii]] = e[ii];
}

/// The supernodes of `rows` (permuted) and all their ancestors, ascending.
std::vector<int> reach(CholeskyColumns& c, std::span<const PetscInt> dofs) {
  std::vector<int> out;
  for (const PetscInt d : dofs) {
    if (d < 0) continue;
    for (int s = c.super_of[static_cast<size_t>(c.pinv[static_cast<size_t>(d)])];
         s >= 0 && !c.mark[static_cast<size_t>(s)]; s = c.parent[static_cast<size_t>(s)]) {
      c.mark[static_cast<size_t>(s)] = 1;
      out.push_back(s);
    }
  }
  for (const int s : out) c.mark[static_cast<size_t>(s)] = 0;
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

bool CholeskySolver::unit_solve_rows(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                                     double* out) const {
  if (distributed()) {
    inverse_entries(cols, rows, out);
    return true;
  }
  CholeskyColumns* c = columns_of(factor_.get(), columns_);
  if (!c || cols.empty()) return c != nullptr;
  const cholmod_factor& l = *c->factor;
  const int n = static_cast<int>(l.n);
  const int k = static_cast<int>(cols.size());
  const auto* super = static_cast<const int*>(l.super);
  const auto* lpi = static_cast<const int*>(l.pi);
  const auto* lpx = static_cast<const int*>(l.px);
  const auto* ls = static_cast<const int*>(l.s);
  const auto* lx = static_cast<const double*>(l.x);
  c->y.assign(static_cast<size_t>(n) * static_cast<size_t>(k), 0.0);
  c->e.resize(std::max<size_t>(1, l.maxesize) * static_cast<size_t>(k));
  double* y = c->y.data();
  double* e = c->e.data();
  for (int j = 0; j < k; ++j)  // Y = P B, B the unit columns (a skipped column stays zero)
    if (cols[static_cast<size_t>(j)] >= 0)
      y[static_cast<size_t>(c->pinv[static_cast<size_t>(cols[static_cast<size_t>(j)])]) +
        static_cast<size_t>(j) * static_cast<size_t>(n)] = 1.0;
  const double one = 1.0, minus_one = -1.0;
  // E = the rows of Y below a supernode's diagonal block (its ancestors' rows), CHOLMOD's E.
  const auto gather_below = [&](int ps2, int nsrow2) {
    for (int ii = 0; ii < nsrow2; ++ii)
      for (int j = 0; j < k; ++j)
        e[ii + j * nsrow2] = y[static_cast<size_t>(ls[ps2 + ii]) + static_cast<size_t>(j) * n];
  };
  // Forward, Y = L⁻¹Y, on the supernodes the columns reach: elsewhere Y stays zero and every
  // skipped update would subtract an exact zero. Each visited supernode makes CHOLMOD's own
  // calls (cholmod_super_lsolve), in the same order.
  for (const int s : reach(*c, cols)) {
    const int k1 = super[s], nscol = super[s + 1] - k1;
    const int psi = lpi[s], nsrow = lpi[s + 1] - psi, nsrow2 = nsrow - nscol, ps2 = psi + nscol;
    const double* l1 = lx + lpx[s];
    if (k == 1) {
      forward_one(l, s, y, e);
      continue;
    }
    gather_below(ps2, nsrow2);
    dtrsm_("L", "L", "N", "N", &nscol, &k, &one, l1, &nsrow, y + k1, &n);
    if (nsrow2 > 0)
      dgemm_("N", "N", &nsrow2, &k, &nscol, &minus_one, l1 + nscol, &nsrow, y + k1, &n, &one, e,
             &nsrow2);
    for (int ii = 0; ii < nsrow2; ++ii)
      for (int j = 0; j < k; ++j)
        y[static_cast<size_t>(ls[ps2 + ii]) + static_cast<size_t>(j) * n] = e[ii + j * nsrow2];
  }
  // Backward, Y = L⁻ᵀY, on the supernodes of the wanted rows and their ancestors (the rows
  // below a supernode's diagonal block belong to its ancestors), descending as CHOLMOD.
  const auto back = reach(*c, rows);
  for (auto it = back.rbegin(); it != back.rend(); ++it) {
    const int s = *it;
    if (k == 1) {
      backward_one(l, s, y, e);
      continue;
    }
    const int k1 = super[s], nscol = super[s + 1] - k1;
    const int psi = lpi[s], nsrow = lpi[s + 1] - psi, nsrow2 = nsrow - nscol, ps2 = psi + nscol;
    const double* l1 = lx + lpx[s];
    gather_below(ps2, nsrow2);
    if (nsrow2 > 0)
      dgemm_("C", "N", &nscol, &k, &nsrow2, &minus_one, l1 + nscol, &nsrow, e, &nsrow2, &one,
             y + k1, &n);
    dtrsm_("L", "L", "C", "N", &nscol, &k, &one, l1, &nsrow, y + k1, &n);
  }
  const auto nr = rows.size();
  for (int j = 0; j < k; ++j)  // X = Pᵀ Y on the wanted rows
    for (size_t i = 0; i < nr; ++i)
      out[i + static_cast<size_t>(j) * nr] =
          y[static_cast<size_t>(c->pinv[static_cast<size_t>(rows[i])]) +
            static_cast<size_t>(j) * n];
  return true;
}

namespace {

/// A postorder of the supernodal tree: post[s] is s's position, first[s] the first position
/// of its subtree, so the subtree of s is the range [first[s], post[s]]. Parents come after
/// their children in CHOLMOD's numbering (checked in columns_of), which gives the subtree
/// sizes in one ascending pass and the ranges in one descending pass.
void postorder(const std::vector<int>& parent, std::vector<int>& post, std::vector<int>& first) {
  const auto ns = parent.size();
  std::vector<int> size(ns, 1), cursor(ns, 0);
  for (size_t s = 0; s < ns; ++s)
    if (parent[s] >= 0) size[static_cast<size_t>(parent[s])] += size[s];
  post.assign(ns, 0);
  first.assign(ns, 0);
  int roots = 0;
  for (size_t s = ns; s-- > 0;) {
    int& at = parent[s] >= 0 ? cursor[static_cast<size_t>(parent[s])] : roots;
    first[s] = at;
    at += size[s];
    cursor[s] = first[s];
    post[s] = first[s] + size[s] - 1;
  }
}

/// Reorders the rows and the columns of the symmetric nt × nt matrix `a` (column-major) in
/// place: a'(i, j) = a(pos[i], pos[j]).
void permute_symmetric(double* a, const std::vector<int>& pos) {
  const auto nt = pos.size();
  std::vector<double> tmp(nt);
  for (size_t j = 0; j < nt; ++j) {  // the rows, column by column
    double* col = a + j * nt;
    for (size_t i = 0; i < nt; ++i) tmp[i] = col[pos[i]];
    std::copy(tmp.begin(), tmp.end(), col);
  }
  std::vector<char> done(nt, 0);
  for (size_t j0 = 0; j0 < nt; ++j0) {  // the columns, by the cycles of j ← pos[j]
    if (done[j0]) continue;
    std::copy(a + j0 * nt, a + (j0 + 1) * nt, tmp.begin());
    size_t j = j0;
    for (auto from = static_cast<size_t>(pos[j]); from != j0; from = static_cast<size_t>(pos[j])) {
      std::copy(a + from * nt, a + (from + 1) * nt, a + j * nt);
      done[j] = 1;
      j = from;
    }
    std::copy(tmp.begin(), tmp.end(), a + j * nt);
    done[j] = 1;
  }
}

/// One cover's columns in the order of the postorder position of the supernode where their unit
/// entry lies: the columns that reach supernode s (those starting in its subtree) are then one
/// contiguous range [lo[s], hi[s]) of the sorted ones. A constrained dof (−1) reaches nothing.
struct SortedColumns {
  std::vector<int> order;   // sorted position → position among the cover's columns
  std::vector<int> lo, hi;  // per supernode
  SortedColumns(const CholeskyColumns& c, const std::vector<int>& post,
                const std::vector<int>& first, std::span<const PetscInt> dofs) {
    constexpr int none = std::numeric_limits<int>::max();
    const auto nt = dofs.size();
    std::vector<int> key(nt);
    order.resize(nt);
    for (size_t j = 0; j < nt; ++j) {
      const PetscInt d = dofs[j];
      key[j] = d < 0 ? none
                     : post[static_cast<size_t>(
                           c.super_of[static_cast<size_t>(c.pinv[static_cast<size_t>(d)])])];
      order[j] = static_cast<int>(j);
    }
    // Equal keys (one supernode) by their row in it: a supernode's own columns then enter it
    // in order, which groups their leading zeros (leading_zero_groups).
    const auto row = [&](int j) {
      const PetscInt d = dofs[static_cast<size_t>(j)];
      return d < 0 ? 0 : c.pinv[static_cast<size_t>(d)];
    };
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      const auto ka = key[static_cast<size_t>(a)], kb = key[static_cast<size_t>(b)];
      return ka != kb ? ka < kb : row(a) < row(b);
    });
    std::vector<int> sorted(nt);
    for (size_t q = 0; q < nt; ++q) sorted[q] = key[static_cast<size_t>(order[q])];
    lo.resize(post.size());
    hi.resize(post.size());
    for (size_t s = 0; s < post.size(); ++s) {
      lo[s] = static_cast<int>(std::lower_bound(sorted.begin(), sorted.end(), first[s]) -
                               sorted.begin());
      hi[s] = static_cast<int>(std::upper_bound(sorted.begin(), sorted.end(), post[s]) -
                               sorted.begin());
    }
  }
  [[nodiscard]] int count(size_t s) const { return hi[s] - lo[s]; }
};

}  // namespace

/// Consecutive columns of a supernode's block of Y (nscol × cnt, before its triangular solve)
/// whose leading exact zeros are alike: [begin, end) with p the fewest. The rows above p stay
/// zero through the solve, the update below and S's products, so each group starts at its p.
/// A column's zeros are those above the row where its path in the elimination tree enters the
/// supernode (the children's update or its own unit entry): on the 10⁶-dof plate they halve the
/// forward solve's triangular flops at the root's separators. Columns join a group while its
/// widest trailing block stays within 1.25× of the narrowest (a bounded waste, few BLAS calls).
struct ZeroGroup {
  int begin, end, p;
};
std::vector<ZeroGroup> leading_zero_groups(const double* y, int nscol, int cnt) {
  std::vector<ZeroGroup> out;
  int lo = 0, hi = 0;  // the group's fewest and most leading zeros
  for (int j = 0; j < cnt; ++j) {
    const double* col = y + static_cast<ptrdiff_t>(j) * nscol;
    int p = 0;
    while (p < nscol && col[p] == 0.0) ++p;
    if (!out.empty()) {
      const int l = std::min(lo, p), h = std::max(hi, p);
      if (4 * (nscol - l) <= 5 * (nscol - h)) {
        out.back().end = j + 1;
        out.back().p = lo = l;
        hi = h;
        continue;
      }
    }
    out.push_back({j, j + 1, p});
    lo = hi = p;
  }
  return out;
}

/// Y = L⁻¹P E_T of the covers so far, cover by cover, on the supernodes each reaches: block
/// (s) is nscol(s) × count(s), the cover's sorted columns of that range.
struct ForwardColumns {
  const cholmod_factor* factor = nullptr;  // the factor Y belongs to
  std::vector<int> post, first;
  struct Cover {
    SortedColumns columns;
    size_t offset;  // position of the cover's first dof in T
    std::vector<std::vector<double>> y;
  };
  std::vector<Cover> covers;
  size_t size = 0;  // |T|
};

namespace {

/// Flops of one supernode's forward step with k right-hand sides (dtrsm, then dgemm below).
double forward_flops(int nscol, int nsrow, double k) {
  return k * (static_cast<double>(nscol) * nscol + 2.0 * nscol * (nsrow - nscol));
}

}  // namespace

bool CholeskySolver::forward_compliance_pays(std::span<const PetscInt> dofs, int block) const {
  CholeskyColumns* c = columns_of(factor_.get(), columns_);
  if (!c || dofs.empty()) return false;
  // -tc_forward_compliance takes this path at any size of a supernodal factor (CHOLMOD picks
  // a simplicial one for the smallest cases, then there is no c): no case of test size
  // reaches the bound below, and the tests check its later-step columns and restart replay
  // this way.
  PetscBool forced = PETSC_FALSE;
  TC_PETSC(PetscOptionsGetBool(nullptr, nullptr, "-tc_forward_compliance", &forced, nullptr));
  if (forced) return true;
  const cholmod_factor& l = *c->factor;
  const auto* super = static_cast<const int*>(l.super);
  const auto* lpi = static_cast<const int*>(l.pi);
  const auto ns = static_cast<size_t>(l.nsuper);
  std::vector<int> post, first;
  postorder(c->parent, post, first);
  const SortedColumns sorted(*c, post, first, dofs);
  double forward = 0, restricted = 0, back = 0;
  for (size_t s = 0; s < ns; ++s) {
    const int nscol = super[s + 1] - super[s], nsrow = lpi[s + 1] - lpi[s];
    const double c1 = nscol;
    const double k = sorted.count(s);
    forward += forward_flops(nscol, nsrow, k) + c1 * k * k;  // the solve, then S += Y_sᵀY_s
    if (k > 0) back += forward_flops(nscol, nsrow, 1);
  }
  for (size_t j0 = 0; j0 < dofs.size(); j0 += static_cast<size_t>(block)) {
    const auto part = dofs.subspan(j0, std::min(static_cast<size_t>(block), dofs.size() - j0));
    restricted += back * static_cast<double>(part.size());
    for (const int s : reach(*c, part))
      restricted += forward_flops(super[s + 1] - super[s], lpi[s + 1] - lpi[s],
                                  static_cast<double>(part.size()));
  }
  // Below `negligible` (a third of a second at the 30 GFlop/s of one core here) the restricted
  // solves cost next to nothing, and a switch would change the set-up's rounding for no
  // measurable time: they are kept there. Above it the fewer flops win: at 10⁶ dofs the
  // plate's forward solves are 2.5× fewer flops and 3.5× less time than its restricted ones
  // (bench/RESULTS.md), whether or not those stay below the factorisation.
  constexpr double negligible = 1e10;
  return restricted > negligible && forward < restricted;
}

void ForwardColumnsDeleter::operator()(ForwardColumns* y) const {
  delete y;
}

bool CholeskySolver::forward_compliance(ForwardColumnsPtr& kept, std::span<const PetscInt> fresh,
                                        double* out) const {
  CholeskyColumns* c = columns_of(factor_.get(), columns_);
  if (!c || (kept && kept->factor != c->factor)) return false;
  if (!kept) {
    kept.reset(new ForwardColumns);
    kept->factor = c->factor;
    postorder(c->parent, kept->post, kept->first);
  }
  auto& f = *kept;
  const cholmod_factor& l = *c->factor;
  const auto* super = static_cast<const int*>(l.super);
  const auto* lpi = static_cast<const int*>(l.pi);
  const auto* lpx = static_cast<const int*>(l.px);
  const auto* ls = static_cast<const int*>(l.s);
  const auto* lx = static_cast<const double*>(l.x);
  const auto ns = static_cast<size_t>(l.nsuper);
  const size_t old = f.size, nt = old + fresh.size();
  f.covers.push_back({SortedColumns(*c, f.post, f.first, fresh), old, {}});
  f.size = nt;
  auto& cover = f.covers.back();
  const auto& cols = cover.columns;
  const int k = static_cast<int>(fresh.size());
  auto& y = cover.y;
  y.resize(ns);
  const auto block = [&](size_t s) -> double* {
    if (y[s].empty())
      y[s].assign(static_cast<size_t>(super[s + 1] - super[s]) * static_cast<size_t>(cols.count(s)),
                  0.0);
    return y[s].data();
  };
  for (size_t q = 0; q < fresh.size(); ++q) {  // Y = P E before the solve
    const PetscInt d = fresh[static_cast<size_t>(cols.order[q])];
    if (d < 0) continue;
    const int r = c->pinv[static_cast<size_t>(d)];
    const auto s = static_cast<size_t>(c->super_of[static_cast<size_t>(r)]);
    block(s)[static_cast<size_t>(r - super[s]) +
             (q - static_cast<size_t>(cols.lo[s])) * static_cast<size_t>(super[s + 1] - super[s])] =
        1.0;
  }
  // S(T, fresh) in sorted order: the fresh columns with themselves (k × k, lower triangle by
  // dsyrk), and with each earlier cover's columns (|cover| × k by dgemm); on the first cover
  // the former is `out` itself.
  std::vector<double> own, with_old;
  double* ss = out;
  if (old > 0) {
    own.assign(static_cast<size_t>(k) * static_cast<size_t>(k), 0.0);
    with_old.assign(old * static_cast<size_t>(k), 0.0);
    ss = own.data();
  } else {
    std::fill(out, out + nt * nt, 0.0);
  }
  const double one = 1.0, zero = 0.0;
  constexpr int chunk = 256;  // columns per update: bounds E to (rows below) × chunk
  std::vector<double> e;
  std::vector<double*> dst;
  std::vector<int> ld;
  // Forward, Y = L⁻¹Y, supernode by supernode in CHOLMOD's (topological) order, each with all
  // the columns that reach it at once (the rows below its diagonal block are its ancestors',
  // whose ranges contain its own); once Y_s is final, its products with Y_s of every cover.
  for (size_t s = 0; s < ns; ++s) {
    const int cnt = cols.count(s);
    if (cnt == 0) continue;
    const int k1 = super[s], nscol = super[s + 1] - k1;
    const int psi = lpi[s], nsrow = lpi[s + 1] - psi, nsrow2 = nsrow - nscol, ps2 = psi + nscol;
    const double* l1 = lx + lpx[s];
    double* ys = block(s);
    const auto groups = leading_zero_groups(ys, nscol, cnt);
    for (const auto& g : groups) {  // Y_s ← L_11⁻¹Y_s below each group's leading zero rows
      const int r = nscol - g.p, kg = g.end - g.begin;
      dtrsm_("L", "L", "N", "N", &r, &kg, &one, l1 + g.p + static_cast<ptrdiff_t>(g.p) * nsrow,
             &nsrow, ys + g.p + static_cast<ptrdiff_t>(g.begin) * nscol, &nscol);
    }
    if (nsrow2 > 0) {
      dst.resize(static_cast<size_t>(nsrow2));
      ld.resize(static_cast<size_t>(nsrow2));
      for (int ii = 0; ii < nsrow2; ++ii) {
        const int r = ls[ps2 + ii];
        const auto a = static_cast<size_t>(c->super_of[static_cast<size_t>(r)]);
        ld[static_cast<size_t>(ii)] = super[a + 1] - super[a];
        dst[static_cast<size_t>(ii)] =
            block(a) + (r - super[a]) +
            static_cast<ptrdiff_t>(cols.lo[s] - cols.lo[a]) * (super[a + 1] - super[a]);
      }
      e.resize(static_cast<size_t>(nsrow2) * static_cast<size_t>(std::min(cnt, chunk)));
      for (const auto& g : groups) {  // the rows below: L_21 Y_s, from the group's first row
        const int r = nscol - g.p;
        for (int j0 = g.begin; j0 < g.end; j0 += chunk) {
          const int kc = std::min(chunk, g.end - j0);
          dgemm_("N", "N", &nsrow2, &kc, &r, &one, l1 + nscol + static_cast<ptrdiff_t>(g.p) * nsrow,
                 &nsrow, ys + g.p + static_cast<ptrdiff_t>(j0) * nscol, &nscol, &zero, e.data(),
                 &nsrow2);
          for (int j = 0; j < kc; ++j)
            for (int ii = 0; ii < nsrow2; ++ii)
              dst[static_cast<size_t>(ii)]
                 [static_cast<ptrdiff_t>(j0 + j) * ld[static_cast<size_t>(ii)]] -=
                  e[static_cast<size_t>(ii) + static_cast<size_t>(j) * static_cast<size_t>(nsrow2)];
        }
      }
    }
    // S += Y_sᵀY_s, lower triangle, group by group from the later group's first nonzero row.
    const int lds = old > 0 ? k : static_cast<int>(nt);
    double* s0 = ss + cols.lo[s] + static_cast<ptrdiff_t>(cols.lo[s]) * lds;
    for (size_t b = 0; b < groups.size(); ++b) {
      const auto& gb = groups[b];
      const int kb = gb.end - gb.begin;
      const int rb = nscol - gb.p;
      dsyrk_("L", "T", &kb, &rb, &one, ys + gb.p + static_cast<ptrdiff_t>(gb.begin) * nscol, &nscol,
             &one, s0 + gb.begin + static_cast<ptrdiff_t>(gb.begin) * lds, &lds);
      for (size_t a = 0; a < b; ++a) {
        const auto& ga = groups[a];
        const int ka = ga.end - ga.begin;
        const int p = std::max(ga.p, gb.p), r = nscol - p;
        dgemm_("T", "N", &kb, &ka, &r, &one, ys + p + static_cast<ptrdiff_t>(gb.begin) * nscol,
               &nscol, ys + p + static_cast<ptrdiff_t>(ga.begin) * nscol, &nscol, &one,
               s0 + gb.begin + static_cast<ptrdiff_t>(ga.begin) * lds, &lds);
      }
    }
    for (size_t g = 0; g + 1 < f.covers.size(); ++g) {
      const auto& earlier = f.covers[g];
      const int cg = earlier.columns.count(s);
      if (cg == 0) continue;
      const int ldw = static_cast<int>(old);
      dgemm_("T", "N", &cg, &cnt, &nscol, &one, earlier.y[s].data(), &nscol, ys, &nscol, &one,
             with_old.data() + earlier.offset + static_cast<size_t>(earlier.columns.lo[s]) +
                 static_cast<size_t>(cols.lo[s]) * old,
             &ldw);
    }
  }
  // Back to T's order: out(i, j) = S(T_i, fresh_j); with_old's rows are each cover's sorted
  // columns after its offset.
  const auto uk = static_cast<size_t>(k);
  std::vector<size_t> pos(uk);  // fresh column → sorted position
  for (size_t q = 0; q < uk; ++q) pos[static_cast<size_t>(cols.order[q])] = q;
  const auto lower = [&](size_t i, size_t j) {  // the fresh block, sorted, from its lower half
    return i >= j ? own[i + j * uk] : own[j + i * uk];
  };
  if (old == 0) {
    for (size_t j = 0; j < nt; ++j)  // the upper triangle from the lower: S exactly symmetric
      for (size_t i = j + 1; i < nt; ++i) out[j + i * nt] = out[i + j * nt];
    std::vector<int> p(nt);
    for (size_t i = 0; i < nt; ++i) p[i] = static_cast<int>(pos[i]);
    permute_symmetric(out, p);
    return true;
  }
  for (size_t j = 0; j < uk; ++j) {
    double* o = out + j * nt;
    for (const auto& earlier : f.covers) {
      if (&earlier == &cover) break;
      const auto& eo = earlier.columns.order;
      for (size_t q = 0; q < eo.size(); ++q)
        o[earlier.offset + static_cast<size_t>(eo[q])] =
            with_old[earlier.offset + q + pos[j] * old];
    }
    for (size_t i = 0; i < uk; ++i) o[old + i] = lower(pos[i], pos[j]);
  }
  return true;
}

bool CholeskySolver::forward_half(std::span<const double> b, std::vector<double>& z) const {
  CholeskyColumns* c = columns_of(factor_.get(), columns_);
  if (!c || b.size() != c->factor->n) return false;
  const cholmod_factor& l = *c->factor;
  const auto* perm = static_cast<const int*>(l.Perm);
  const auto n = static_cast<size_t>(l.n);
  z.resize(n);
  for (size_t k = 0; k < n; ++k) z[k] = b[static_cast<size_t>(perm[k])];  // P b
  c->e.resize(std::max<size_t>(1, l.maxesize));
  for (int s = 0; s < static_cast<int>(l.nsuper); ++s) forward_one(l, s, z.data(), c->e.data());
  return true;
}

bool CholeskySolver::forward_values(const ForwardColumns& kept, std::span<const double> z,
                                    std::span<double> out) const {
  CholeskyColumns* c = columns_of(factor_.get(), columns_);
  if (!c || kept.factor != c->factor || z.size() != c->factor->n || out.size() != kept.size)
    return false;
  const auto* super = static_cast<const int*>(c->factor->super);
  const auto ns = static_cast<size_t>(c->factor->nsuper);
  std::fill(out.begin(), out.end(), 0.0);
  const double one = 1.0, zero = 0.0;
  const int inc = 1;
  std::vector<double> t;
  // (Yᵀz)_q = Σ_s Y_s(:, q)ᵀ z_s over the supernodes column q reaches.
  for (const auto& cover : kept.covers) {
    const auto& cols = cover.columns;
    for (size_t s = 0; s < ns; ++s) {
      const int cnt = cols.count(s);
      const auto& ys = cover.y[s];
      if (cnt == 0 || ys.empty()) continue;
      const int nscol = super[s + 1] - super[s];
      t.resize(static_cast<size_t>(cnt));
      dgemv_("T", &nscol, &cnt, &one, ys.data(), &nscol, z.data() + super[s], &inc, &zero, t.data(),
             &inc);
      for (int q = 0; q < cnt; ++q)
        out[cover.offset + static_cast<size_t>(cols.order[static_cast<size_t>(cols.lo[s] + q)])] +=
            t[static_cast<size_t>(q)];
    }
  }
  return true;
}

bool CholeskySolver::solve_from_forward(const ForwardColumns& kept, std::span<const double> w,
                                        double* x, std::span<const double> z) const {
  CholeskyColumns* c = columns_of(factor_.get(), columns_);
  if (!c || kept.factor != c->factor || w.size() != kept.size ||
      (!z.empty() && z.size() != c->factor->n))
    return false;
  const cholmod_factor& l = *c->factor;
  const int n = static_cast<int>(l.n);
  const auto* super = static_cast<const int*>(l.super);
  const auto ns = static_cast<int>(l.nsuper);
  if (z.empty())
    c->y.assign(static_cast<size_t>(n), 0.0);
  else
    c->y.assign(z.begin(), z.end());
  c->e.resize(std::max<size_t>(1, l.maxesize));
  double* y = c->y.data();
  double* e = c->e.data();
  const double one = 1.0;
  const int inc = 1;
  // y += Y w, supernode by supernode: block s of a cover holds L⁻¹P E (rows of s's diagonal
  // block) for the cover's sorted columns [lo[s], hi[s]), which are T's offset + order[q].
  std::vector<double> ws;
  for (const auto& cover : kept.covers) {
    const auto& cols = cover.columns;
    for (int s = 0; s < ns; ++s) {
      const int cnt = cols.count(static_cast<size_t>(s));
      const auto& ys = cover.y[static_cast<size_t>(s)];
      if (cnt == 0 || ys.empty()) continue;
      ws.resize(static_cast<size_t>(cnt));
      for (int q = 0; q < cnt; ++q)
        ws[static_cast<size_t>(q)] =
            w[cover.offset + static_cast<size_t>(cols.order[static_cast<size_t>(
                                 cols.lo[static_cast<size_t>(s)] + q)])];
      const int nscol = super[s + 1] - super[s];
      dgemv_("N", &nscol, &cnt, &one, ys.data(), &nscol, ws.data(), &inc, &one, y + super[s], &inc);
    }
  }
  for (int s = ns - 1; s >= 0; --s) backward_one(l, s, y, e);  // L⁻ᵀ, every supernode
  for (int i = 0; i < n; ++i) x[i] = y[c->pinv[static_cast<size_t>(i)]];  // x = Pᵀ y
  return true;
}

#else

struct CholeskyColumns {};

struct ForwardColumns {};
void ForwardColumnsDeleter::operator()(ForwardColumns* y) const {
  delete y;
}
bool CholeskySolver::forward_compliance_pays(std::span<const PetscInt>, int) const {
  return false;
}
bool CholeskySolver::forward_compliance(ForwardColumnsPtr&, std::span<const PetscInt>,
                                        double*) const {
  return false;
}
bool CholeskySolver::forward_half(std::span<const double>, std::vector<double>&) const {
  return false;
}
bool CholeskySolver::forward_values(const ForwardColumns&, std::span<const double>,
                                    std::span<double>) const {
  return false;
}
bool CholeskySolver::solve_from_forward(const ForwardColumns&, std::span<const double>, double*,
                                        std::span<const double>) const {
  return false;
}

bool CholeskySolver::unit_solve_rows(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                                     double* out) const {
  if (!distributed()) return false;
  inverse_entries(cols, rows, out);
  return true;
}

#endif

}  // namespace tc::core
