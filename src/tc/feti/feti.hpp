#pragma once
// Total FETI for one body (6.2, 6.4): the body's linear system A x = b, with x prescribed on
// its Dirichlet dofs, solved on non-overlapping subdomains s with local matrices A_s (Σ_s A_s
// assembled = A). Every subdomain copy of an interface dof is a separate unknown; the copies
// are glued by the rows of B_g (for a node shared by m subdomains, m − 1 orthonormal rows per
// component) and the Dirichlet data enter as rows of B_D on every copy (u_i = u_D,i). Then
//   A_s u_s + B_sᵀ λ = f_s,   Σ_s B_s u_s = c,
// and, eliminating u_s = A_s⁺(f_s − B_sᵀλ) + R_s α_s (R_s the kernel of a floating A_s),
//   F λ − Gᵀ α = d,   G λ = e,   F = Σ_s B_s A_s⁺ B_sᵀ,  d = Σ_s B_s A_s⁺ f_s − c,
//   G = Rᵀ Bᵀ,  e = Rᵀ f,
// which projected CG solves on λ₀ + Ker G with P = I − Gᵀ(GGᵀ)⁻¹G (Farhat–Mandel–Roux;
// Dostál et al. 2006 for Total FETI). With inertia or heat capacity A_s is non-singular and
// there is no kernel; but when K dominates 4/τ²M the rigid motions are still nearly free and
// plain CG crawls (640 iterations instead of 70 on 27 subdomains). The same coarse space then
// deflates CG: λ₀ = W E⁻¹Wᵀd, search directions F-orthogonal to W = Gᵀ, E = WᵀFW (the
// conjugate projector of Dostál, Kozubek, Brzobohatý et al. 2012), W an orthonormal basis
// of the columns of Gᵀ.
//
// Parallel model: subdomains are dealt to the ranks of the communicator in contiguous blocks;
// a rank assembles and factorises only its own. Every multiplier (row of B) is owned by one
// rank, the rank of the lowest-numbered subdomain it touches, and a rank stores only its own
// rows of every dual block (λ, the PCG vectors, the deflation space W and FW): m/ranks rows
// each for an even cut. A PetscSF moves the rows between the owners and the ranks whose
// subdomains touch them: F·x is the owners' x broadcast to the users, the owned subdomains'
// products B_s A_s⁺ B_sᵀ x, and a reduction (sum) of those back to the owners, so only the
// rows on interfaces between two ranks travel. Dots and norms are local sums and one
// MPI_Allreduce of k values; the coarse problem (GGᵀ or E = WᵀFW, n_kernel²) is factorised
// on every rank, and Gx is the owned columns' product summed by MPI_Allreduce. Primal vectors
// (b, x) stay replicated. Every rank-local phase (assembly, factorisation, the subdomain
// solves of F, the preconditioner, the right-hand side and the primal solution) runs in
// core::collective_check: a failure on one rank throws on all, "rank r: <phase>: <message>".
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/feti/dual_distribution.hpp"
#include "tc/feti/preconditioner.hpp"
#include "tc/mesh/partition.hpp"

namespace tc::feti {

/// The kernel of a subdomain matrix without Dirichlet data.
/// The kernel of a subdomain matrix without Dirichlet data, or its near-kernel when the
/// matrix is regularised (inertia, heat capacity): the coarse space.
enum class Kernel {
  none,      // no coarse space
  rigid,     // elasticity: dim translations and dim(dim − 1)/2 rotations
  constant,  // heat conduction: constants
};

/// Whether A_s has the kernel exactly (TFETI projector) or only nearly (deflation).
enum class Singular { no, yes };

/// The first of the contiguous block of subdomains that `rank` of `size` owns (rank + 1: one
/// past its last): the dealing of Feti, which the output's pieces follow too.
[[nodiscard]] inline int first_subdomain(int n_subdomains, int rank, int size) {
  return static_cast<int>(static_cast<long>(n_subdomains) * rank / size);
}

struct FetiOptions {
  /// Stop when ‖B u − c‖ (the projected dual gradient: gluing jumps and Dirichlet misfit)
  /// ≤ max(tolerance · max(‖P d‖, ‖P F λ₀‖), 1e3 ε max(‖d‖, ‖F λ₀‖)): relative, but never
  /// below the round-off at which P(Fλ − d) can be computed.
  double tolerance = 1e-10;
  int max_iterations = 2000;
  Preconditioner preconditioner = Preconditioner::dirichlet;
  bool orthonormal_gluing = true;  // Helmert rows; else chains u_s − u_{s+1}
  bool deflation = true;           // the coarse space of a non-singular A_s deflates CG
  std::string package;             // Cholesky package of the subdomain factorisations
  /// The ranks the subdomains are dealt to (PETSC_COMM_SELF: this rank solves them all).
  MPI_Comm comm = PETSC_COMM_WORLD;
};

struct FetiStatistics {
  long solves = 0;            // calls, each with one block of right-hand sides
  long right_hand_sides = 0;  // columns over all calls
  long iterations = 0;        // PCG iterations over all solves (shared by a block's columns)
  int last_iterations = 0;    // of the last solve
  double last_residual = 0;   // ‖B u − c‖ / ‖P d‖ at the end of the last solve
  /// The largest ‖B u − c‖ (absolute: a length for elasticity, the gluing rows orthonormal)
  /// at the end of the solves since Feti::clear_peak_residual, over their right-hand sides:
  /// the misfit of the glued and supported body that the solves left (physics::ContactLaws).
  double peak_residual = 0;
  double seconds = 0;  // wall time in the solves (dual and primal), this rank
  // The solves with one right-hand side alone (an iteration of a block costs k columns):
  long single_solves = 0, single_iterations = 0;
  double single_seconds = 0;
  /// Sums the counters and times (the `last_` entries are those of `o`).
  FetiStatistics& operator+=(const FetiStatistics& o) {
    solves += o.solves, right_hand_sides += o.right_hand_sides, iterations += o.iterations;
    last_iterations = o.last_iterations, last_residual = o.last_residual;
    peak_residual = std::max(peak_residual, o.peak_residual);
    seconds += o.seconds, single_solves += o.single_solves;
    single_iterations += o.single_iterations, single_seconds += o.single_seconds;
    return *this;
  }
};

class Feti {
 public:
  /// Assembles A_s of the subdomains this rank owns with `local_matrix(s)` (the body's
  /// assembly restricted to the cells of subdomain s, `block` dofs per node, interleaved).
  Feti(const std::vector<mesh::SubMesh>& subdomains, int n_nodes, int block,
       std::vector<PetscInt> dirichlet_dofs, Kernel kernel, Singular singular,
       const std::function<core::SparseMatrix(int s)>& local_matrix, FetiOptions options = {});
  ~Feti();
  Feti(const Feti&) = delete;
  Feti& operator=(const Feti&) = delete;

  /// On entry x holds the prescribed values at the Dirichlet dofs; on exit x solves A x = b
  /// (same contract as physics::ConstrainedSolver). Collective on PETSC_COMM_WORLD.
  void solve(const core::Vector& b, core::Vector& x) const;
  /// X = A⁻¹B with zero prescribed values (dense n × k): the k right-hand sides share every
  /// product with F, so the subdomains do multi-RHS solves (level-3 BLAS).
  void solve_homogeneous_many(::Mat b, ::Mat x) const;

  [[nodiscard]] int n_subdomains() const { return static_cast<int>(subs_.size()); }
  [[nodiscard]] PetscInt n_multipliers() const { return m_; }
  [[nodiscard]] PetscInt n_gluing() const { return m_gluing_; }
  /// The multipliers this rank owns (rows of B, gluing first, then Dirichlet): every row is
  /// owned by exactly one rank of the communicator.
  [[nodiscard]] const std::vector<Eigen::Index>& owned_multipliers() const {
    return rows_.owned_rows();
  }
  [[nodiscard]] int coarse_dimension() const { return static_cast<int>(n_kernel_); }
  [[nodiscard]] const FetiStatistics& statistics() const { return stats_; }
  /// Starts FetiStatistics::peak_residual anew (a caller's window of solves, e.g. a step).
  void clear_peak_residual() const { stats_.peak_residual = 0; }
  [[nodiscard]] const std::string& package() const { return package_; }

  // What a dual over the subdomains of several bodies (ContactFeti) builds on.
  struct Subdomain;  // subdomain.hpp
  [[nodiscard]] const Subdomain& subdomain(int s) const { return *subs_[static_cast<size_t>(s)]; }
  [[nodiscard]] int block() const { return block_; }
  /// The subdomain that carries the load of each body node.
  [[nodiscard]] const std::vector<int>& load_owners() const { return owner_; }
  [[nodiscard]] const std::vector<PetscInt>& dirichlet_dofs() const { return dirichlet_dofs_; }
  /// The body dof of each Dirichlet row (rows n_gluing() … n_multipliers() − 1).
  [[nodiscard]] const std::vector<PetscInt>& dirichlet_row_dofs() const {
    return dirichlet_row_dof_;
  }
  [[nodiscard]] bool singular() const { return singular_; }
  [[nodiscard]] MPI_Comm comm() const { return options_.comm; }

 private:
  using Block = Eigen::MatrixXd;  // k dual or primal vectors, one per column
  void build_rows(int n_nodes, const std::vector<PetscInt>& dirichlet);
  void build_kernels(const std::vector<mesh::SubMesh>& subdomains, Kernel kernel);
  void build_distribution();
  Eigen::SparseMatrix<double> build_g();
  void build_coarse();
  void build_deflation();
  /// y = Σ_s B_s X_s B_sᵀ x over all subdomains (x, y: owned rows), X_s applied by `local`
  /// from sub.w to sub.z on the owned ones; `before` runs first inside the checked phase.
  void sum_subdomain_products(const Block& x, Block& y, const char* phase,
                              const std::function<void(const Subdomain&)>& local,
                              const std::function<void()>& before = {}) const;
  void apply_f(const Block& x, Block& y) const;
  void precondition(const Block& x, Block& y) const;
  void project(Block& x) const;  // x ← P x
  void deflate(Block& z) const;  // z ← z − W E⁻¹ (FW)ᵀ z
  /// λ (this rank's rows; below them α of the floating subdomains, replicated) for k
  /// right-hand sides f (body dofs × k) and Dirichlet data c (owned rows × k); f is split
  /// into the subdomains' loads on the way.
  Block solve_dual(const Block& f_global, const Block& c, std::vector<Block>& f) const;
  Block primal(const Block& solution, const std::vector<Block>& f) const;
  void record_time(double seconds, Eigen::Index columns) const;
  void sum_over_ranks(double* data, Eigen::Index n) const;
  /// The dots a_jᵀb_j of the columns over all rows (local sums, one MPI_Allreduce).
  [[nodiscard]] Eigen::ArrayXd column_dots(const Block& a, const Block& b) const;

  int block_;
  FetiOptions options_;
  std::vector<std::unique_ptr<Subdomain>> subs_;
  Eigen::Index m_ = 0, m_gluing_ = 0, n_kernel_ = 0;
  std::vector<PetscInt> dirichlet_dofs_;     // sorted
  std::vector<PetscInt> dirichlet_row_dof_;  // body dof of each Dirichlet row
  std::vector<int> owner_;                   // subdomain that carries each body node's load
  DualDistribution rows_;                    // the owner of every row of B, the star forest
  Eigen::SparseMatrix<double> g_;            // G = Rᵀ Bᵀ, its columns of the owned rows
  Eigen::LLT<Eigen::MatrixXd> coarse_;       // GGᵀ (singular) or E = GFGᵀ (deflation)
  bool singular_ = false;
  // Deflation only, owned rows: W (orthonormal basis of range Gᵀ) and F W.
  Eigen::MatrixXd w_, fw_;
  int first_owned_ = 0, last_owned_ = 0;  // [first, last) subdomains of this rank
  std::string package_;
  // -tc_fail_on_rank, -tc_fail_phase solve (core/numeric/collective.hpp)
  PetscInt fail_after_ = -1;
  mutable FetiStatistics stats_;
};

}  // namespace tc::feti
