#pragma once
// `subdomains = "auto"` (the default): each body's direct path (its factorisation) against
// FETI subdomains (6.2), chosen by estimated memory and time: the faster path that fits, and
// the direct path wherever it fits and is not slower (docs/choices.md, "subdomains = auto").

#include <array>
#include <string>
#include <vector>

#include "tc/linalg/cholmod/cholmod_analysis.hpp"

namespace tc::mesh {
class Mesh;
}

namespace tc::io {

/// Peak memory of a body solved directly [bytes], for `u_dofs` displacement dofs, by a fit to
/// serial runs of one box body on the 2-core VM: the estimate of bodies too large to analyse
/// (kMaxAnalysedDofs). With `factor_ranks` > 1 the factors are spread over that many ranks
/// (MUMPS, as linalg::CholeskySolver does over the ranks) and the peak is that of one rank.
[[nodiscard]] double direct_memory(int dim, double u_dofs, int factor_ranks = 1);

/// Displacement dofs per subdomain when a body is decomposed: FETI's subdomain factors are
/// cheap there and its coarse problem stays small (bench/RESULTS.md, FETI).
inline constexpr double kDofsPerSubdomain = 40000;

/// Share of the machine's memory the bodies' solves may take together: the rest is for the
/// contact dual, the output and the system (4.7 GiB of the 23.5 GiB VM). The estimate is within
/// 8 % above the measured peaks (docs/choices.md), so no further margin is kept.
inline constexpr double kMemoryShare = 0.8;

/// What the process holds per byte of a CHOLMOD factor as cholmod_analyze sizes it (its values
/// and indices): 1.1, measured on the ch. 7 example ×3 and ×5.5 (the rest is CHOLMOD's and the
/// heap's; docs/choices.md, "subdomains = auto").
inline constexpr double kFactorOverhead = 1.1;

/// Bodies up to this many displacement dofs get CHOLMOD's symbolic analysis of their pattern
/// (a few seconds at 10⁶ dofs); larger ones the fit direct_memory, far beyond any budget here.
inline constexpr double kMaxAnalysedDofs = 1.5e6;

/// The symmetric pattern of a body's operator, the upper triangle row by row as
/// linalg::analyse_cholesky takes it: nodes coupled when they share a cell, `block` dofs per node
/// interleaved (block·a + k) as the assembler numbers them.
struct Pattern {
  std::vector<int> start, column;
};
[[nodiscard]] Pattern operator_pattern(const mesh::Mesh& mesh, int block);

/// What one body costs on each path, estimated before anything is assembled.
struct BodyCosts {
  double u_dofs = 0;
  bool analysed = false;              // from CHOLMOD's analysis of the pattern, else the fit
  linalg::FactorAnalysis mech, heat;  // the factors of A_u and A_θ (when analysed)
  double direct_bytes = 0;            // peak of the direct path on one rank of factor_ranks
  double factor_seconds = 0;          // its factorisations, once
  double direct_step_seconds = 0;     // its solves in one step
  int parts = 1;                      // FETI subdomains: ⌈u_dofs / kDofsPerSubdomain⌉, ≥ 2
  double feti_bytes = 0;              // peak of the FETI path
  double feti_setup_seconds = 0;      // its subdomains' factorisations, once
  double feti_step_seconds = 0;       // its solves in one step
};

/// The cost model's rates on the 2-core VM (docs/choices.md, "subdomains = auto"): CHOLMOD's
/// factorisation, one BLAS thread (the ch. 7 example ×3: 1.87e11 flops in 9.9 s); a solve's
/// two passes over the factor (bytes of it read per second, the memory's bandwidth) and the
/// full solves' worth a step makes of each body (the staggered loop's mechanical and heat
/// solves, most of them forward halves or skipped when idle: ×5.3, 7.4 s of mechanical solves
/// a step); FETI's iterations per solve (bench/feti, Dirichlet preconditioner, 40–41 from 27
/// subdomains). A contact body's compliance adds a right-hand side per multiplier at each
/// sliding step: FETI solves them all, the direct path restricted solves on its factor.
inline constexpr double kFactorFlopsPerSecond = 1.9e10;
inline constexpr double kSolveBytesPerSecond = 8e9;
inline constexpr double kSolvesPerStep = 3;
inline constexpr double kFetiIterations = 40;

/// The body's costs: its pattern analysed when it has at most kMaxAnalysedDofs (else the fit);
/// `compliance_columns` the multipliers of the contact pairs it is in (0 without contact).
[[nodiscard]] BodyCosts body_costs(const mesh::Mesh& mesh, int dim, int factor_ranks,
                                   double compliance_columns);

/// Subdomains per body (1 = solved directly) and why. Every body direct when the sum of the
/// direct peaks fits `budget`; else the largest bodies one by one to FETI until the sum fits.
/// A body also goes to FETI where its estimated run (factorisation and `steps` steps) is faster
/// there and fits. A budget ≤ 0 (memory unknown) keeps every body direct.
struct SubdomainChoice {
  std::vector<int> subdomains;
  std::vector<std::string> reasons;
};
[[nodiscard]] SubdomainChoice choose_subdomains(const std::vector<BodyCosts>& bodies, double budget,
                                                int steps);

/// A process's own memory before any body: PETSc, MPI, the libraries, the case and its meshes
/// (0.15 GiB measured before the assembly of the ch. 7 example ×3).
inline constexpr double kBaseBytes = 0.15 * 1024.0 * 1024.0 * 1024.0;

/// Memory left to the bodies with subdomains = "auto" [bytes]: kMemoryShare of memory_per_rank
/// less kBaseBytes and `fixed` (what the bodies with one subdomain take), at least 1; 0 when
/// the machine's memory is unknown (choose_subdomains then keeps every body direct).
[[nodiscard]] double auto_budget(double fixed);

inline constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

/// A lower bound of the memory a box body takes before any factorisation [bytes]: its mesh
/// and the five matrices that BodySystem assembles for the whole body (M_u, K_u, K_uθ, M_θ,
/// K_θ; AIJ, 12 bytes per nonzero, rows of 3^dim nodes). A box that does not fit it was
/// allocated until the OOM killer ended the process without a message (issue 20, #3).
[[nodiscard]] double box_memory(int dim, const std::array<int, 3>& cells);

/// This machine's physical memory [bytes] (0 if unknown).
[[nodiscard]] double physical_memory();

/// A rank's share of it: every rank holds every body and its direct factors (docs/choices.md,
/// "Replicated state"), so the ranks on one node each need what one rank alone would.
[[nodiscard]] double memory_per_rank();

/// " shared by N ranks" when more than one rank of the run is on this node, else "".
[[nodiscard]] std::string shared_by_ranks();

}  // namespace tc::io
