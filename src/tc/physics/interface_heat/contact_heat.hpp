#pragma once
// The heat of the contact interface (2.13, §4.4) from the multipliers and the slip of a step:
// the friction work per contact node, its distribution to the two bodies' nodes (d_θγ), and
// the conducted flux β_C λ_n [θ]. ContactCoupling::heat_step puts them into (4.3).
#include <span>
#include <vector>

#include "tc/contact/contact_rows.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/core/numeric/petsc.hpp"

namespace tc::physics {

/// The mean contact traction of a step per unit of λ. The contact-stabilised Newmark puts the
/// whole step's contact impulse on λ^{k+1}: its position update has τ²/4 Bᵀλ^{k+1} where every
/// other force enters as τ²/4 (F^k + F^{k+1}), so at rest 2(f − K u) = Bᵀλ, and the contact's
/// work in the discrete energy identity is ½ λᵀB(u^{k+1} − u^k). λ/2 is the traction there
/// (pressure for the conductance, force and work for the history); plain Newmark and the
/// quasistatic scheme have λ^{k+1} itself. The QP's bounds 𝔉λ_n are homogeneous: unchanged.
[[nodiscard]] double traction_per_multiplier(bool stabilised);

/// The work of friction in a step per contact node [J], W_k = λ_τ,k · (B_τ(u − u^k))_k (λ_τ a
/// traction, B_τ carries the weights). It is what leaves the mechanical energy: with Newmark's
/// average acceleration the discrete energy identity holds with λᵀB(u^{k+1} − u^k) as the
/// contact's work, and B_τ(u^{k+1} − u^k) = τ B_τ(u̇^k + u̇^{k+1})/2 is the slip of the step
/// (quasistatic: τ B_τu̇^{k+1}). W_k/τ is the step's mean of 𝔉γ‖[u̇]_τ‖ w_k of d_θγ (2.13,
/// §4.4): on a node sliding steadily λ_τ,k ∥ its slip with ‖λ_τ,k‖ = 𝔉λ_n,k. The power at
/// t^{k+1} alone, λ_τ·B_τu̇^{k+1}, would follow Newmark's step-to-step oscillation of u̇ (2v, 0,
/// 2v, … after a sudden start; docs/choices.md). W_k < 0 only where the slip reverses within a
/// step (nonnegative_heat).
[[nodiscard]] std::vector<double> friction_work(const contact::ContactRows& rows,
                                                std::span<const double> lambda,
                                                std::span<const double> slip);

/// B(u_s − u_s^k) + B(u_m − u_m^k), node-major (the normal rows are not used).
[[nodiscard]] std::vector<double> step_slip(const contact::ContactRows& rows,
                                            const core::Vector& du_slave,
                                            const core::Vector& du_master);

/// Nodal heat inputs of one body from the contact nodes' powers P_k ≥ 0 and the mortar matrix
/// X (D for the slave, M for the master): q_j = share Σ_k P_k X⁺_kj / Σ_j' X⁺_kj', X⁺ = max(X, 0).
/// With a flux density Σ_k (P_k/D_kk) ψ_k this is its integral against the body's shape
/// functions (∫ψ_kφ_j = X_kj, Σ_j X_kj = D_kk where the master covers ψ_k's support); the
/// dual basis ψ_k is negative on part of its support, so M has negative entries (measured in
/// example 06: 7 master nodes, −17 W of 4.9e5 W), which would cool them: X⁺ keeps every input
/// ≥ 0, and the row sums make 1ᵀq = share·ΣP exactly, also where the master covers part of it.
/// `share` is per contact node (δ_C,k of the slave, 1 − δ_C,k of the master).
[[nodiscard]] std::vector<double> distribute(std::span<const double> power,
                                             std::span<const double> share,
                                             const core::SparseMatrix& x);

/// The heat of a step per contact node from the friction work W_k: where the slip of the step
/// opposes λ_τ,k (the slip reverses within the step — the contact nodes' undamped Newmark
/// chatter; example 06: 5–8 of 42 nodes, −6e4 W against +2e5 W while sliding) W_k < 0 would
/// be a heat sink. The step's total Σ_k W_k, the mechanical dissipation, is kept and spread
/// in proportion to the positive parts; a step with Σ W ≤ 0 keeps W as it is.
[[nodiscard]] std::vector<double> nonnegative_heat(std::vector<double> work);

/// The master's temperature at each contact node of the mortar pair, (Mθ_m)_k/(D1)_k, and
/// (D1)_k: the mortar projection of θ_m onto the slave node (meaningful where (D1)_k > 0, the
/// master covering the node's support).
struct MasterAtNodes {
  std::vector<double> theta, d_sum;
};
[[nodiscard]] MasterAtNodes master_at_nodes(const contact::MortarPair& mortar,
                                            const core::Vector& theta_master);

/// The conducted flux q_C^s = β_C λ_n [θ] per contact node of the mortar pair (W/m², out of
/// the slave), [θ] = θ_s − θ_m with θ_m at the node (Mθ_m)_k/(D1)_k (master_at_nodes);
/// `scale` per contact node = β_C,k times the traction per multiplier; `open` (if not empty)
/// h(g_k) of the gap conductance per node, added: (scale_k λ_n,k⁺ + open_k)[θ]_k. Zero where
/// (D1)_k ≤ 0.
[[nodiscard]] std::vector<double> conduction_flux(
    const contact::MortarPair& mortar, const contact::ContactRows& rows,
    std::span<const double> lambda, std::span<const double> scale, const core::Vector& theta_slave,
    const core::Vector& theta_master, std::span<const double> open = {});

}  // namespace tc::physics
