#include "tc/linalg/cholmod/cholmod_analysis.hpp"

#include <cholmod.h>
#include <fmt/format.h>
#include <petscsys.h>

#include "tc/core/error.hpp"
#include "tc/core/verify.hpp"

namespace tc::linalg {

FactorAnalysis analyse_cholesky(const std::vector<int>& start, const std::vector<int>& column) {
  TC_VERIFY(!start.empty() && static_cast<size_t>(start.back()) == column.size(),
            "analyse_cholesky: start must end at the number of entries");
  cholmod_common c{};
  cholmod_start(&c);
  c.print = 0;
  // The defaults of CholmodFactor (its ordering: AMD, METIS where AMD fills too much), so the
  // analysis is the one its factorisation would make.
  cholmod_sparse a{};
  a.nrow = a.ncol = start.size() - 1;
  a.nzmax = column.size();
  a.p = const_cast<int*>(start.data());  // CHOLMOD's type has no const; A is only read
  a.i = const_cast<int*>(column.data());
  a.stype = -1;
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_PATTERN;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  cholmod_factor* l = cholmod_analyze(&a, &c);
  if (!l) {
    const int status = c.status;
    cholmod_finish(&c);
    throw PetscError(PETSC_ERR_LIB,
                     fmt::format("CHOLMOD: cholmod_analyze failed (status {})", status));
  }
  FactorAnalysis out;
  out.n = static_cast<double>(a.nrow);
  out.entries = c.lnz;
  out.flops = c.fl;
  if (l->is_super) {
    // x: xsize doubles; s: ssize ints; super, pi, px: nsuper + 1 each; Perm, ColCount: n.
    out.bytes = 8.0 * static_cast<double>(l->xsize) + 4.0 * static_cast<double>(l->ssize) +
                4.0 * 3.0 * static_cast<double>(l->nsuper + 1) + 8.0 * out.n;
    out.work_bytes = 8.0 * static_cast<double>(l->maxcsize);
  } else {  // simplicial: x and i per entry, p, nz, next, prev, Perm, ColCount per column
    out.bytes = 12.0 * c.lnz + 4.0 * 6.0 * out.n;
  }
  cholmod_free_factor(&l, &c);
  cholmod_finish(&c);
  return out;
}

}  // namespace tc::linalg
