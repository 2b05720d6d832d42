#pragma once
// The mechanical step with contact, dualised (6.9): for the slave and master bodies with
// factorised A_i (4/τ²M_u + K_u, or K_u when quasistatic; Dirichlet data eliminated),
//   A_i u_i + B_iᵀ λ = f_i,   λ ∈ M(γ),   (μ − λ)ᵀ(B u − c) ≤ 0  ∀μ ∈ M(γ),
// where B = [B_1 … B_N] (the bodies of every contact pair) stacks, per contact node k, the normal
// row and the dim − 1 tangential rows (5.3–5.4, 6.4). Eliminating u gives the QP in λ:
//   min ½λᵀFλ − λᵀd,  F = Σ_i B_i A_i⁻¹ B_iᵀ,  d = Σ_i B_i A_i⁻¹ f_i − c,
// over λ_n,k ≥ 0 and ‖λ_τ,k‖ ≤ 𝔉γ_k (an interval in 2D, a disc in 3D), and then
// u_i = A_i⁻¹(f_i − B_iᵀλ). F is applied matrix-free (two solves per application) or formed
// explicitly when the interface is small; which one is reported. Explicitly, F is formed from
// each body's compliance on the dofs the rows touch (linalg::Compliance): no solve once the rows
// stay on dofs seen before, whatever the geometry of the step.
#include <Eigen/Dense>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "tc/contact/contact_rows.hpp"
#include "tc/core/verify.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/linalg/compliance.hpp"
#include "tc/qp/mpgp.hpp"

namespace tc::physics {

using contact::ContactRows;

enum class DualOperator { matrix_free, explicit_schur };
[[nodiscard]] const char* name(DualOperator k);

struct DualContactSettings {
  qp::QpOptions qp;
  /// F is formed explicitly when it has at most this many rows (m solves per body and an
  /// m×m dense matrix, against two solves per QP iteration matrix-free); 0 = never.
  PetscInt explicit_limit = 1500;
  /// Beyond explicit_limit, F is still formed explicitly up to this many rows while the
  /// compliance covers them (compliance_limit): then forming it costs no solve beyond the new
  /// dofs, and its dense products (m² flops, 512 MB at 8000 rows) cost less than the two body
  /// solves per QP iteration of the matrix-free F. Without it a case of 1875 rows spent 139 s
  /// in 6 steps' QPs (issue 22's "cliff at 1500 multipliers").
  PetscInt covered_limit = 8000;
  /// Explicit F from the compliance S = (A_i⁻¹)_TT on the dofs T the rows have touched while
  /// |T| stays at most this per body (|T|² doubles: 8000 → 512 MB); beyond, or with 0, F is
  /// formed by 2m solves at every set_rows.
  PetscInt compliance_limit = 8000;
  /// Explicit F only: solve the QP in μ = Σ⁻¹λ with Σ diagonal, one scale for the normal row
  /// and one for the tangent rows of each node (discs stay discs): Σ F Σ has a unit diagonal
  /// per node (docs/choices.md). Same minimiser; the stopping test is on Σ g^P against Σ d.
  bool scale = true;
  /// Threads that form the explicit F from the compliance (its bands of rows are independent);
  /// 0 = the thread policy's for a kernel of its size (core::KernelThreads). The same F to the
  /// bit with any number.
  int form_threads = 0;
};

/// The bodies of one contact pair among the bodies of a DualContactSolver.
struct PairBodies {
  int slave = 0, master = 1;
};

/// Body vectors of the dual solve, one per body of the solver, in its order.
using BodyVectors = std::span<const core::Vector* const>;
using BodyVectorsOut = std::span<core::Vector* const>;

class DualContactSolver {
 public:
  /// The bodies' factorised operators A_i and their displacement sizes (same order).
  DualContactSolver(std::vector<const ConstrainedSolver*> bodies, std::vector<PetscInt> n_u,
                    DualContactSettings settings);
  /// One pair: the slave is body 0, the master body 1.
  DualContactSolver(const ConstrainedSolver& slave, const ConstrainedSolver& master,
                    PetscInt n_u_slave, PetscInt n_u_master, DualContactSettings settings);

  /// Body i's solver was refactorised (ConstrainedSolver::refactorise): its compliance is
  /// formed anew from the new factor, the records of the old one dropped. The next set_rows
  /// forms F from it.
  void refactorised(int i);
  /// New constraint rows (each step, from the mortar pairs in the current configuration): the
  /// rows of every pair, stacked in this order (pair p's contact nodes follow pair p − 1's),
  /// with the bodies each pair's slave and master columns belong to.
  void set_rows(std::vector<ContactRows> pairs, std::vector<PairBodies> bodies);
  /// One pair on bodies 0 and 1.
  void set_rows(ContactRows rows);
  [[nodiscard]] int n_pairs() const { return static_cast<int>(pairs_.size()); }
  [[nodiscard]] const ContactRows& pair_rows(int p) const { return pairs_[p]; }
  [[nodiscard]] const std::vector<PairBodies>& pair_bodies() const { return pair_bodies_; }
  /// The first contact node of pair p in the stacked rows (p = n_pairs(): the total).
  [[nodiscard]] PetscInt pair_offset(int p) const { return offsets_[p]; }
  /// The rows of the one pair (set_rows with a single pair).
  [[nodiscard]] const ContactRows& rows() const {
    TC_VERIFY(pairs_.size() == 1, "one contact pair");
    return pairs_.front();
  }
  [[nodiscard]] int dim() const { return dim_; }
  [[nodiscard]] PetscInt n_nodes() const { return offsets_.back(); }
  [[nodiscard]] PetscInt n_rows() const { return dim_ * n_nodes(); }
  [[nodiscard]] DualOperator kind() const { return kind_; }
  /// The explicit F (dense m × m) of the last set_rows, Σ F Σ in its place when the QP is
  /// scaled (DualContactSettings::scale); null when matrix-free.
  [[nodiscard]] ::Mat explicit_matrix() const {
    return kind_ == DualOperator::explicit_schur ? f_dense_.get() : nullptr;
  }
  /// Solves applied while forming F explicitly in the last set_rows (0 when matrix-free; with
  /// the compliance, only the columns of newly touched dofs).
  [[nodiscard]] int setup_solves() const { return setup_solves_; }

  /// B u of the stacked rows, one vector per body.
  [[nodiscard]] std::vector<double> row_values(BodyVectors u) const;
  /// c of (5.4): c_n,k = g_k + (B u_ref)_n,k (non-penetration of the increment from the
  /// configuration of B) and c_τ = (B u_slip)_τ (the slip is measured from u_slip: u^k, or
  /// u^k + τ/2 u̇^k with Newmark, which makes B_τ u − c_τ = τ/2 B_τ u̇^{k+1}).
  [[nodiscard]] std::vector<double> targets(BodyVectors ref, BodyVectors slip) const;
  /// Adds `shift` (one per node, stacked like the rows) to the weighted gaps g_k of the last
  /// set_rows, i.e. to the normal targets c_n: the correction of the gap's linearisation along
  /// the step's predicted motion (ContactCoupling::set_rows). Until the next set_rows.
  void shift_gaps(std::span<const double> shift);
  [[nodiscard]] std::vector<double> targets(const core::Vector& ref_slave,
                                            const core::Vector& ref_master,
                                            const core::Vector& slip_slave,
                                            const core::Vector& slip_master) const {
    return targets(std::array{&ref_slave, &ref_master}, std::array{&slip_slave, &slip_master});
  }

  /// Given u_free,i = A_i⁻¹ f_i (with the Dirichlet values), the targets c and the friction
  /// bounds 𝔉γ_k per node, solves for λ (warm-started from its value on entry) and returns
  /// u_i = u_free,i − A_i⁻¹ B_iᵀ λ. With `recover` false u_i = u_free,i on return (two solves
  /// saved: see recover() and constraint_values()). `rtol` > 0 overrides the settings' QP
  /// tolerance (a looser one for the early updates of a fixed point).
  qp::QpResult solve(BodyVectors u_free, std::span<const double> c,
                     std::span<const double> friction_bound, core::Vector& lambda, BodyVectorsOut u,
                     bool recover = true, double rtol = 0);
  qp::QpResult solve(const core::Vector& u_free_slave, const core::Vector& u_free_master,
                     std::span<const double> c, std::span<const double> friction_bound,
                     core::Vector& lambda, core::Vector& u_slave, core::Vector& u_master,
                     bool recover = true, double rtol = 0) {
    return solve(std::array{&u_free_slave, &u_free_master}, c, friction_bound, lambda,
                 std::array{&u_slave, &u_master}, recover, rtol);
  }
  /// Until clear_rank_one (or the next set_rows), the QPs of solve() are those of
  /// F + weight·g gᵀ and d + shift·g: a face under load control whose displacement w is
  /// eliminated (ContactCoupling::solve_qp, docs/theory.md "Load control"). g is per row.
  void set_rank_one(std::vector<double> g, double weight, double shift) {
    rank_one_g_ = std::move(g);
    rank_one_weight_ = weight;
    rank_one_shift_ = shift;
  }
  void clear_rank_one() {
    rank_one_g_.clear();
    rank_one_weight_ = rank_one_shift_ = 0;
  }
  /// Nodes whose multipliers are held at 0 (λ_n ∈ [0, 0], λ_τ = 0) until the next set_rows:
  /// the crosspoints of a later pair (ContactCoupling), whose rows repeat an earlier pair's.
  void hold_at_zero(std::vector<char> held) { held_ = std::move(held); }
  [[nodiscard]] const std::vector<char>& held() const { return held_; }
  [[nodiscard]] bool held_at_zero(PetscInt k) const {
    return !held_.empty() && held_[static_cast<size_t>(k)] != 0;
  }
  /// u_i −= A_i⁻¹ B_iᵀ λ (a solve per body): what solve() skips with recover = false. A solve
  /// left half done by solve_free is finished here: u_i = A_i⁻¹(b_i − B_iᵀλ), all of it.
  void recover(const core::Vector& lambda, BodyVectorsOut u) const;
  /// u_i = A_i⁻¹b with the Dirichlet data in u_i, as body i's ConstrainedSolver::solve, when
  /// recover() follows before anything reads u_i off the contact dofs: where λ (the current
  /// iterate) loads the body, u_free and u_i = A_i⁻¹(b − B_iᵀλ) are one corrected solve of its
  /// compliance (linalg::Compliance::begin_corrected: u_i on T now, all that B_i and the QP
  /// read; recover() finishes it), which CHOLMOD's kept forward columns do for the price of one
  /// solve. Until then u_i off T may be stale. Whether a body's solve is corrected depends on λ
  /// alone, so a restarted run takes the same path.
  void solve_free(int i, const core::Vector& b, core::Vector& u, const core::Vector& lambda);
  void recover(const core::Vector& lambda, core::Vector& u_slave, core::Vector& u_master) const {
    recover(lambda, std::array{&u_slave, &u_master});
  }
  /// B u = B u_free − F λ of u = u_free − A⁻¹Bᵀλ without forming u (explicit F: one dense
  /// product; matrix-free: a solve per body).
  void constraint_values(BodyVectors u_free, const core::Vector& lambda, core::Vector& bu) const;
  void constraint_values(const core::Vector& u_free_slave, const core::Vector& u_free_master,
                         const core::Vector& lambda, core::Vector& bu) const {
    constraint_values(std::array{&u_free_slave, &u_free_master}, lambda, bu);
  }

  /// The bound on |(c − B u)_n,k| (the weighted gap's part of the gradient at node k) that
  /// the last solve guarantees: its stopping tolerance on ‖g^P‖ divided by node k's normal
  /// scale σ_n,k when the QP ran in μ = Σ⁻¹λ (1 otherwise). 0 before any solve.
  [[nodiscard]] double normal_gradient_bound(PetscInt k) const {
    const auto row = static_cast<size_t>(dim_ * k);
    return row < last_sigma_.size() ? last_tolerance_ / last_sigma_[row] : last_tolerance_;
  }

  /// y = Σ_i B_i A_i⁻¹ B_iᵀ x (matrix-free application; also used to form F).
  void apply_f(const core::Vector& x, core::Vector& y) const;

  /// The checkpoint's part of the compliances: their records (linalg::save_compliances), and
  /// S rebuilt from them with the same bits.
  void save_compliance(std::vector<std::vector<int>>& record) const {
    linalg::save_compliances(compliance_, record);
  }
  void replay_compliance(std::span<const std::vector<int>> record) {
    linalg::replay_compliances(compliance_, record, "contact");
  }
  /// How body i's compliance is grown (linalg::Compliance::path), and whether it holds any
  /// column yet.
  [[nodiscard]] const linalg::Compliance& compliance(int i) const { return *compliance_[i]; }

 private:
  [[nodiscard]] int n_bodies() const { return static_cast<int>(bodies_.size()); }
  void stack_rows();            // b_ from pairs_
  void form_scaled();           // Σ, and Σ F Σ in f_dense_'s place
  void form_by_solves();        // F column blocks by multi-right-hand-side solves
  bool form_from_compliance();  // F = Σ B_i,T S_i B_i,Tᵀ; false if T would pass the limit
  /// U_i, the T-positions in `pos`, with this rank's rows of S_i among them (used_, kept_,
  /// used_row_), and `pos` renumbered into U. S_UU itself is never copied: form_bands reads it
  /// from S tile by tile.
  void restrict_compliance(int i, std::vector<PetscInt>& pos);
  /// B_i's rows on the positions of U_i, each row's in ascending order (CSR).
  struct RowsT {
    std::vector<PetscInt> start, pos;
    std::vector<double> value;
  };
  /// F = Σ_i B_i,U S_i,UU B_i,Uᵀ into F's storage (column-major, leading dimension ldf), before
  /// its symmetrisation; B_i given by rows on U (RowsT).
  void form_bands(const std::vector<RowsT>& bt, double* fv, PetscInt ldf);
  /// form_bands' rows of F per band, and columns of W_i per tile: a tile of S_UU is
  /// |U| × kTile doubles (250 KB at |U| = 3 948, within a core's L2), its row sums in registers.
  static constexpr PetscInt kBand = 32, kTile = 8;

  std::vector<const ConstrainedSolver*> bodies_;
  DualContactSettings settings_;
  std::vector<ContactRows> pairs_;
  std::vector<PairBodies> pair_bodies_;
  std::vector<PetscInt> offsets_{0};  // first contact node of each pair, then the total
  int dim_ = 3;
  std::vector<core::SparseMatrix> b_;  // B_i: the stacked rows' columns of body i
  std::vector<double> gap_;            // the pairs' weighted gaps, stacked
  std::vector<char> held_;             // per node; empty: none held
  std::vector<double> rank_one_g_;     // set_rank_one: g per row (empty: none), weight, shift
  double rank_one_weight_ = 0, rank_one_shift_ = 0;
  DualOperator kind_ = DualOperator::matrix_free;
  core::Handle<::Mat, MatDestroy> f_dense_;  // F, or Σ F Σ (explicit and settings_.scale)
  std::vector<double> sigma_;                // the diagonal of Σ, per row
  int setup_solves_ = 0;
  double lambda_max_ = 0;           // reused while the number of rows does not change
  double last_tolerance_ = 0;       // the last solve's tolerance on ‖g^P‖ (its variables)
  std::vector<double> last_sigma_;  // … and its Σ (empty: unscaled)
  PetscInt lambda_max_rows_ = -1;
  std::vector<std::unique_ptr<linalg::Compliance>> compliance_;  // per body
  // form_from_compliance, per body: the T-position of each U-position (U: the T-positions the
  // rows reach), the rows of this rank's S that W_i = B_i,U S_i,UU has (its U-positions' rows,
  // all unless S's rows are spread), each U-position's row of W_i (−1: another rank's), and
  // W_i by bands of F's rows, kept between steps so that its pages are not faulted in again.
  std::vector<std::vector<PetscInt>> used_, kept_, used_row_;
  std::vector<std::vector<double>> w_bands_;
  mutable std::vector<core::Vector> w_in_, y_;  // per body: B_iᵀx and A_i⁻¹B_iᵀx
  // Per body: a corrected solve begun by solve_free for recover() to finish.
  mutable std::vector<linalg::CorrectedSolve> corrected_;
};

}  // namespace tc::physics
