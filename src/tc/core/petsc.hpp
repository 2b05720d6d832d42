#pragma once
// PETSc behind RAII: the session (the one place that initialises PETSc and MPI), owning
// handles for Vec/Mat/KSP, and TC_PETSC, which turns every failed call into a PetscError
// naming the call. MPI and PETSc headers stay inside core and the layers that assemble.
#include <petscksp.h>

#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace tc::core {

/// Throws PetscError naming `call` (with PETSc's message) when `code` is non-zero.
void check_petsc(PetscErrorCode code, const char* call, const char* file, int line);

#define TC_PETSC(call) ::tc::core::check_petsc((call), #call, __FILE__, __LINE__)

/// Initialises PETSc (and MPI) on construction, finalises on destruction. Create exactly one,
/// in main() or the test runner, before any other PETSc object. Collective on MPI_COMM_WORLD.
class PetscSession {
 public:
  PetscSession(int* argc, char*** argv);
  ~PetscSession();
  PetscSession(const PetscSession&) = delete;
  PetscSession& operator=(const PetscSession&) = delete;

  [[nodiscard]] static int rank();
  [[nodiscard]] static int size();
  /// The ranks of PETSC_COMM_WORLD on this rank's node, sharing its memory (1 before a session):
  /// every rank holds every body (docs/choices.md, "Replicated state"), so they divide it.
  [[nodiscard]] static int node_size();
  /// BLAS threads of this rank outside large kernels: 1, or OPENBLAS_NUM_THREADS (the policy
  /// and the kernels' threads: core/threads.hpp).
  [[nodiscard]] static int blas_threads();

 private:
  static int node_size_;
};

/// Owning handle of a PETSc object (Vec, Mat, KSP, ...): move-only, destroyed once.
template <class H, PetscErrorCode (*Destroy)(H*)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(H h) : h_(h) {}
  ~Handle() { reset(); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      h_ = std::exchange(o.h_, nullptr);
    }
    return *this;
  }
  void reset() {
    if (h_) (void)Destroy(&h_);  // a destructor must not throw; PETSc nulls h_
    h_ = nullptr;
  }
  [[nodiscard]] H get() const { return h_; }
  [[nodiscard]] H* out() {
    reset();
    return &h_;
  }
  explicit operator bool() const { return h_ != nullptr; }

 private:
  H h_ = nullptr;
};

/// A dense vector of doubles: sequential (per rank) by default, or distributed over the ranks
/// of a communicator (the dual vectors of the QP layer).
class Vector {
 public:
  Vector() = default;
  explicit Vector(PetscInt n);  // zero-initialised, on PETSC_COMM_SELF
  [[nodiscard]] static Vector from(std::span<const double> values);
  /// Zero-initialised, `local_size` entries on this rank of `comm` (collective).
  [[nodiscard]] static Vector distributed(MPI_Comm comm, PetscInt local_size);
  /// Takes ownership of an existing PETSc vector (one reference).
  [[nodiscard]] static Vector adopt(::Vec v);

  [[nodiscard]] ::Vec get() const { return v_.get(); }
  [[nodiscard]] PetscInt size() const;  // global size
  [[nodiscard]] PetscInt local_size() const;
  [[nodiscard]] MPI_Comm comm() const;
  [[nodiscard]] Vector clone() const;      // same layout and values
  [[nodiscard]] Vector duplicate() const;  // same layout, zero values
  void zero();
  void fill(double value);
  void copy_from(const Vector& other);
  void axpy(double a, const Vector& x);  // this += a x
  void scale(double a);
  void shift(double a);  // every entry += a
  [[nodiscard]] double dot(const Vector& other) const;
  [[nodiscard]] double norm() const;  // 2-norm
  [[nodiscard]] double sum() const;
  [[nodiscard]] double max_abs() const;              // the infinity norm
  [[nodiscard]] std::vector<double> to_std() const;  // the local entries
  [[nodiscard]] bool all_finite() const;             // collective

  /// Read/write access to the local entries for the lifetime of the view.
  class View {
   public:
    explicit View(::Vec v);
    ~View();
    View(const View&) = delete;
    View& operator=(const View&) = delete;
    double& operator[](PetscInt i) { return data_[i]; }
    [[nodiscard]] std::span<double> span() { return {data_, static_cast<size_t>(n_)}; }

   private:
    ::Vec v_;
    double* data_ = nullptr;
    PetscInt n_ = 0;
  };
  [[nodiscard]] View view() { return View(get()); }

  /// Read-only access to the local entries for the lifetime of the view.
  class ReadView {
   public:
    explicit ReadView(::Vec v);
    ~ReadView();
    ReadView(const ReadView&) = delete;
    ReadView& operator=(const ReadView&) = delete;
    double operator[](PetscInt i) const { return data_[i]; }
    [[nodiscard]] std::span<const double> span() const { return {data_, static_cast<size_t>(n_)}; }

   private:
    ::Vec v_;
    const double* data_ = nullptr;
    PetscInt n_ = 0;
  };
  [[nodiscard]] ReadView read() const { return ReadView(get()); }

 private:
  Handle<::Vec, VecDestroy> v_;
};

/// The rows 0..n−1 dealt to the ranks of `comm` in contiguous blocks, the first n mod size
/// ranks one row more: the layout of a factor spread over the ranks and of the matrices whose
/// rows are spread with it (SparseMatrix::over_ranks), so that each rank's rows of the
/// replicated vectors are its part of both.
struct RowBlocks {
  MPI_Comm comm = MPI_COMM_NULL;  // MPI_COMM_NULL: not spread
  std::vector<int> count, start;
  int rank = 0;
  PetscInt n = 0;
  [[nodiscard]] static RowBlocks over(MPI_Comm comm, PetscInt n);
  [[nodiscard]] bool spread() const { return comm != MPI_COMM_NULL; }
  [[nodiscard]] PetscInt first() const { return start[static_cast<size_t>(rank)]; }
  [[nodiscard]] PetscInt here() const { return count[static_cast<size_t>(rank)]; }
  [[nodiscard]] bool owns(PetscInt row) const { return row >= first() && row < first() + here(); }
  /// Gathers every rank's block of the replicated array `x` (length n) into every rank's x.
  void gather(double* x) const;
};

/// A sparse matrix, whole on each rank (a sequential AIJ), or with its rows spread over the
/// ranks (`over_ranks`, an MPIAIJ in RowBlocks): then the vectors it takes and gives are still
/// replicated and whole, every method is collective, each rank computes its rows and the
/// results are gathered.
class SparseMatrix {
 public:
  SparseMatrix() = default;
  SparseMatrix(PetscInt rows, PetscInt cols, std::span<const PetscInt> nnz_per_row);
  /// A matrix whose rows are spread over the ranks in `rows` and whose columns are dealt in
  /// `cols` (the blocks of the vectors it multiplies: the rows' own for a square matrix),
  /// preallocated exactly: `diagonal` and `off_diagonal` give, for each of this rank's rows,
  /// its entries in this rank's block of columns and outside it.
  [[nodiscard]] static SparseMatrix over_ranks(const RowBlocks& rows, const RowBlocks& cols,
                                               std::span<const PetscInt> diagonal,
                                               std::span<const PetscInt> off_diagonal);
  [[nodiscard]] bool distributed() const { return blocks_.spread(); }
  [[nodiscard]] const RowBlocks& row_blocks() const { return blocks_; }
  /// Whether this rank holds row r (every row when the matrix is whole).
  [[nodiscard]] bool owns_row(PetscInt r) const { return !distributed() || blocks_.owns(r); }

  [[nodiscard]] ::Mat get() const { return m_.get(); }
  [[nodiscard]] PetscInt rows() const;
  [[nodiscard]] PetscInt cols() const;
  void add_values(std::span<const PetscInt> rows, std::span<const PetscInt> cols,
                  const double* row_major_block);
  void assemble();
  [[nodiscard]] SparseMatrix copy() const;
  /// Another owner of the same PETSc matrix (reference counted), not a copy.
  [[nodiscard]] SparseMatrix share() const;
  void mult(const Vector& x, Vector& y) const;            // y = A x
  void mult_add(const Vector& x, Vector& y) const;        // y += A x
  void mult_transpose(const Vector& x, Vector& y) const;  // y = Aᵀ x
  void mult_transpose_add(const Vector& x, Vector& y) const;
  void axpy(double a, const SparseMatrix& x);  // this += a x, same nonzero pattern
  void scale(double a);
  /// Zeroes the listed rows and columns and puts `diag` on their diagonal.
  void zero_rows_columns(std::span<const PetscInt> rows, double diag);
  [[nodiscard]] double quadratic_form(const Vector& x, Vector& work) const;  // xᵀ A x

 private:
  Handle<::Mat, MatDestroy> m_;
  RowBlocks blocks_;      // spread when the rows are dealt over the ranks
  RowBlocks col_blocks_;  // then the columns' blocks (the vectors a product takes)
};

/// The mean of the diagonal (1 if not positive): the scale given to the rows of eliminated
/// dofs, so that a matrix with them replaced by a scaled identity keeps its conditioning.
[[nodiscard]] double mean_diagonal(const SparseMatrix& a);

class CholmodFactor;     // cholmod_factor.hpp
struct CholeskyColumns;  // cholmod_supernodes.hpp
struct ForwardColumns;  // cholmod_columns.cpp: Y = L⁻¹P E_T kept between forward_compliance calls
struct ForwardColumnsDeleter {
  void operator()(ForwardColumns* y) const;
};
using ForwardColumnsPtr = std::unique_ptr<ForwardColumns, ForwardColumnsDeleter>;

/// Where a factor lives: on the calling rank alone, or spread over the ranks of
/// PETSC_COMM_WORLD.
enum class FactorRanks { this_rank, all_ranks };

/// A direct Cholesky factorisation of an SPD SparseMatrix, done once, solved many times.
/// The package is "mumps", "cholmod" or "petsc" (PETSc's MatSolverType names); it may be
/// overridden with the PETSc option -tc_factor_package. CHOLMOD on one rank is called through
/// SuiteSparse's public API (CholmodFactor), the others through PETSc.
///
/// With FactorRanks::all_ranks on more than one rank, and the package MUMPS or left to the
/// solver, or with a matrix whose rows are spread over the ranks (SparseMatrix::over_ranks),
/// the matrix (whole on every rank, or spread) is factorised once by MUMPS over all ranks,
/// each holding its part of the factor, instead of once per rank: every method is then
/// collective, called by every rank with the same arguments, and returns the same replicated
/// result on each.
class CholeskySolver {
 public:
  CholeskySolver() = default;
  explicit CholeskySolver(const SparseMatrix& a, const std::string& package = "",
                          FactorRanks ranks = FactorRanks::this_rank);
  /// The factor of `a` with the rows and columns of the sorted `eliminated` replaced by
  /// diag·I (symmetric elimination of Dirichlet dofs), without a whole copy of `a` when the
  /// factor is spread over the ranks (each rank takes its rows, eliminated on the way).
  CholeskySolver(const SparseMatrix& a, std::span<const PetscInt> eliminated, double diag,
                 const std::string& package, FactorRanks ranks);
  /// The same consuming `a`: eliminated in place (no copy), and with CHOLMOD freed as soon as
  /// CHOLMOD holds its triangle, before the numeric factorisation, so that the factor's peak
  /// holds no whole copy of the operator (the same factor, the same bits).
  CholeskySolver(SparseMatrix&& a, std::span<const PetscInt> eliminated, double diag,
                 const std::string& package, FactorRanks ranks);
  void solve(const Vector& b, Vector& x) const;
  void solve_raw(::Vec b, ::Vec x) const;  // the same on bare PETSc vectors
  /// X = A⁻¹B for dense B and X (n × k, column-major, PETSc MATSEQDENSE): one multi-right-hand
  /// side solve, which the factorisation packages do with level-3 BLAS.
  void solve_many(::Mat b, ::Mat x) const;
  /// out(i, j) = (A⁻¹ e_c)[rows[i]] for c = cols[j] (a column −1 is a zero right-hand side),
  /// column-major |rows| × |cols|: with CHOLMOD's supernodal factor, the forward solve visits
  /// only the supernodes the columns reach and the backward solve only those of the rows and
  /// their ancestors, each with CHOLMOD's own BLAS calls, so the entries are those of
  /// solve_many on the same block, bit for bit. With the factor spread over the ranks, MUMPS's
  /// selected entries of A⁻¹ (to round-off, any number of columns at once). Returns false,
  /// writing nothing, with another package (the caller then uses solve_many).
  bool unit_solve_rows(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                       double* out) const;
  /// Whether forward_compliance is worth it for a first cover of `dofs`: with CHOLMOD's
  /// supernodal factor, when unit_solve_rows in blocks of `block` columns would cost more flops
  /// than the forward solves and more than a third of a second. Below that, the restricted
  /// solves keep the set-up's bits as they were.
  [[nodiscard]] bool forward_compliance_pays(std::span<const PetscInt> dofs, int block) const;
  /// Grows S = (A⁻¹)_TT by the forward solve alone: S = YᵀY with Y = L⁻¹P E_T (A = PᵀLLᵀP,
  /// E_T the unit columns of T), each supernode once with all the columns that reach it, and
  /// no backward solve. T is the dofs of the earlier calls with `kept`, then `fresh`; out is
  /// S(T, fresh), column-major |T| × |fresh| (on the first call |fresh| × |fresh|, exactly
  /// symmetric). A dof −1 gives a zero row and column. `kept` holds Y for later calls (on the
  /// supernodes each column reaches; about as large as S). The entries agree with
  /// unit_solve_rows to round-off, not to the bit (other sums). Returns false, writing
  /// nothing, with another package or another factor than kept's.
  bool forward_compliance(ForwardColumnsPtr& kept, std::span<const PetscInt> fresh,
                          double* out) const;
  /// x = A⁻¹(b + E_T w) for w given on T (kept's dofs, in their order) and z = L⁻¹P b from
  /// forward_half (empty: b = 0): Y w = L⁻¹P E_T w from the kept columns, then the backward
  /// solve alone, x = PᵀL⁻ᵀ(z + Y w). Half a solve plus one pass over Y; equal to solve() on
  /// that right-hand side to round-off. Returns false, writing nothing, without CHOLMOD or for
  /// another factor than kept's.
  bool solve_from_forward(const ForwardColumns& kept, std::span<const double> w, double* x,
                          std::span<const double> z = {}) const;
  /// The first half of solve(): z = L⁻¹P b (CHOLMOD's supernodal factor, its own BLAS calls),
  /// for solve_from_forward to finish. False, z untouched, without CHOLMOD.
  bool forward_half(std::span<const double> b, std::vector<double>& z) const;
  /// (A⁻¹b)_T = Yᵀz for z = forward_half(b) without the backward solve: one pass over Y
  /// (E_Tᵀ A⁻¹ = (L⁻¹P E_T)ᵀ L⁻¹P). out is on T in kept's order; a dof of T given as −1 to
  /// forward_compliance gets 0. False, out untouched, as solve_from_forward.
  bool forward_values(const ForwardColumns& kept, std::span<const double> z,
                      std::span<double> out) const;
  [[nodiscard]] const std::string& package() const { return package_; }
  /// Whether the factor is spread over the ranks (see the class comment).
  [[nodiscard]] bool distributed() const { return ranks_.comm != MPI_COMM_NULL; }

 private:
  // Resolves package_ too; a matrix spread over the ranks is factorised there.
  [[nodiscard]] bool spread_over_ranks(FactorRanks ranks, bool spread_matrix);
  void factor_over_ranks(const SparseMatrix& a, std::span<const PetscInt> eliminated = {},
                         double diag = 1.0);
  void solve_over_ranks(::Vec b, ::Vec x) const;
  void solve_many_over_ranks(::Mat b, ::Mat x) const;
  void inverse_entries(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                       double* out) const;
  // Entries (A⁻¹)(wanted, asked), column-major, on every rank: one MUMPS request.
  void inverse_entries_chunk(std::span<const PetscInt> asked, std::span<const PetscInt> wanted,
                             std::vector<double>& entries) const;

  Handle<::Mat, MatDestroy> factor_;              // PETSc's factored matrix (MUMPS or PETSc's own)
  std::shared_ptr<const CholmodFactor> cholmod_;  // or CHOLMOD's, through its own API
  std::string package_;
  RowBlocks ranks_;
  mutable std::shared_ptr<CholeskyColumns> columns_;  // the factor's structure, on first use
};

/// Conjugate gradients with Jacobi's preconditioner from x = 0 until ‖r‖ ≤ rtol·‖b‖ (PETSc's
/// KSPCG, unpreconditioned norm): for matrices whose diagonal scaling leaves them well
/// conditioned independently of the mesh, such as a mass matrix. Returns the residual norm
/// ratio reached and sets `iterations`; the caller decides what not converging means.
double jacobi_cg(const SparseMatrix& a, const Vector& b, Vector& x, double rtol, int max_iterations,
                 int& iterations);

/// The factorisation packages this PETSc build offers for Cholesky on sequential AIJ.
[[nodiscard]] std::vector<std::string> available_cholesky_packages();
/// The package named by the PETSc option -tc_factor_package, or "" when it is not set.
[[nodiscard]] std::string requested_factor_package();
/// The ranks an undecomposed body's factor is spread over (CholeskySolver with
/// FactorRanks::all_ranks) for the case's `package` ("" automatic; -tc_factor_package
/// overrides it): every rank of PETSC_COMM_WORLD with MUMPS or the automatic choice, else 1.
[[nodiscard]] int ranks_sharing_a_factor(const std::string& package);

}  // namespace tc::core
