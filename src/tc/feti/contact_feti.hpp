#pragma once
// The single dual QP of TFETI for two bodies in contact (6.2, 6.4): the gluing and Dirichlet
// multipliers of both decomposed bodies and the contact multipliers together,
//   min ½λᵀFλ − λᵀd   over λ ∈ Ω and Gλ = e,
//   B = [B_0 0; 0 B_1; B_c],  F = Σ_s B_s A_s⁺ B_sᵀ,  d = Σ_s B_s A_s⁺ f_s − c,
//   G = RᵀBᵀ,  e = Rᵀf,
// where the contact rows B_c (given in body dofs) enter B on one subdomain copy of every dof
// they touch, Ω leaves the gluing and Dirichlet multipliers free, bounds the normal ones
// (λ_n ≥ 0) and the tangential ones by a fixed Tresca bound (|λ_τ| ≤ 𝔉γ in 2D, a disc in 3D).
// Solved by SMALBE with MPGP inside (qp::Smalbe); F is applied by one solve on every subdomain
// of both bodies — against the nested form (physics::DualContactSolver on feti::Feti), whose F
// = B_c A⁻¹ B_cᵀ costs two full FETI solves per application.
//
// Quasistatic only: A_s is the stiffness, the floating subdomains' rigid motions enter
// through G (both Feti objects built with Kernel::rigid, Singular::yes). The subdomains, their
// factorisations, kernels and gluing/Dirichlet rows are those of the two Feti objects; their
// dealing to ranks too (dual vectors replicated, F products summed by MPI_Allreduce).
#include <span>
#include <vector>

#include "tc/feti/feti.hpp"
#include "tc/qp/smalbe.hpp"

namespace tc::feti {

struct ContactFetiOptions {
  /// ρ = 100 λ_max(F): on the two blocks (tests/mpi/feti_contact_mpi_test.cpp, H/h = 2) 426
  /// applications of F against 474 with 10 and 811 with 1, the outer iterations 9 against 14
  /// and 34 (docs/choices.md, FETI).
  qp::SmalbeOptions smalbe = [] {
    qp::SmalbeOptions o;
    o.rho_factor = 100;
    return o;
  }();
  /// The lumped FETI preconditioner Σ_s B_s A_s B_sᵀ (contact rows included) for MPGP's CG
  /// steps in the face (QpOptions::preconditioner); the fixed-step moves stay unpreconditioned.
  bool lumped_preconditioner = false;
};

/// The dual state of a solve beyond the contact multipliers, to start the next one from
/// (warm start): the gluing and Dirichlet multipliers of both bodies and SMALBE's μ. Their
/// sizes depend only on the two decompositions, not on the contact rows, so a state carries
/// over to a ContactFeti rebuilt on other rows (the contact part comes from `lambda`).
struct ContactFetiState {
  Eigen::VectorXd body;  // λ of the gluing and Dirichlet rows (body 0's, then body 1's)
  Eigen::VectorXd mu;    // SMALBE's multiplier of Gλ = e (−α, the rigid motions' amplitudes)
};

struct ContactFetiStatistics {
  int applications = 0;  // of the combined F (each one solve per subdomain)
  double seconds = 0;    // wall time of the last solve, this rank
};

class ContactFeti {
 public:
  /// `slave`, `master`: the two bodies' FETI solvers (quasistatic, rigid kernels, on the same
  /// communicator). `b_slave`, `b_master`: the contact rows in each body's dofs (node-major:
  /// row dim·k the normal of contact node k, then its dim − 1 tangents; see
  /// contact::ContactRows), replicated on every rank.
  ContactFeti(const Feti& slave, const Feti& master, const core::SparseMatrix& b_slave,
              const core::SparseMatrix& b_master, int dim);
  ~ContactFeti();
  ContactFeti(const ContactFeti&) = delete;
  ContactFeti& operator=(const ContactFeti&) = delete;

  /// b_i: the loads; x_i: the prescribed values at the Dirichlet dofs on entry, the
  /// displacements on exit. c: the contact targets (B_c u ≤ c on the normal rows, = c on the
  /// tangential ones while sticking); friction_bound: 𝔉γ per contact node (0: frictionless).
  /// lambda: the contact multipliers on exit (in the rows' units, as the nested solver's).
  /// `warm`: null for a cold start (λ = 0, μ = 0); else SMALBE starts from the contact
  /// multipliers of `lambda` on entry, and from warm's gluing/Dirichlet λ and μ when they
  /// have this problem's sizes (0 otherwise); warm holds this solve's on exit. λ_max(F) is
  /// estimated at the first solve of this object and reused by the next ones (F is fixed by
  /// the rows). Collective.
  qp::SmalbeResult solve(const core::Vector& b_slave, const core::Vector& b_master,
                         std::span<const double> c, std::span<const double> friction_bound,
                         core::Vector& x_slave, core::Vector& x_master, core::Vector& lambda,
                         const ContactFetiOptions& options = {},
                         ContactFetiState* warm = nullptr) const;

  [[nodiscard]] Eigen::Index n_multipliers() const { return m_; }
  [[nodiscard]] Eigen::Index n_contact() const { return m_ - offset_[2]; }
  [[nodiscard]] Eigen::Index coarse_dimension() const { return g_.rows(); }
  [[nodiscard]] const ContactFetiStatistics& statistics() const { return stats_; }

 private:
  struct Part;  // one subdomain of one body with its rows of the combined B
  using Local = void (Feti::Subdomain::*)(Eigen::MatrixXd&, Eigen::MatrixXd&) const;
  using DualIn = Eigen::Ref<const Eigen::VectorXd>;  // a replicated dual vector, not copied
  using DualOut = Eigen::Ref<Eigen::VectorXd>;
  void sum_subdomain_products(DualIn x, DualOut y, const char* phase, Local local) const;
  void apply_f(DualIn x, DualOut y) const;
  void precondition(DualIn x, DualOut y) const;
  void sum_over_ranks(double* data, Eigen::Index n) const;

  const Feti* body_[2];
  int dim_;
  MPI_Comm comm_;
  std::vector<Part> parts_;             // body 0's subdomains, then body 1's
  Eigen::Index offset_[3] = {0, 0, 0};  // first row of body 0, body 1, contact
  Eigen::Index m_ = 0;
  std::vector<double> node_scale_;  // per contact node: 1/‖normal row‖ (unit contact rows)
  Eigen::SparseMatrix<double> g_;   // G = RᵀBᵀ, all kernels × m
  mutable double lambda_max_ = 0;   // λ_max(F) of the first solve, reused
  mutable ContactFetiStatistics stats_;
};

}  // namespace tc::feti
