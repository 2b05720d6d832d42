// CholeskySolver: the choice of the package and one DirectFactor per package — CHOLMOD through
// its own API (cholmod/cholmod_factor.hpp), MUMPS or PETSc's own through a KSP on this rank, or
// MUMPS spread over the ranks (mumps_ranks.hpp).
#include "tc/linalg/cholesky_solver.hpp"

#include <algorithm>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc_blocks.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/core/verify.hpp"
#include "tc/linalg/cholmod/cholmod_factor.hpp"
#include "tc/linalg/mumps_ranks.hpp"

namespace tc::linalg {

using core::Handle;
using core::KernelThreads;
using core::SparseMatrix;
using core::Vector;

DirectFactor::~DirectFactor() = default;

namespace {

/// CHOLMOD's factor (CholmodFactor, SuiteSparse's public API) behind DirectFactor.
class CholmodDirect final : public DirectFactor {
 public:
  explicit CholmodDirect(::Mat a) : f_(a) {}
  CholmodDirect(::Mat a, const std::function<void()>& release, std::span<const PetscInt> decoupled)
      : f_(a, release, decoupled) {}
  void solve(::Vec b, ::Vec x) const override {
    const double* bv = nullptr;
    double* xv = nullptr;
    TC_PETSC(VecGetArrayRead(b, &bv));
    TC_PETSC(VecGetArrayWrite(x, &xv));
    const int n = f_.size();
    f_.solve(bv, n, xv, n, 1);
    TC_PETSC(VecRestoreArrayWrite(x, &xv));
    TC_PETSC(VecRestoreArrayRead(b, &bv));
  }
  void solve_many(::Mat b, ::Mat x) const override {
    PetscInt n = 0, k = 0, ldb = 0, ldx = 0;
    TC_PETSC(MatGetSize(b, &n, &k));
    TC_PETSC(MatDenseGetLDA(b, &ldb));
    TC_PETSC(MatDenseGetLDA(x, &ldx));
    const double* bv = nullptr;
    double* xv = nullptr;
    TC_PETSC(MatDenseGetArrayRead(b, &bv));
    TC_PETSC(MatDenseGetArrayWrite(x, &xv));
    f_.solve(bv, static_cast<int>(ldb), xv, static_cast<int>(ldx), static_cast<int>(k));
    TC_PETSC(MatDenseRestoreArrayWrite(x, &xv));
    TC_PETSC(MatDenseRestoreArrayRead(b, &bv));
  }
  [[nodiscard]] const CholmodFactor& factor() const { return f_; }

 private:
  CholmodFactor f_;
};

/// MUMPS or PETSc's own Cholesky on this rank, through PETSc: the factor a KSP (PREONLY,
/// PCCHOLESKY) made, kept without the KSP. MatSolve and MatMatSolve on it are what the KSP
/// calls: the same bits as solving through it.
class PetscDirect final : public DirectFactor {
 public:
  PetscDirect(const SparseMatrix& a, const std::string& package) {
    TC_PETSC(MatSetOption(a.get(), MAT_SYMMETRIC, PETSC_TRUE));
    TC_PETSC(MatSetOption(a.get(), MAT_SPD, PETSC_TRUE));
    // The KSP only factorises: the factor is kept and the KSP dropped, so that it no longer
    // holds a reference to `a` and the caller's copy of the matrix can be freed (a 3D body's
    // operator is about a tenth of its factor).
    Handle<::KSP, KSPDestroy> ksp;
    TC_PETSC(KSPCreate(PETSC_COMM_SELF, ksp.out()));
    TC_PETSC(KSPSetOperators(ksp.get(), a.get(), a.get()));
    TC_PETSC(KSPSetType(ksp.get(), KSPPREONLY));
    PC pc = nullptr;
    TC_PETSC(KSPGetPC(ksp.get(), &pc));
    TC_PETSC(PCSetType(pc, PCCHOLESKY));
    TC_PETSC(PCFactorSetMatSolverType(pc, package.c_str()));
    TC_PETSC(KSPSetErrorIfNotConverged(ksp.get(), PETSC_TRUE));
    {
      const KernelThreads threads(factorisation_flops(a.rows()));
      TC_PETSC(KSPSetUp(ksp.get()));  // the factorisation happens here, once
    }
    ::Mat f = nullptr;
    TC_PETSC(PCFactorGetMatrix(pc, &f));
    TC_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(f)));
    factor_ = Handle<::Mat, MatDestroy>(f);
  }
  void solve(::Vec b, ::Vec x) const override { TC_PETSC(MatSolve(factor_.get(), b, x)); }
  void solve_many(::Mat b, ::Mat x) const override { TC_PETSC(MatMatSolve(factor_.get(), b, x)); }

 private:
  Handle<::Mat, MatDestroy> factor_;
};

}  // namespace

double factorisation_flops(PetscInt n) {
  return static_cast<double>(n) * static_cast<double>(n);
}

std::vector<std::string> available_cholesky_packages() {
  // The packages register with Mat's initialisation, which nothing may have triggered yet.
  TC_PETSC(MatInitializePackage());
  // CHOLMOD is this project's own (CholmodFactor, required at configure time), first: the
  // automatic choice on one rank. The others are PETSc's.
  std::vector<std::string> out{MATSOLVERCHOLMOD};
  for (const char* p : {MATSOLVERMUMPS, MATSOLVERPETSC}) {
    PetscBool found = PETSC_FALSE;
    TC_PETSC(MatSolverTypeGet(p, MATSEQAIJ, MAT_FACTOR_CHOLESKY, &found, nullptr, nullptr));
    if (found) out.emplace_back(p);
  }
  return out;
}

std::string requested_factor_package() {
  char opt[64] = {};
  PetscBool set = PETSC_FALSE;
  TC_PETSC(PetscOptionsGetString(nullptr, nullptr, "-tc_factor_package", opt, sizeof opt, &set));
  return set ? std::string(opt) : std::string();
}

int ranks_sharing_a_factor(const std::string& package) {
  std::string asked = requested_factor_package();
  if (asked.empty()) asked = package;
  // Over ranks, the factor is MUMPS's unless a package that factorises on one rank only was
  // asked for: the same factorisation repeated on every rank divides nothing.
  if (!asked.empty() && asked != MATSOLVERMUMPS) return 1;
  int size = 1;
  TC_MPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  return size;
}

CholeskySolver::CholeskySolver(const SparseMatrix& a, const std::string& package,
                               FactorRanks ranks) {
  package_ = package;
  if (spread_over_ranks(ranks, a.distributed())) {
    keep(std::make_shared<const MumpsOverRanks>(a));
    return;
  }
  if (package_ == MATSOLVERCHOLMOD)
    keep(std::make_shared<const CholmodDirect>(a.get()));
  else
    keep(std::make_shared<const PetscDirect>(a, package_));
}

void CholeskySolver::keep(std::shared_ptr<const DirectFactor> f) {
  factor_ = std::move(f);
  const auto* c = dynamic_cast<const CholmodDirect*>(factor_.get());
  cholmod_ = c ? &c->factor() : nullptr;
  ranks_ = dynamic_cast<const MumpsOverRanks*>(factor_.get());
}

bool CholeskySolver::spread_over_ranks(FactorRanks ranks, bool spread_matrix) {
  // A matrix already spread over the ranks is factorised where it lies, by MUMPS.
  if (spread_matrix || (ranks == FactorRanks::all_ranks && ranks_sharing_a_factor(package_) > 1)) {
    package_ = MATSOLVERMUMPS;
    return true;
  }
  if (auto opt = requested_factor_package(); !opt.empty()) package_ = std::move(opt);
  if (package_.empty()) package_ = available_cholesky_packages().front();
  return false;
}

CholeskySolver::CholeskySolver(const SparseMatrix& a, std::span<const PetscInt> eliminated,
                               double diag, const std::string& package, FactorRanks ranks) {
  package_ = package;
  if (spread_over_ranks(ranks, a.distributed())) {
    keep(std::make_shared<const MumpsOverRanks>(a, eliminated, diag));
    return;
  }
  auto reduced = a.copy();  // freed once factorised: the factor keeps no reference to it
  reduced.zero_rows_columns(eliminated, diag);
  if (package_ == MATSOLVERCHOLMOD) {
    keep(std::make_shared<const CholmodDirect>(reduced.get(), nullptr, eliminated));
    return;
  }
  *this = CholeskySolver(reduced, package_, FactorRanks::this_rank);
}

CholeskySolver::CholeskySolver(SparseMatrix&& a, std::span<const PetscInt> eliminated, double diag,
                               const std::string& package, FactorRanks ranks) {
  package_ = package;
  if (spread_over_ranks(ranks, a.distributed())) {
    keep(std::make_shared<const MumpsOverRanks>(a, eliminated, diag));
    return;
  }
  a.zero_rows_columns(eliminated, diag);
  if (package_ == MATSOLVERCHOLMOD) {
    keep(std::make_shared<const CholmodDirect>(
        a.get(), [&a] { a = SparseMatrix{}; }, eliminated));
    return;
  }
  *this = CholeskySolver(a, package_, FactorRanks::this_rank);
}

void CholeskySolver::solve(const Vector& b, Vector& x) const {
  // A⁻¹0 = 0 without reading the factor (the solve's own result, +0 everywhere): a body at rest
  // with no load, before a touch, would otherwise be solved at every coupling iteration. Over
  // the ranks b is replicated; they agree all the same before leaving a collective solve.
  int zero = 1;  // every entry == 0 (a NaN is not: it goes to the solve, and on to the checks)
  {
    const auto bv = b.read();
    for (const double e : bv.span())
      if (e != 0.0) {
        zero = 0;
        break;
      }
  }
  if (ranks_) TC_MPI(MPI_Allreduce(MPI_IN_PLACE, &zero, 1, MPI_INT, MPI_LAND, ranks_->comm()));
  if (zero) {
    x.zero();
    return;
  }
  solve_raw(b.get(), x.get());
}

void CholeskySolver::solve_raw(::Vec b, ::Vec x) const {
  TC_VERIFY(factor_ != nullptr, "a solve with a factor");
  TC_VERIFY(b != x, "MatSolve and CHOLMOD need distinct vectors");
  factor_->solve(b, x);
}

void CholeskySolver::solve_many(::Mat b, ::Mat x) const {
  TC_VERIFY(factor_ != nullptr, "a solve with a factor");
  factor_->solve_many(b, x);
}

void CholeskySolver::selected_inverse(std::span<const PetscInt> cols,
                                      std::span<const PetscInt> rows, double* out) const {
  TC_VERIFY(ranks_ != nullptr, "the selected inverse is MUMPS's over the ranks");
  ranks_->selected_inverse(cols, rows, out);
}

}  // namespace tc::linalg
