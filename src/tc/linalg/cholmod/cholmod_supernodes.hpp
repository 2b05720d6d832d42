#pragma once
// The supernodal structure of a CHOLMOD factor (cholmod_factor.hpp) and the per-supernode
// steps of its solves, shared by the restricted solves (cholmod_columns.cpp) and the forward
// solves of the compliance (cholmod_forward.cpp). Private to linalg/cholmod/: only those two
// include it.
#include <cholmod.h>

#include <memory>
#include <span>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/linalg/cholmod/cholmod_factor.hpp"

namespace tc::linalg {

/// The supernodal structure the restricted solves need, built on first use.
struct CholeskyColumns {
  const cholmod_factor* factor = nullptr;
  std::vector<int> pinv;      // dof → permuted row
  std::vector<int> super_of;  // permuted row → supernode
  std::vector<int> parent;    // supernode → parent supernode, −1 at a root
  std::vector<char> mark;     // per supernode, work
  std::vector<double> y, e;   // n × k solution, maxesize × k update
};

namespace supernodal {

/// The columns' structure of `f`'s factor, built into `cache` on first use; nullptr without a
/// CHOLMOD factor or with a simplicial one (CHOLMOD's choice for the smallest matrices): the
/// callers then solve with dense right-hand sides.
CholeskyColumns* columns_of(const CholmodFactor* f, std::shared_ptr<CholeskyColumns>& cache);

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
void backward_one(const cholmod_factor& l, int s, double* y, double* e);
/// Supernode s's step of the forward solve y ← L⁻¹y for one right-hand side (permuted), with
/// CHOLMOD's calls: y_s ← L_11⁻¹ y_s, then E = y below the diagonal block, E −= L_21 y_s, and
/// E back into y. `e` holds at least the factor's maxesize entries.
void forward_one(const cholmod_factor& l, int s, double* y, double* e);
/// The supernodes of `dofs` (−1 skipped) and all their ancestors, ascending.
std::vector<int> reach(CholeskyColumns& c, std::span<const PetscInt> dofs);

}  // namespace supernodal
}  // namespace tc::linalg
