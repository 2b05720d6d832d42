// Columns of A⁻¹ on a few rows, for unit right-hand sides, from CHOLMOD's supernodal factor
// (CholeskySolver::unit_solve_rows). PETSc keeps the factor inside its CHOLMOD matrix type,
// whose layout is private: it is reached through the PETSc 3.14–3.18 layout and every field
// used is checked against the matrix before use; anything unexpected returns false and the
// caller solves with the dense right-hand sides instead.
#include <petsc/private/matimpl.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <vector>

#include "tc/core/petsc.hpp"

#if defined(TC_CHOLMOD_COLUMNS)  // cholmod.h and the BLAS found (CMakeLists.txt)
#include <cholmod.h>
#define TC_HAVE_CHOLMOD 1
#endif

namespace tc::core {

// PETSc's private layout is assumed for 3.14–3.18 only (run and tested here on 3.18.5); other
// versions compile the fallback.
#if defined(TC_HAVE_CHOLMOD) && !defined(PETSC_USE_64BIT_INDICES) && \
    !defined(PETSC_USE_COMPLEX) && PETSC_VERSION_GE(3, 14, 0) && PETSC_VERSION_LT(3, 19, 0)

extern "C" {
// The Fortran BLAS that CHOLMOD calls (the same library: the same kernels, the same bits).
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const double* alpha, const double* a, const int* lda, double* b,
            const int* ldb);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
            const double* beta, double* c, const int* ldc);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a,
            const int* lda, double* x, const int* incx);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a,
            const int* lda, const double* x, const int* incx, const double* beta, double* y,
            const int* incy);
}

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

CholeskyColumns* columns_of(::KSP ksp, std::shared_ptr<CholeskyColumns>& cache) {
  if (cache) return cache->factor ? cache.get() : nullptr;
  cache = std::make_shared<CholeskyColumns>();
  ::PC pc = nullptr;
  ::Mat f = nullptr;
  if (KSPGetPC(ksp, &pc) || PCFactorGetMatrix(pc, &f) || !f) return nullptr;
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
  CholeskyColumns* c = columns_of(ksp_.get(), columns_);
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
  const int inc = 1;
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
    gather_below(ps2, nsrow2);
    if (k == 1) {
      dtrsv_("L", "N", "N", &nscol, l1, &nsrow, y + k1, &inc);
      dgemv_("N", &nsrow2, &nscol, &minus_one, l1 + nscol, &nsrow, y + k1, &inc, &one, e, &inc);
    } else {
      dtrsm_("L", "L", "N", "N", &nscol, &k, &one, l1, &nsrow, y + k1, &n);
      if (nsrow2 > 0)
        dgemm_("N", "N", &nsrow2, &k, &nscol, &minus_one, l1 + nscol, &nsrow, y + k1, &n, &one, e,
               &nsrow2);
    }
    for (int ii = 0; ii < nsrow2; ++ii)
      for (int j = 0; j < k; ++j)
        y[static_cast<size_t>(ls[ps2 + ii]) + static_cast<size_t>(j) * n] = e[ii + j * nsrow2];
  }
  // Backward, Y = L⁻ᵀY, on the supernodes of the wanted rows and their ancestors (the rows
  // below a supernode's diagonal block belong to its ancestors), descending as CHOLMOD.
  const auto back = reach(*c, rows);
  for (auto it = back.rbegin(); it != back.rend(); ++it) {
    const int s = *it;
    const int k1 = super[s], nscol = super[s + 1] - k1;
    const int psi = lpi[s], nsrow = lpi[s + 1] - psi, nsrow2 = nsrow - nscol, ps2 = psi + nscol;
    const double* l1 = lx + lpx[s];
    gather_below(ps2, nsrow2);
    if (k == 1) {
      dgemv_("C", &nsrow2, &nscol, &minus_one, l1 + nscol, &nsrow, e, &inc, &one, y + k1, &inc);
      dtrsv_("L", "C", "N", &nscol, l1, &nsrow, y + k1, &inc);
    } else {
      if (nsrow2 > 0)
        dgemm_("C", "N", &nscol, &k, &nsrow2, &minus_one, l1 + nscol, &nsrow, e, &nsrow2, &one,
               y + k1, &n);
      dtrsm_("L", "L", "C", "N", &nscol, &k, &one, l1, &nsrow, y + k1, &n);
    }
  }
  const auto nr = rows.size();
  for (int j = 0; j < k; ++j)  // X = Pᵀ Y on the wanted rows
    for (size_t i = 0; i < nr; ++i)
      out[i + static_cast<size_t>(j) * nr] =
          y[static_cast<size_t>(c->pinv[static_cast<size_t>(rows[i])]) +
            static_cast<size_t>(j) * n];
  return true;
}

#else

struct CholeskyColumns {};

bool CholeskySolver::unit_solve_rows(std::span<const PetscInt>, std::span<const PetscInt>,
                                     double*) const {
  return false;
}

#endif

}  // namespace tc::core
