// (A⁻¹)_TT by forward solves alone on CHOLMOD's supernodal factor (CholmodFactor::
// forward_compliance), the values (A⁻¹b)_T from a kept forward half (forward_values) and the
// solve finished from it (solve_from_forward): the dual set-up's forward solves
// (docs/theory.md). The factor is read through cholmod_factor's public fields.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "tc/core/numeric/blas.hpp"  // the BLAS that CHOLMOD calls: the same kernels, the same bits
#include "tc/linalg/cholmod/cholmod_supernodes.hpp"

namespace tc::linalg {

using supernodal::backward_one;
using supernodal::columns_of;
using supernodal::reach;

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

bool CholmodFactor::forward_compliance_pays(std::span<const PetscInt> dofs, int block) const {
  CholeskyColumns* c = columns_of(this, columns_);
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
  // Below `negligible` (a fraction of a second on one core at the level-3 BLAS rate) the
  // restricted solves cost next to nothing, and a switch would change the set-up's rounding for
  // no measurable time: they are kept there. Above it the fewer flops win, in time too
  // (bench/RESULTS.md, the 10⁶-dof plate), whether or not those stay below the factorisation.
  constexpr double negligible = 1e10;
  return restricted > negligible && forward < restricted;
}

void ForwardColumnsDeleter::operator()(ForwardColumns* y) const {
  delete y;
}

bool CholmodFactor::forward_compliance(ForwardColumnsPtr& kept, std::span<const PetscInt> fresh,
                                       double* out) const {
  CholeskyColumns* c = columns_of(this, columns_);
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

bool CholmodFactor::forward_values(const ForwardColumns& kept, std::span<const double> z,
                                   std::span<double> out) const {
  CholeskyColumns* c = columns_of(this, columns_);
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

bool CholmodFactor::solve_from_forward(const ForwardColumns& kept, std::span<const double> w,
                                       double* x, std::span<const double> z) const {
  CholeskyColumns* c = columns_of(this, columns_);
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

}  // namespace tc::linalg
