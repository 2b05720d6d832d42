#include "tc/core/numeric/petsc.hpp"

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

#include "tc/core/error.hpp"
#include "tc/core/numeric/collective.hpp"
#include "tc/core/numeric/matrix_views.hpp"
#include "tc/core/numeric/petsc_blocks.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/core/verify.hpp"

namespace tc::core {

using blocks::on_blocks;

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

namespace {

// jacobi_cg's masked operator: A with the rows and columns of `fixed` replaced by diag·I,
// applied to A itself. CG's iterates are zero on the fixed dofs (b is, and so are the residual,
// the search direction and the product there), so A's product sums on a free row the terms of
// a copy whose fixed columns are zeroed, in the same order, A_ij·0 where the copy has 0·x_j:
// the same values (zeros may differ in sign only).
struct MaskedOperator {
  ::Mat a = nullptr;
  std::vector<PetscInt> fixed;  // this rank's rows among them
  double diag = 1.0;
};

// PETSc calls these back: errors are returned, not thrown (PetscCall's PetscError would name
// tc::PetscError here).
#define TC_RETURN_ON_ERROR(call)         \
  do {                                   \
    const PetscErrorCode code_ = (call); \
    if (code_) return code_;             \
  } while (0)

PetscErrorCode masked_apply(::Mat shell, ::Vec x, ::Vec y) {
  MaskedOperator* op = nullptr;
  TC_RETURN_ON_ERROR(MatShellGetContext(shell, &op));
  TC_RETURN_ON_ERROR(MatMult(op->a, x, y));
  PetscInt lo = 0, hi = 0;
  TC_RETURN_ON_ERROR(VecGetOwnershipRange(y, &lo, &hi));
  const PetscScalar* xv = nullptr;
  PetscScalar* yv = nullptr;
  TC_RETURN_ON_ERROR(VecGetArrayRead(x, &xv));
  TC_RETURN_ON_ERROR(VecGetArray(y, &yv));
  for (const PetscInt d : op->fixed) yv[d - lo] = op->diag * xv[d - lo];
  TC_RETURN_ON_ERROR(VecRestoreArray(y, &yv));
  return VecRestoreArrayRead(x, &xv);
}

PetscErrorCode masked_diagonal(::Mat shell, ::Vec d) {
  MaskedOperator* op = nullptr;
  TC_RETURN_ON_ERROR(MatShellGetContext(shell, &op));
  TC_RETURN_ON_ERROR(MatGetDiagonal(op->a, d));
  PetscInt lo = 0, hi = 0;
  TC_RETURN_ON_ERROR(VecGetOwnershipRange(d, &lo, &hi));
  PetscScalar* dv = nullptr;
  TC_RETURN_ON_ERROR(VecGetArray(d, &dv));
  for (const PetscInt f : op->fixed) dv[f - lo] = op->diag;
  return VecRestoreArray(d, &dv);
}

#undef TC_RETURN_ON_ERROR

}  // namespace

double jacobi_cg(const SparseMatrix& a, std::span<const PetscInt> fixed, double diag,
                 const Vector& b, Vector& x, double rtol, int max_iterations, int& iterations) {
  MaskedOperator op;
  op.a = a.get();
  op.diag = diag;
  PetscInt lo = 0, hi = 0, m = 0, n = 0;
  TC_PETSC(MatGetOwnershipRange(a.get(), &lo, &hi));
  TC_PETSC(MatGetLocalSize(a.get(), &m, &n));
  std::copy_if(fixed.begin(), fixed.end(), std::back_inserter(op.fixed),
               [&](PetscInt d) { return d >= lo && d < hi; });
  MPI_Comm comm = MPI_COMM_NULL;
  TC_PETSC(PetscObjectGetComm(reinterpret_cast<PetscObject>(a.get()), &comm));
  Handle<::Mat, MatDestroy> shell;
  TC_PETSC(MatCreateShell(comm, m, n, a.rows(), a.cols(), &op, shell.out()));
  TC_PETSC(
      MatShellSetOperation(shell.get(), MATOP_MULT, reinterpret_cast<void (*)()>(masked_apply)));
  TC_PETSC(MatShellSetOperation(shell.get(), MATOP_GET_DIAGONAL,
                                reinterpret_cast<void (*)()>(masked_diagonal)));
  if (a.distributed()) {
    double reached = 0;
    on_blocks(a.row_blocks(), a.row_blocks(), b.get(), x.get(), [&](::Vec bl, ::Vec xl) {
      reached = jacobi_cg_on(shell.get(), bl, xl, rtol, max_iterations, iterations);
    });
    return reached;
  }
  return jacobi_cg_on(shell.get(), b.get(), x.get(), rtol, max_iterations, iterations);
}

}  // namespace tc::core
