#pragma once
// `subdomains = "auto"` (the default): one subdomain, the body's direct factorisation, while
// it fits comfortably in memory; FETI subdomains (6.2) beyond.

namespace tc::io {

/// Peak memory of a run's body solved directly [bytes], for `u_dofs` displacement dofs (its
/// matrices, the factors of the mechanical and heat operators, the vectors), fitted to serial
/// runs of one box body on the 2-core VM (docs/choices.md, "subdomains = auto").
[[nodiscard]] double direct_memory(int dim, double u_dofs);

/// Displacement dofs per subdomain when a body is decomposed: FETI's subdomain factors are
/// cheap there and its coarse problem stays small (bench/RESULTS.md, FETI).
inline constexpr double kDofsPerSubdomain = 40000;

/// 1 when direct_memory(dim, u_dofs) ≤ budget, else ⌈u_dofs / kDofsPerSubdomain⌉ (at least 2).
[[nodiscard]] int auto_subdomains(int dim, double u_dofs, double budget);

}  // namespace tc::io
