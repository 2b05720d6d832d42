#pragma once
// `subdomains = "auto"` (the default): one subdomain, the body's direct factorisation, while
// the bodies' direct solves fit comfortably in memory together; FETI subdomains (6.2) for the
// largest bodies beyond.

#include <array>
#include <string>
#include <vector>

namespace tc::io {

/// Peak memory of a run's body solved directly [bytes], for `u_dofs` displacement dofs (its
/// matrices, the factors of the mechanical and heat operators, the vectors), fitted to serial
/// runs of one box body on the 2-core VM (docs/choices.md, "subdomains = auto").
/// With `factor_ranks` > 1 the factors are spread over that many ranks (MUMPS, as
/// core::CholeskySolver does over the ranks) and the peak is that of one rank: its share of
/// the factors, the matrices and vectors whole.
[[nodiscard]] double direct_memory(int dim, double u_dofs, int factor_ranks = 1);

/// Displacement dofs per subdomain when a body is decomposed: FETI's subdomain factors are
/// cheap there and its coarse problem stays small (bench/RESULTS.md, FETI).
inline constexpr double kDofsPerSubdomain = 40000;

/// Memory of a body cut into subdomains of kDofsPerSubdomain [bytes]: their direct solves.
[[nodiscard]] double decomposed_memory(int dim, double u_dofs);

/// Share of the machine's memory the bodies' solves may take together: the rest is for the
/// contact dual, the output and the system. direct_memory is above the measured peaks of
/// non-cubic bodies (docs/choices.md), so the runs stay below about two thirds.
inline constexpr double kMemoryShare = 0.75;

/// Subdomains per body (1 = solved directly): every body directly when the sum of
/// direct_memory fits `budget`; else the largest bodies are decomposed, ⌈u_dofs /
/// kDofsPerSubdomain⌉ subdomains each (at least 2), one by one until the sum fits. A budget
/// ≤ 0 (memory unknown) keeps every body direct.
[[nodiscard]] std::vector<int> auto_subdomains(int dim, const std::vector<double>& u_dofs,
                                               double budget, int factor_ranks = 1);

/// Memory left to the bodies with subdomains = "auto" [bytes]: kMemoryShare of memory_per_rank
/// less what the bodies with one subdomain take (approximately: as if direct), at least 1; 0
/// when the machine's memory is unknown (auto_subdomains then keeps every body direct).
[[nodiscard]] double auto_budget(int dim, const std::vector<double>& direct_u_dofs,
                                 int factor_ranks);

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
