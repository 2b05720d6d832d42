#include "tc/core/petsc.hpp"

#include <fmt/format.h>
#include <malloc.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iterator>

#include "tc/core/cholmod_factor.hpp"
#include "tc/core/collective.hpp"
#include "tc/core/error.hpp"
#include "tc/core/threads.hpp"
#include "tc/core/verify.hpp"

namespace tc::core {

void check_petsc(PetscErrorCode code, const char* call, const char* file, int line) {
  if (code == 0) return;
  const char* text = nullptr;
  (void)PetscErrorMessage(code, &text, nullptr);
  // The source file relative to the project (src/tc/…): not the build machine's directories.
  const char* project = std::strstr(file, "src/tc/");
  throw PetscError(code, fmt::format("PETSc call failed: {} ({}:{}): {} (error {})", call,
                                     project ? project : file, line, text ? text : "unknown error",
                                     static_cast<int>(code)));
}

namespace {
/// The heap on transparent huge pages. In a fresh process the first assembly and
/// factorisations touch their memory 4 KiB page by page, and on the 2-core VM those faults
/// were half of the set-up (example 05: 0.42 s in a fresh process, 0.22 s when a first run
/// had left its pages in the heap). glibc grows its heap by sbrk: with a large top pad it
/// grows once, by a range that madvise then marks for 2 MiB pages where the kernel's THP mode
/// is "madvise" (as GLIBC_TUNABLES=glibc.malloc.hugetlb=1 would, had it been set before the
/// process started). Allocations up to 32 MiB (glibc's largest threshold) come from that heap;
/// past the pad the heap grows on ordinary pages. Only address space is reserved: pages are
/// backed when touched.
void prefer_huge_pages() {
#if defined(__GLIBC__) && defined(MADV_HUGEPAGE)
  // Not under an address-space limit (ulimit -v): glibc asks for the pad with every growth of
  // the heap, by mmap too when sbrk fails, so every allocation that grew the heap failed once
  // the pad no longer fit (Open MPI's "out of dynamic memory" at MPI_Init under
  // `ulimit -v 600000`; issue 42, D19).
  if (rlimit as{}; getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) return;
  constexpr std::size_t huge = std::size_t{2} << 20;
  constexpr int pad = 512 << 20;
  if (mallopt(M_MMAP_THRESHOLD, 32 << 20) == 0 || mallopt(M_TOP_PAD, pad) == 0 ||
      mallopt(M_TRIM_THRESHOLD, 2 * pad) == 0)
    return;
  // The top chunk is the free end of the heap: the probe asks for more than it holds, so the
  // heap grows (by the probe and the pad), and the range marked is the old top and the growth.
  const std::size_t top = mallinfo2().keepcost;
  auto* end_before = static_cast<char*>(sbrk(0));
  void* probe = top + huge < (std::size_t{32} << 20) ? std::malloc(top + huge) : nullptr;
  auto* end_after = static_cast<char*>(sbrk(0));
  std::free(probe);
  const auto lo = (reinterpret_cast<std::uintptr_t>(end_before - top) + huge - 1) & ~(huge - 1);
  const auto hi = reinterpret_cast<std::uintptr_t>(end_after) & ~(huge - 1);
  if (hi > lo) (void)madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
#endif
}

/// Open MPI's transport defaults for a process that no launcher started (a serial run from a
/// shell): without them MPI_Init of a singleton starts a PMIx server and probes every
/// transport, 0.3 s of a 0.5 s `thermocontact info` on the 2-core VM (0.2 s with them). A
/// singleton has one rank, so it needs no server and only the self and shared-memory
/// transports. Set before MPI_Init, never over a value the user set, and not at all under
/// mpirun, whose ranks carry OMPI_COMM_WORLD_SIZE (or PMIX_RANK): their transports are the
/// user's and the cluster's choice.
void singleton_transport_defaults() {
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(launched)) return;
  setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  // Every isolated singleton takes the same job name ([0,1]), hence the same session
  // directory /tmp/ompi.<host>.<uid>/jf.0/1: two serial runs started together race, one
  // removing it at MPI_Finalize while the other creates it, and MPI_Init aborts ("A call to
  // mkdir was unable to create …"; 2 of 320 concurrent `info` runs on the 2-core VM). One
  // rank with the self and vader transports keeps nothing there, so no run makes one.
  setenv("OMPI_MCA_orte_create_session_dirs", "0", 0);
  setenv("OMPI_MCA_pml", "ob1", 0);
  setenv("OMPI_MCA_btl", "self,vader", 0);
  // hwloc's OpenGL component looks for X displays (connects to :0 … :N and localhost:6000+)
  // to find GPUs: nothing a solver uses.
  setenv("HWLOC_COMPONENTS", "-gl", 0);
}
}  // namespace

int PetscSession::node_size_ = 1;

PetscSession::PetscSession(int* argc, char*** argv) {
  prefer_huge_pages();
  singleton_transport_defaults();
  TC_PETSC(PetscInitialize(argc, argv, nullptr, nullptr));
  // Errors come back as codes, turned into exceptions by TC_PETSC; no traceback spam.
  TC_PETSC(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  // Collective, so here where every rank passes, not on the first call of node_size().
  MPI_Comm node = MPI_COMM_NULL;
  if (MPI_Comm_split_type(PETSC_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node) ==
          MPI_SUCCESS &&
      node != MPI_COMM_NULL) {
    int n = 1;
    if (MPI_Comm_size(node, &n) == MPI_SUCCESS) node_size_ = n;
    MPI_Comm_free(&node);
  }
  ThreadPolicy::start(node_size_, size());
}

PetscSession::~PetscSession() {
  (void)PetscPopErrorHandler();
  (void)PetscFinalize();
}

int PetscSession::rank() {
  PetscMPIInt r = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

int PetscSession::node_size() {
  return node_size_;
}

int PetscSession::blas_threads() {
  return ThreadPolicy::outside_kernels();
}

int PetscSession::size() {
  PetscMPIInt s = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &s);
  return s;
}

// ---------------------------------------------------------------------------- Vector

Vector::Vector(PetscInt n) {
  TC_PETSC(VecCreateSeq(PETSC_COMM_SELF, n, v_.out()));
  TC_PETSC(VecSet(v_.get(), 0.0));
}

Vector Vector::from(std::span<const double> values) {
  Vector v(static_cast<PetscInt>(values.size()));
  auto view = v.view();
  std::copy(values.begin(), values.end(), view.span().begin());
  return v;
}

Vector Vector::distributed(MPI_Comm comm, PetscInt local_size) {
  Vector v;
  TC_PETSC(VecCreateMPI(comm, local_size, PETSC_DETERMINE, v.v_.out()));
  TC_PETSC(VecSet(v.get(), 0.0));
  return v;
}

Vector Vector::adopt(::Vec v) {
  Vector out;
  *out.v_.out() = v;
  return out;
}

PetscInt Vector::size() const {
  PetscInt n = 0;
  TC_PETSC(VecGetSize(get(), &n));
  return n;
}

PetscInt Vector::local_size() const {
  PetscInt n = 0;
  TC_PETSC(VecGetLocalSize(get(), &n));
  return n;
}

MPI_Comm Vector::comm() const {
  return PetscObjectComm(reinterpret_cast<PetscObject>(get()));
}

Vector Vector::clone() const {
  Vector c = duplicate();
  TC_PETSC(VecCopy(get(), c.get()));
  return c;
}

Vector Vector::duplicate() const {
  Vector c;
  TC_PETSC(VecDuplicate(get(), c.v_.out()));
  TC_PETSC(VecSet(c.get(), 0.0));
  return c;
}

void Vector::zero() {
  TC_PETSC(VecSet(get(), 0.0));
}
void Vector::fill(double value) {
  TC_PETSC(VecSet(get(), value));
}
void Vector::copy_from(const Vector& other) {
  TC_PETSC(VecCopy(other.get(), get()));
}
void Vector::axpy(double a, const Vector& x) {
  TC_PETSC(VecAXPY(get(), a, x.get()));
}
void Vector::scale(double a) {
  TC_PETSC(VecScale(get(), a));
}
void Vector::shift(double a) {
  TC_PETSC(VecShift(get(), a));
}

double Vector::dot(const Vector& other) const {
  PetscScalar d = 0;
  TC_PETSC(VecDot(get(), other.get(), &d));
  return d;
}

double Vector::norm() const {
  PetscReal n = 0;
  TC_PETSC(VecNorm(get(), NORM_2, &n));
  return n;
}

double Vector::sum() const {
  PetscScalar s = 0;
  TC_PETSC(VecSum(get(), &s));
  return s;
}

double Vector::max_abs() const {
  PetscReal n = 0;
  TC_PETSC(VecNorm(get(), NORM_INFINITY, &n));
  return n;
}

std::vector<double> Vector::to_std() const {
  auto r = read();
  return {r.span().begin(), r.span().end()};
}

bool Vector::all_finite() const {
  // NaN propagates through the sum of |x_i| and Inf stays Inf: one collective reduction.
  PetscReal n1 = 0;
  TC_PETSC(VecNorm(get(), NORM_1, &n1));
  return std::isfinite(n1);
}

Vector::View::View(::Vec v) : v_(v) {
  TC_PETSC(VecGetArray(v_, &data_));
  TC_PETSC(VecGetLocalSize(v_, &n_));
}

Vector::View::~View() {
  (void)VecRestoreArray(v_, &data_);
}

Vector::ReadView::ReadView(::Vec v) : v_(v) {
  TC_PETSC(VecGetArrayRead(v_, &data_));
  TC_PETSC(VecGetLocalSize(v_, &n_));
}

Vector::ReadView::~ReadView() {
  (void)VecRestoreArrayRead(v_, &data_);
}

// ------------------------------------------------------------------------- RowBlocks

#define TC_MPI(call) check_mpi((call), #call)

RowBlocks RowBlocks::over(MPI_Comm comm, PetscInt n) {
  RowBlocks r;
  r.comm = comm;
  r.n = n;
  int size = 1;
  TC_MPI(MPI_Comm_size(comm, &size));
  TC_MPI(MPI_Comm_rank(comm, &r.rank));
  r.count.resize(static_cast<size_t>(size));
  r.start.resize(static_cast<size_t>(size));
  for (int q = 0, at = 0; q < size; ++q) {
    r.count[static_cast<size_t>(q)] = static_cast<int>(n / size + (q < n % size ? 1 : 0));
    r.start[static_cast<size_t>(q)] = at;
    at += r.count[static_cast<size_t>(q)];
  }
  return r;
}

void RowBlocks::gather(double* x) const {
  TC_MPI(MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, x, count.data(), start.data(),
                        MPIU_SCALAR, comm));
}

namespace {

// This rank's block of a replicated array as a vector of the spread layout: nothing copied.
Handle<::Vec, VecDestroy> block_view(const RowBlocks& r, const double* data) {
  Handle<::Vec, VecDestroy> v;
  TC_PETSC(VecCreateMPIWithArray(r.comm, 1, r.here(), r.n, data + r.first(), v.out()));
  return v;
}

// op(x_block, y_block) on this rank's blocks of the replicated x (dealt in rx) and y (in ry),
// then y gathered: a product, a solve or CG on a matrix or factor spread over the ranks.
template <class Op>
void on_blocks(const RowBlocks& rx, const RowBlocks& ry, ::Vec x, ::Vec y, Op op) {
  const PetscScalar* xp = nullptr;
  PetscScalar* yp = nullptr;
  TC_PETSC(VecGetArrayRead(x, &xp));
  TC_PETSC(VecGetArray(y, &yp));
  {
    const auto xl = block_view(rx, xp);
    const auto yl = block_view(ry, yp);
    op(xl.get(), yl.get());
  }
  ry.gather(yp);
  TC_PETSC(VecRestoreArray(y, &yp));
  TC_PETSC(VecRestoreArrayRead(x, &xp));
}

}  // namespace

// ---------------------------------------------------------------------- SparseMatrix

SparseMatrix::SparseMatrix(PetscInt rows, PetscInt cols, std::span<const PetscInt> nnz_per_row) {
  TC_PETSC(MatCreateSeqAIJ(PETSC_COMM_SELF, rows, cols, 0, nnz_per_row.data(), m_.out()));
  // Exact preallocation is a promise: a missing entry is a bug, not a slow path.
  TC_PETSC(MatSetOption(get(), MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
}

SparseMatrix SparseMatrix::over_ranks(const RowBlocks& rows, const RowBlocks& cols,
                                      std::span<const PetscInt> diagonal,
                                      std::span<const PetscInt> off_diagonal) {
  TC_VERIFY(rows.spread() && cols.comm == rows.comm &&
                diagonal.size() == static_cast<size_t>(rows.here()) &&
                off_diagonal.size() == diagonal.size(),
            "a spread matrix is preallocated for each of this rank's rows");
  SparseMatrix a;
  a.blocks_ = rows;
  a.col_blocks_ = cols;
  TC_PETSC(MatCreate(rows.comm, a.m_.out()));
  TC_PETSC(MatSetSizes(a.get(), rows.here(), cols.here(), rows.n, cols.n));
  TC_PETSC(MatSetType(a.get(), MATMPIAIJ));
  TC_PETSC(MatMPIAIJSetPreallocation(a.get(), 0, diagonal.data(), 0, off_diagonal.data()));
  TC_PETSC(MatSetOption(a.get(), MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  TC_PETSC(MatSetOption(a.get(), MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE));  // add_values filters
  return a;
}

PetscInt SparseMatrix::rows() const {
  PetscInt m = 0, n = 0;
  TC_PETSC(MatGetSize(get(), &m, &n));
  return m;
}

PetscInt SparseMatrix::cols() const {
  PetscInt m = 0, n = 0;
  TC_PETSC(MatGetSize(get(), &m, &n));
  return n;
}

void SparseMatrix::add_values(std::span<const PetscInt> rows, std::span<const PetscInt> cols,
                              const double* row_major_block) {
  if (distributed()) {  // this rank's rows only: nothing is sent at assembly
    const auto n = static_cast<PetscInt>(cols.size());
    for (size_t i = 0; i < rows.size(); ++i)
      if (blocks_.owns(rows[i]))
        TC_PETSC(MatSetValues(get(), 1, &rows[i], n, cols.data(), row_major_block + i * cols.size(),
                              ADD_VALUES));
    return;
  }
  TC_PETSC(MatSetValues(get(), static_cast<PetscInt>(rows.size()), rows.data(),
                        static_cast<PetscInt>(cols.size()), cols.data(), row_major_block,
                        ADD_VALUES));
}

void SparseMatrix::assemble() {
  TC_PETSC(MatAssemblyBegin(get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(get(), MAT_FINAL_ASSEMBLY));
}

SparseMatrix SparseMatrix::copy() const {
  SparseMatrix c;
  TC_PETSC(MatDuplicate(get(), MAT_COPY_VALUES, c.m_.out()));
  c.blocks_ = blocks_;
  c.col_blocks_ = col_blocks_;
  return c;
}

SparseMatrix SparseMatrix::share() const {
  TC_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(get())));
  SparseMatrix s;
  *s.m_.out() = get();
  s.blocks_ = blocks_;
  s.col_blocks_ = col_blocks_;
  return s;
}

void SparseMatrix::mult(const Vector& x, Vector& y) const {
  if (distributed())
    return on_blocks(col_blocks_, blocks_, x.get(), y.get(),
                     [&](::Vec xl, ::Vec yl) { TC_PETSC(MatMult(get(), xl, yl)); });
  TC_PETSC(MatMult(get(), x.get(), y.get()));
}
void SparseMatrix::mult_add(const Vector& x, Vector& y) const {
  if (distributed())
    return on_blocks(col_blocks_, blocks_, x.get(), y.get(),
                     [&](::Vec xl, ::Vec yl) { TC_PETSC(MatMultAdd(get(), xl, yl, yl)); });
  TC_PETSC(MatMultAdd(get(), x.get(), y.get(), y.get()));
}
void SparseMatrix::mult_transpose(const Vector& x, Vector& y) const {
  if (distributed())
    return on_blocks(blocks_, col_blocks_, x.get(), y.get(),
                     [&](::Vec xl, ::Vec yl) { TC_PETSC(MatMultTranspose(get(), xl, yl)); });
  TC_PETSC(MatMultTranspose(get(), x.get(), y.get()));
}
void SparseMatrix::mult_transpose_add(const Vector& x, Vector& y) const {
  if (distributed())
    return on_blocks(blocks_, col_blocks_, x.get(), y.get(),
                     [&](::Vec xl, ::Vec yl) { TC_PETSC(MatMultTransposeAdd(get(), xl, yl, yl)); });
  TC_PETSC(MatMultTransposeAdd(get(), x.get(), y.get(), y.get()));
}
void SparseMatrix::axpy(double a, const SparseMatrix& x) {
  TC_PETSC(MatAXPY(get(), a, x.get(), SAME_NONZERO_PATTERN));
}
void SparseMatrix::scale(double a) {
  TC_PETSC(MatScale(get(), a));
}

void SparseMatrix::zero_rows_columns(std::span<const PetscInt> rows, double diag) {
  std::vector<PetscInt> here;  // spread: each rank names its own rows (collective)
  if (distributed())
    std::copy_if(rows.begin(), rows.end(), std::back_inserter(here),
                 [&](PetscInt r) { return blocks_.owns(r); });
  const std::span<const PetscInt> named = distributed() ? std::span<const PetscInt>(here) : rows;
  TC_PETSC(MatZeroRowsColumns(get(), static_cast<PetscInt>(named.size()), named.data(), diag,
                              nullptr, nullptr));
}

double SparseMatrix::quadratic_form(const Vector& x, Vector& work) const {
  mult(x, work);
  return x.dot(work);
}

double mean_diagonal(const SparseMatrix& a) {
  Vector d = a.distributed() ? Vector::distributed(a.row_blocks().comm, a.row_blocks().here())
                             : Vector(a.rows());
  TC_PETSC(MatGetDiagonal(a.get(), d.get()));
  const double mean = d.sum() / static_cast<double>(a.rows());
  return mean > 0 ? mean : 1.0;
}

// -------------------------------------------------------------------- CholeskySolver

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

namespace {
/// The work of factorising n rows, for the thread policy: n², nested dissection's flops for a
/// 3D body (a 2D body's n^1.5 are fewer: it may get threads it could do without, never the
/// reverse). 10⁴ rows (a 3D body's 0.4 s on one core) sit at the threshold.
double factorisation_flops(PetscInt n) {
  return static_cast<double>(n) * static_cast<double>(n);
}
}  // namespace

CholeskySolver::CholeskySolver(const SparseMatrix& a, const std::string& package,
                               FactorRanks ranks) {
  package_ = package;
  if (spread_over_ranks(ranks, a.distributed())) {
    factor_over_ranks(a);
    return;
  }

  if (package_ == MATSOLVERCHOLMOD) {
    cholmod_ = std::make_shared<const CholmodFactor>(a.get());
    return;
  }
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
  TC_PETSC(PCFactorSetMatSolverType(pc, package_.c_str()));
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
    factor_over_ranks(a, eliminated, diag);
    return;
  }
  auto reduced = a.copy();  // freed once factorised: the factor keeps no reference to it
  reduced.zero_rows_columns(eliminated, diag);
  *this = CholeskySolver(reduced, package_, FactorRanks::this_rank);
}

// MatSolve and MatMatSolve on the factor are what KSPPREONLY with PCCHOLESKY calls: the same
// bits as solving through the KSP.
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
  if (distributed()) TC_MPI(MPI_Allreduce(MPI_IN_PLACE, &zero, 1, MPI_INT, MPI_LAND, ranks_.comm));
  if (zero) {
    x.zero();
    return;
  }
  solve_raw(b.get(), x.get());
}

void CholeskySolver::solve_raw(::Vec b, ::Vec x) const {
  TC_VERIFY(b != x, "MatSolve and CHOLMOD need distinct vectors");
  if (distributed()) {
    solve_over_ranks(b, x);
    return;
  }
  if (cholmod_) {
    const double* bv = nullptr;
    double* xv = nullptr;
    TC_PETSC(VecGetArrayRead(b, &bv));
    TC_PETSC(VecGetArrayWrite(x, &xv));
    const int n = cholmod_->size();
    cholmod_->solve(bv, n, xv, n, 1);
    TC_PETSC(VecRestoreArrayWrite(x, &xv));
    TC_PETSC(VecRestoreArrayRead(b, &bv));
    return;
  }
  TC_PETSC(MatSolve(factor_.get(), b, x));
}

void CholeskySolver::solve_many(::Mat b, ::Mat x) const {
  if (distributed()) {
    solve_many_over_ranks(b, x);
    return;
  }
  if (cholmod_) {
    PetscInt n = 0, k = 0, ldb = 0, ldx = 0;
    TC_PETSC(MatGetSize(b, &n, &k));
    TC_PETSC(MatDenseGetLDA(b, &ldb));
    TC_PETSC(MatDenseGetLDA(x, &ldx));
    const double* bv = nullptr;
    double* xv = nullptr;
    TC_PETSC(MatDenseGetArrayRead(b, &bv));
    TC_PETSC(MatDenseGetArrayWrite(x, &xv));
    cholmod_->solve(bv, static_cast<int>(ldb), xv, static_cast<int>(ldx), static_cast<int>(k));
    TC_PETSC(MatDenseRestoreArrayWrite(x, &xv));
    TC_PETSC(MatDenseRestoreArrayRead(b, &bv));
    return;
  }
  TC_PETSC(MatMatSolve(factor_.get(), b, x));
}

// ------------------------------------------------------- CholeskySolver over the ranks

void CholeskySolver::factor_over_ranks(const SparseMatrix& a, std::span<const PetscInt> eliminated,
                                       double diag) {
  auto& r = ranks_;
  r = RowBlocks::over(PETSC_COMM_WORLD, a.rows());
  const int size = static_cast<int>(r.count.size());
  // A matrix spread over the ranks is spread as the factor is (the same rule).
  TC_VERIFY(!a.distributed() ||
                (a.row_blocks().first() == r.first() && a.row_blocks().here() == r.here()),
            "a spread matrix is spread as its factor");
  const PetscInt first = r.first();
  const PetscInt m = r.here();

  // This rank's rows (of the replicated matrix, or its own), global columns, as an MPIAIJ.
  Handle<::Mat, MatDestroy> local;
  {
    // The eliminated rows keep diag alone, the other rows lose the eliminated columns.
    std::vector<char> gone(static_cast<size_t>(r.n), 0);
    for (const PetscInt d : eliminated) gone[static_cast<size_t>(d)] = 1;
    std::vector<PetscInt> offsets(static_cast<size_t>(m) + 1, 0), columns;
    std::vector<PetscScalar> values;
    PetscInt entries = 0;  // reserved exactly: the copy is as large as this rank's rows
    for (PetscInt row = first; row < first + m; ++row) {
      PetscInt nz = 0;
      TC_PETSC(MatGetRow(a.get(), row, &nz, nullptr, nullptr));
      entries += nz;
      TC_PETSC(MatRestoreRow(a.get(), row, &nz, nullptr, nullptr));
    }
    columns.reserve(static_cast<size_t>(entries));
    values.reserve(static_cast<size_t>(entries));
    for (PetscInt i = 0; i < m; ++i) {
      const PetscInt row = first + i;
      if (gone[static_cast<size_t>(row)]) {
        columns.push_back(row);
        values.push_back(diag);
      } else {
        PetscInt nz = 0;
        const PetscInt* cols = nullptr;
        const PetscScalar* vals = nullptr;
        TC_PETSC(MatGetRow(a.get(), row, &nz, &cols, &vals));  // columns in increasing order
        for (PetscInt e = 0; e < nz; ++e)
          if (!gone[static_cast<size_t>(cols[e])]) {
            columns.push_back(cols[e]);
            values.push_back(vals[e]);
          }
        TC_PETSC(MatRestoreRow(a.get(), row, &nz, &cols, &vals));
      }
      offsets[static_cast<size_t>(i) + 1] = static_cast<PetscInt>(columns.size());
    }
    TC_PETSC(MatCreateMPIAIJWithArrays(r.comm, m, m, r.n, r.n, offsets.data(), columns.data(),
                                       values.data(), local.out()));
  }
  TC_PETSC(MatSetOption(local.get(), MAT_SYMMETRIC, PETSC_TRUE));
  TC_PETSC(MatSetOption(local.get(), MAT_SPD, PETSC_TRUE));
  // MUMPS allocates its estimate of the factorisation's work space plus ICNTL(14) per cent
  // (20 % on more than one rank). Cholesky of an SPD matrix delays no pivot, so only the
  // ranks' dynamic scheduling can exceed the estimate: 10 % first (the 200 k-dof ch. 7 case at
  // 2 ranks: 1.50 → 1.43 GiB per rank; 5 % ran out in 4 runs of 5), and when MUMPS reports a
  // work space too small (INFOG(1) −8, −9, −11, −12, −14, −15, −17), once more with 35 %.
  const KernelThreads threads(factorisation_flops(r.n) / size);
  for (const PetscInt relaxation : {10, 35}) {
    ::Mat f = nullptr;
    TC_PETSC(MatGetFactor(local.get(), MATSOLVERMUMPS, MAT_FACTOR_CHOLESKY, &f));
    factor_ = Handle<::Mat, MatDestroy>(f);
    TC_PETSC(MatMumpsSetIcntl(f, 14, relaxation));
    MatFactorInfo info;
    TC_PETSC(MatFactorInfoInitialize(&info));
    TC_PETSC(MatCholeskyFactorSymbolic(f, local.get(), nullptr, &info));
    MatFactorError error = MAT_FACTOR_NOERROR;
    TC_PETSC(MatFactorGetError(f, &error));
    if (error == MAT_FACTOR_NOERROR) {
      TC_PETSC(MatCholeskyFactorNumeric(f, local.get(), &info));
      TC_PETSC(MatFactorGetError(f, &error));
    }
    if (error == MAT_FACTOR_NOERROR) return;
    PetscInt infog1 = 0;
    TC_PETSC(MatMumpsGetInfog(f, 1, &infog1));
    const bool work_space = infog1 == -8 || infog1 == -9 || infog1 == -11 || infog1 == -12 ||
                            infog1 == -14 || infog1 == -15 || infog1 == -17;
    if (work_space && relaxation == 10) continue;
    // Every rank has the same INFOG: a collective error, reported once.
    throw CollectiveError<PetscError>(PetscError(
        PETSC_ERR_LIB, fmt::format("MUMPS Cholesky over {} ranks failed (INFOG(1) = {}{})", size,
                                   infog1, infog1 == -13 ? ": out of memory" : "")));
  }
}

void CholeskySolver::solve_over_ranks(::Vec b, ::Vec x) const {
  on_blocks(ranks_, ranks_, b, x,
            [&](::Vec bl, ::Vec xl) { TC_PETSC(MatSolve(factor_.get(), bl, xl)); });
}

void CholeskySolver::solve_many_over_ranks(::Mat b, ::Mat x) const {
  const auto& r = ranks_;
  const PetscInt first = r.start[static_cast<size_t>(r.rank)];
  const PetscInt m = r.count[static_cast<size_t>(r.rank)];
  PetscInt n = 0, k = 0;
  TC_PETSC(MatGetSize(b, &n, &k));
  PetscInt ldb = n, ldx = n;
  TC_PETSC(MatDenseGetLDA(b, &ldb));
  TC_PETSC(MatDenseGetLDA(x, &ldx));
  std::vector<PetscScalar> rows(static_cast<size_t>(m * k));
  {
    const PetscScalar* bp = nullptr;
    TC_PETSC(MatDenseGetArrayRead(b, &bp));
    for (PetscInt j = 0; j < k; ++j) std::copy_n(bp + j * ldb + first, m, rows.begin() + j * m);
    TC_PETSC(MatDenseRestoreArrayRead(b, &bp));
  }
  Handle<::Mat, MatDestroy> bl, xl;
  TC_PETSC(MatCreateDense(r.comm, m, PETSC_DECIDE, r.n, k, rows.data(), bl.out()));
  TC_PETSC(MatCreateDense(r.comm, m, PETSC_DECIDE, r.n, k, nullptr, xl.out()));
  TC_PETSC(MatMatSolve(factor_.get(), bl.get(), xl.get()));
  const PetscScalar* mine = nullptr;
  PetscInt ldl = m;
  TC_PETSC(MatDenseGetLDA(xl.get(), &ldl));
  TC_PETSC(MatDenseGetArrayRead(xl.get(), &mine));
  PetscScalar* xp = nullptr;
  TC_PETSC(MatDenseGetArray(x, &xp));
  for (PetscInt j = 0; j < k; ++j) {
    std::copy_n(mine + j * ldl, m, xp + j * ldx + first);
    TC_MPI(MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, xp + j * ldx, r.count.data(),
                          r.start.data(), MPIU_SCALAR, r.comm));
  }
  TC_PETSC(MatDenseRestoreArray(x, &xp));
  TC_PETSC(MatDenseRestoreArrayRead(xl.get(), &mine));
}

// Entries of A⁻¹ by MUMPS's own selected-inverse solve (ICNTL(30)): the sparse right-hand
// sides e_c and the requested rows let it prune both triangular solves to the paths of the
// elimination tree they touch, and no n × k block is formed. MUMPS takes the request on the
// host, as a sparse matrix whose row c lists the rows wanted of column c, and writes the
// entries into its values there; the host then sends them to every rank.
void CholeskySolver::inverse_entries(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                                     double* out) const {
  const auto nr = static_cast<PetscInt>(rows.size());
  const auto nc = static_cast<PetscInt>(cols.size());
  std::fill_n(out, nr * nc, 0.0);
  auto distinct = [](std::span<const PetscInt> ids) {  // those ≥ 0, sorted, each once
    std::vector<PetscInt> out;
    for (const PetscInt i : ids)
      if (i >= 0) out.push_back(i);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };
  const auto wanted = distinct(rows);  // the pattern of each request row
  const auto asked = distinct(cols);
  const auto w = static_cast<PetscInt>(wanted.size());
  const auto a = static_cast<PetscInt>(asked.size());
  if (w == 0 || a == 0) return;

  std::vector<PetscInt> at(rows.size(), -1);  // each row's place in `wanted`
  for (PetscInt i = 0; i < nr; ++i)
    if (rows[i] >= 0)
      at[i] = std::lower_bound(wanted.begin(), wanted.end(), rows[i]) - wanted.begin();
  std::vector<PetscInt> place(cols.size(), -1);  // each column's place in `asked`
  for (PetscInt j = 0; j < nc; ++j)
    if (cols[j] >= 0)
      place[j] = std::lower_bound(asked.begin(), asked.end(), cols[j]) - asked.begin();
  // In chunks of columns: the request and its entries, |chunk| × |wanted| each, are held on
  // the host (and MUMPS copies the request), so their memory no longer grows with the columns
  // asked at once (the ch. 7 case ×5.3 on 4 ranks: the dual set-up's rise of a rank's peak
  // 0.56 → 0.43 GiB, its time the same). 1024 columns are four of MUMPS's blocks of 256
  // (ICNTL 27).
  constexpr PetscInt chunk = 1024;
  std::vector<double> entries;
  for (PetscInt q0 = 0; q0 < a; q0 += chunk) {
    const PetscInt q1 = std::min(a, q0 + chunk);
    inverse_entries_chunk(std::span(asked).subspan(q0, q1 - q0), wanted, entries);
    for (PetscInt j = 0; j < nc; ++j) {
      const PetscInt q = place[j];
      if (q < q0 || q >= q1) continue;
      for (PetscInt i = 0; i < nr; ++i)
        if (at[i] >= 0) out[i + j * nr] = entries[static_cast<size_t>((q - q0) * w + at[i])];
    }
  }
}

void CholeskySolver::inverse_entries_chunk(std::span<const PetscInt> asked,
                                           std::span<const PetscInt> wanted,
                                           std::vector<double>& entries) const {
  const auto& r = ranks_;
  const auto w = static_cast<PetscInt>(wanted.size());
  const auto a = static_cast<PetscInt>(asked.size());
  // The request, all of it on the host (rank 0): rows and columns 0..n-1 there, none elsewhere.
  const bool host = r.rank == 0;
  const PetscInt mine = host ? r.n : 0;
  std::vector<PetscInt> offsets(static_cast<size_t>(mine) + 1, 0), columns;
  std::vector<PetscScalar> values;
  if (host) {
    for (const PetscInt c : asked) offsets[static_cast<size_t>(c) + 1] = w;
    for (PetscInt i = 0; i < r.n; ++i)
      offsets[static_cast<size_t>(i) + 1] += offsets[static_cast<size_t>(i)];
    columns.reserve(static_cast<size_t>(a * w));
    for (PetscInt q = 0; q < a; ++q) columns.insert(columns.end(), wanted.begin(), wanted.end());
    values.assign(columns.size(), 0.0);
  }
  Handle<::Mat, MatDestroy> request, transposed;
  TC_PETSC(MatCreateMPIAIJWithArrays(r.comm, mine, mine, r.n, r.n, offsets.data(), columns.data(),
                                     values.data(), request.out()));
  TC_PETSC(MatCreateTranspose(request.get(), transposed.out()));
  // The request sets MUMPS's right-hand side and solution formats (ICNTL 20, 21) and its
  // selected-inverse mode (30) and leaves them set: restored for the ordinary solves after.
  // Its columns go in blocks of 256 (ICNTL 27, MUMPS's default 32): the ch. 7 case ×3 at 2
  // ranks, first dual set-up 5.06 → 3.36 s (8: 9.35 s, 64: 4.08 s, 1024: 3.25 s).
  constexpr std::array<int, 4> kept{20, 21, 27, 30};
  std::array<PetscInt, 4> saved{};
  for (size_t q = 0; q < kept.size(); ++q)
    TC_PETSC(MatMumpsGetIcntl(factor_.get(), kept[q], &saved[q]));
  TC_PETSC(MatMumpsSetIcntl(factor_.get(), 27, 256));
  TC_PETSC(MatMumpsGetInverse(factor_.get(), transposed.get()));
  for (size_t q = 0; q < kept.size(); ++q)
    TC_PETSC(MatMumpsSetIcntl(factor_.get(), kept[q], saved[q]));

  entries.assign(static_cast<size_t>(a * w), 0.0);  // column q of `asked`, row of `wanted`
  if (host) {
    ::Mat diagonal = nullptr;  // the host's rows and columns: all of the request
    TC_PETSC(MatMPIAIJGetSeqAIJ(request.get(), &diagonal, nullptr, nullptr));
    const PetscScalar* v = nullptr;
    TC_PETSC(MatSeqAIJGetArrayRead(diagonal, &v));
    std::copy_n(v, entries.size(), entries.begin());
    TC_PETSC(MatSeqAIJRestoreArrayRead(diagonal, &v));
  }
  TC_MPI(MPI_Bcast(entries.data(), static_cast<int>(entries.size()), MPI_DOUBLE, 0, r.comm));
}

namespace {

double jacobi_cg_on(::Mat a, ::Vec b, ::Vec x, double rtol, int max_iterations, int& iterations) {
  MPI_Comm comm = MPI_COMM_NULL;
  TC_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a), &comm));
  Handle<::KSP, KSPDestroy> ksp;
  TC_PETSC(KSPCreate(comm, ksp.out()));
  TC_PETSC(KSPSetOperators(ksp.get(), a, a));
  TC_PETSC(KSPSetType(ksp.get(), KSPCG));
  PC pc = nullptr;
  TC_PETSC(KSPGetPC(ksp.get(), &pc));
  TC_PETSC(PCSetType(pc, PCJACOBI));
  TC_PETSC(KSPSetNormType(ksp.get(), KSP_NORM_UNPRECONDITIONED));
  TC_PETSC(KSPSetTolerances(ksp.get(), rtol, 0.0, PETSC_DEFAULT, max_iterations));
  TC_PETSC(KSPSolve(ksp.get(), b, x));
  PetscInt its = 0;
  TC_PETSC(KSPGetIterationNumber(ksp.get(), &its));
  iterations = static_cast<int>(its);
  PetscReal r = 0;
  TC_PETSC(KSPGetResidualNorm(ksp.get(), &r));
  PetscReal bn = 0;
  TC_PETSC(VecNorm(b, NORM_2, &bn));
  return bn > 0 ? r / bn : 0.0;
}

}  // namespace

double jacobi_cg(const SparseMatrix& a, const Vector& b, Vector& x, double rtol, int max_iterations,
                 int& iterations) {
  if (a.distributed()) {  // on this rank's blocks of b and x, x gathered after
    double reached = 0;
    on_blocks(a.row_blocks(), a.row_blocks(), b.get(), x.get(), [&](::Vec bl, ::Vec xl) {
      reached = jacobi_cg_on(a.get(), bl, xl, rtol, max_iterations, iterations);
    });
    return reached;
  }
  return jacobi_cg_on(a.get(), b.get(), x.get(), rtol, max_iterations, iterations);
}

}  // namespace tc::core
