// Columns of A⁻¹ on a few rows, for unit right-hand sides, from CHOLMOD's supernodal factor
// (CholmodFactor::unit_solve_rows), and the forward half of a solve (forward_half), each
// supernode with CHOLMOD's own BLAS calls in CHOLMOD's order. The factor is this project's
// (cholmod_factor.hpp, SuiteSparse's public API), read through cholmod_factor's public
// fields.
#include <algorithm>
#include <memory>
#include <vector>

#include "tc/core/numeric/blas.hpp"  // the BLAS that CHOLMOD calls: the same kernels, the same bits
#include "tc/core/verify.hpp"
#include "tc/linalg/cholmod/cholmod_supernodes.hpp"

namespace tc::linalg {
namespace supernodal {

CholeskyColumns* columns_of(const CholmodFactor* f, std::shared_ptr<CholeskyColumns>& cache) {
  if (cache) return cache->factor ? cache.get() : nullptr;
  cache = std::make_shared<CholeskyColumns>();
  if (!f || !f->supernodal()) return nullptr;  // another package, or a simplicial factor
  const cholmod_factor* l = &f->factor();
  const int n = f->size();
  auto& c = *cache;
  const auto* perm = static_cast<const int*>(l->Perm);
  const auto* super = static_cast<const int*>(l->super);
  const auto* lpi = static_cast<const int*>(l->pi);
  const auto* ls = static_cast<const int*>(l->s);
  const auto ns = static_cast<int>(l->nsuper);
  c.pinv.assign(static_cast<size_t>(n), -1);
  for (int k = 0; k < n; ++k) c.pinv[static_cast<size_t>(perm[k])] = k;
  TC_VERIFY(super[0] == 0 && super[ns] == n, "CHOLMOD's supernodes cover the columns");
  c.super_of.assign(static_cast<size_t>(n), -1);
  for (int s = 0; s < ns; ++s)
    for (int k = super[s]; k < super[s + 1]; ++k) c.super_of[static_cast<size_t>(k)] = s;
  c.parent.assign(static_cast<size_t>(ns), -1);
  for (int s = 0; s < ns; ++s) {  // the first row below the diagonal block names the parent
    const int nscol = super[s + 1] - super[s];
    if (lpi[s + 1] - lpi[s] > nscol) {
      const int p = c.super_of[static_cast<size_t>(ls[lpi[s] + nscol])];
      // CHOLMOD numbers the supernodes in a postorder of their tree: the ascending forward
      // and descending backward passes, and the postorder of cholmod_forward.cpp, rely on it.
      TC_VERIFY(p > s, "CHOLMOD's supernodes are in topological order");
      c.parent[static_cast<size_t>(s)] = p;
    }
  }
  c.mark.assign(static_cast<size_t>(ns), 0);
  c.factor = l;
  return cache.get();
}

void backward_one(const cholmod_factor& l, int s, double* y, double* e) {
  const Supernode n(l, s);
  const double one = 1.0, minus_one = -1.0;
  const int inc = 1;
  for (int ii = 0; ii < n.nsrow2; ++ii) e[ii] = y[n.ls[n.ps2 + ii]];
  dgemv_("C", &n.nsrow2, &n.nscol, &minus_one, n.l1 + n.nscol, &n.nsrow, e, &inc, &one, y + n.k1,
         &inc);
  dtrsv_("L", "C", "N", &n.nscol, n.l1, &n.nsrow, y + n.k1, &inc);
}

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

}  // namespace supernodal

using supernodal::backward_one;
using supernodal::columns_of;
using supernodal::forward_one;
using supernodal::reach;

bool CholmodFactor::unit_solve_rows(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                                    double* out) const {
  CholeskyColumns* c = columns_of(this, columns_);
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

bool CholmodFactor::forward_half(std::span<const double> b, std::vector<double>& z) const {
  CholeskyColumns* c = columns_of(this, columns_);
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

}  // namespace tc::linalg
