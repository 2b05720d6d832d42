#include "tc/linalg/cholmod/cholmod_factor.hpp"

#include <cholmod.h>
#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/core/verify.hpp"

namespace tc::linalg {

using core::KernelThreads;

static_assert(std::is_same_v<cholmod_factor_struct, cholmod_factor>);

struct CholmodFactor::State {
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  int n = 0;
  State() {
    cholmod_start(&common);
    // CHOLMOD prints its warnings and errors on stdout otherwise; the status is checked here
    // and turned into an exception.
    common.print = 0;
  }
  ~State() {
    cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
  State(const State&) = delete;
  State& operator=(const State&) = delete;
};

namespace {

/// The matrix as CHOLMOD takes a symmetric one: the entries on and above the diagonal of each
/// row i of the CSR, read as column i of the lower triangle (stype −1). This is what PETSc's
/// MATSOLVERCHOLMOD hands CHOLMOD for a sequential AIJ matrix, so the analysis sees the same
/// pattern in the same order and picks the same ordering and supernodes.
struct LowerColumns {
  std::vector<int> p, i;
  std::vector<double> x;
  cholmod_sparse view{};
  LowerColumns(::Mat a, std::span<const PetscInt> decoupled) {
    PetscInt n = 0;
    const PetscInt *ia = nullptr, *ja = nullptr;
    PetscBool done = PETSC_FALSE;
    TC_PETSC(MatGetRowIJ(a, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
    TC_VERIFY(done, "CholmodFactor needs a sequential AIJ matrix (its rows' structure)");
    const PetscScalar* va = nullptr;
    TC_PETSC(MatSeqAIJGetArrayRead(a, &va));
    TC_VERIFY(ia[n] <= std::numeric_limits<int>::max(),
              "the matrix's entries must fit CHOLMOD's int indices");
    std::vector<char> apart(decoupled.empty() ? 0 : static_cast<size_t>(n), 0);
    for (const PetscInt d : decoupled) apart[static_cast<size_t>(d)] = 1;
    const auto kept = [&](PetscInt r, PetscInt c, PetscScalar v) {  // c ≥ r
      return c == r || v != 0.0 || apart.empty() ||
             !(apart[static_cast<size_t>(r)] || apart[static_cast<size_t>(c)]);
    };
    p.resize(static_cast<size_t>(n) + 1);
    i.reserve(static_cast<size_t>(ia[n] + n) / 2);
    x.reserve(i.capacity());
    for (PetscInt r = 0; r < n; ++r) {
      p[static_cast<size_t>(r)] = static_cast<int>(i.size());
      for (PetscInt k = ia[r]; k < ia[r + 1]; ++k)
        if (ja[k] >= r && kept(r, ja[k], va[k])) {  // sorted: the diagonal, then the upper
          i.push_back(static_cast<int>(ja[k]));
          x.push_back(static_cast<double>(va[k]));
        }
    }
    p[static_cast<size_t>(n)] = static_cast<int>(i.size());
    view.nrow = view.ncol = static_cast<size_t>(n);  // before MatRestoreRowIJ clears n
    TC_PETSC(MatSeqAIJRestoreArrayRead(a, &va));
    TC_PETSC(MatRestoreRowIJ(a, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
    view.nzmax = i.size();
    view.p = p.data();
    view.i = i.data();
    view.x = x.data();
    view.stype = -1;
    view.itype = CHOLMOD_INT;
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    view.sorted = 1;
    view.packed = 1;
  }
};

/// A column-major n × k array seen as a CHOLMOD dense matrix (not owned).
cholmod_dense dense_view(const double* x, int n, int ld, int k) {
  cholmod_dense d{};
  d.nrow = static_cast<size_t>(n);
  d.ncol = static_cast<size_t>(k);
  d.d = static_cast<size_t>(ld);
  d.nzmax = d.d * d.ncol;
  d.x = const_cast<double*>(x);  // CHOLMOD's type has no const; B is only read
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

/// The factorisation's work for the thread policy, as CholeskySolver counts it for PETSc's
/// packages: n², a 3D body's nested-dissection flops.
double factorisation_flops(int n) {
  return static_cast<double>(n) * static_cast<double>(n);
}

}  // namespace

CholmodFactor::CholmodFactor(::Mat a) : CholmodFactor(a, {}) {}

CholmodFactor::CholmodFactor(::Mat a, const std::function<void()>& release,
                             std::span<const PetscInt> decoupled)
    : state_(std::make_unique<State>()) {
  auto& c = state_->common;
  LowerColumns lower(a, decoupled);
  if (release) release();  // `a` is not read again
  state_->n = static_cast<int>(lower.view.nrow);
  const KernelThreads threads(factorisation_flops(state_->n));
  state_->factor = cholmod_analyze(&lower.view, &c);
  if (!state_->factor)
    throw PetscError(PETSC_ERR_LIB,
                     fmt::format("CHOLMOD: cholmod_analyze failed (status {})", c.status));
  if (!cholmod_factorize(&lower.view, state_->factor, &c) || c.status < CHOLMOD_OK)
    throw PetscError(PETSC_ERR_LIB,
                     fmt::format("CHOLMOD: cholmod_factorize failed (status {})", c.status));
  if (c.status == CHOLMOD_NOT_POSDEF)  // the factor stops at the column where it fails
    throw PetscError(PETSC_ERR_MAT_CH_ZRPVT,
                     fmt::format("CHOLMOD: the matrix is not positive definite (column {} of {})",
                                 state_->factor->minor, state_->n));
}

CholmodFactor::~CholmodFactor() = default;

int CholmodFactor::size() const {
  return state_->n;
}

const cholmod_factor_struct& CholmodFactor::factor() const {
  return *state_->factor;
}

bool CholmodFactor::supernodal() const {
  const auto& l = *state_->factor;
  return l.is_super && l.is_ll && l.nsuper > 0 && l.itype == CHOLMOD_INT &&
         l.xtype == CHOLMOD_REAL && l.dtype == CHOLMOD_DOUBLE;
}

void CholmodFactor::solve(const double* b, int ldb, double* x, int ldx, int k) const {
  auto& c = state_->common;
  const int n = state_->n;
  if (k <= 0 || n == 0) return;
  cholmod_dense bv = dense_view(b, n, ldb, k);
  // CHOLMOD allocates X, Y and E itself (a caller's X would be freed and reallocated unless its
  // shape matched exactly); X is copied out, n·k doubles against the solve's work on L.
  cholmod_dense *xd = nullptr, *y = nullptr, *e = nullptr;
  const int ok = cholmod_solve2(CHOLMOD_A, state_->factor, &bv, nullptr, &xd, nullptr, &y, &e, &c);
  if (ok && xd) {
    const auto* from = static_cast<const double*>(xd->x);
    for (int j = 0; j < k; ++j)
      std::copy(from + static_cast<size_t>(j) * xd->d, from + static_cast<size_t>(j) * xd->d + n,
                x + static_cast<size_t>(j) * static_cast<size_t>(ldx));
  }
  cholmod_free_dense(&xd, &c);
  cholmod_free_dense(&y, &c);
  cholmod_free_dense(&e, &c);
  if (!ok)
    throw PetscError(PETSC_ERR_LIB,
                     fmt::format("CHOLMOD: cholmod_solve2 failed (status {})", c.status));
}

std::string cholmod_path() {
  int version[3] = {0, 0, 0};
  cholmod_version(version);
  return fmt::format(
      "{}.{}.{} (SuiteSparse {}.{}.{}) through its public API, built in: the factor on one rank "
      "unless another package is asked for; the dual set-up's restricted and forward solves on "
      "its supernodal factors",
      version[0], version[1], version[2], SUITESPARSE_MAIN_VERSION, SUITESPARSE_SUB_VERSION,
      SUITESPARSE_SUBSUB_VERSION);
}

}  // namespace tc::linalg
