#pragma once
// The time schemes of chapter 5: Newmark's average acceleration (5.1–5.3, β = 1/4, γ = 1/2)
// or the quasistatic scheme for u, backward Euler (5.5–5.6) for θ. Newmark's coefficient of
// M_u is written here only.
namespace tc::physics {

/// 4/τ²: M_u's coefficient in Newmark's step (5.3), (4/τ² M_u + K_u) u^{k+1} = f^{k+1} +
/// M_u(4/τ² u_pred + ü^k) with u_pred = u^k + τu̇^k, and in its update (5.1)
/// ü^{k+1} = 4/τ²(u^{k+1} − u_pred) − ü^k.
[[nodiscard]] constexpr double newmark_mass_factor(double tau) {
  return 4.0 / (tau * tau);
}

}  // namespace tc::physics
