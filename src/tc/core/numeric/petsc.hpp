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
  /// and the kernels' threads: core/numeric/threads.hpp).
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

/// Conjugate gradients with Jacobi's preconditioner from x = 0 until ‖r‖ ≤ rtol·‖b‖ (PETSc's
/// KSPCG, unpreconditioned norm): for matrices whose diagonal scaling leaves them well
/// conditioned independently of the mesh, such as a mass matrix. Returns the residual norm
/// ratio reached and sets `iterations`; the caller decides what not converging means.
double jacobi_cg(const SparseMatrix& a, const Vector& b, Vector& x, double rtol, int max_iterations,
                 int& iterations);

}  // namespace tc::core
