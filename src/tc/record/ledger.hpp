#pragma once
// The run's ledger: what the contact, the interface heat and the boundary heat did, step by
// step and cumulatively (the history.csv columns, summary.json, checkpoints).
#include <span>
#include <string>

#include "tc/contact/contact_rows.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/record/history.hpp"

namespace tc::physics {

/// What the contact did in the last step (history.csv columns).
struct ContactStatistics {
  int qp_iterations = 0;
  int operator_applications = 0;
  int friction_iterations = 0;      // QPs of the step: Tresca → Coulomb updates γ = λ_n (6.3)
  double normal_force = 0;          // Σ_k w_k λ_n,k
  double tangential_force = 0;      // ‖Σ_k w_k λ_τ,k‖: the resultant's magnitude
  double tangential_force_sum = 0;  // Σ_k w_k ‖λ_τ,k‖
  double dissipation = 0;           // cumulative Σ_steps λ_τᵀ B_τ Δu (J)
  int active_nodes = 0;             // λ_n,k > 0
  int slip_nodes = 0;               // active, on the Tresca bound of the step's last QP

  /// A node slips when it lies on the friction circle of the QP that produced λ,
  /// ‖λ_τ,k‖ ≥ 𝔉_kγ_k(1 − slip_tolerance) with 𝔉_kγ_k > 0: exact to the QP's accuracy, where
  /// the Coulomb circle 𝔉_kλ_n,k is met only to the fixed point's (the coupling tolerance on
  /// ‖λ‖, 1e-5 of a node's ratio seen on examples/07, which counted slipping nodes as stuck).
  static constexpr double slip_tolerance = 1e-6;

  /// The forces and node counts of the step from its multipliers (node-major, `unit` the
  /// traction per multiplier), and its friction work per node `work` (λ_τ,k·slip_k,
  /// friction_work in contact_heat.hpp) added to the dissipation. The resultant uses the
  /// mortar pair's tangents when there is one. `bound` holds the Tresca bound 𝔉_kγ_k of the
  /// last QP per contact node (empty: no friction).
  void record_step(const contact::ContactRows& rows, std::span<const double> lambda,
                   std::span<const double> work, double unit, std::span<const double> bound,
                   const contact::MortarPair* mortar);
  /// Its history.csv columns (qp_iterations, operator_applications, the forces, the
  /// dissipation, the node counts, friction_iterations).
  void register_history(History& h) const;
  /// The columns of one pair among several: its forces, dissipation and node counts, each
  /// name followed by `suffix`.
  void register_pair_history(History& h, const std::string& suffix) const;
};

/// Heat through the contact interface, cumulative from t = 0 [J] (history.csv):
///  generated = Σ_steps λ_τᵀB_τΔu (the friction work of the step, the discrete τ∫𝔉λ_n‖[u̇]_τ‖dS;
///  = frictional_dissipation), to_slave / to_master its δ_C / 1 − δ_C shares,
///  conducted = Σ_steps τ β_C ∫ λ_n (θ_s − θ_m) dS: the heat that crossed by conductance from
///  the slave to the master (negative when it went the other way), θ at t^{k+1}. With the
///  contact-stabilised Newmark λ/2 is the traction (traction_per_multiplier, contact_heat.hpp):
///  these sums, the conductance and the history's forces use it.
struct ContactHeat {
  double generated = 0, to_slave = 0, to_master = 0, conducted = 0;
  /// The part of `conducted` through the gap conductance h(g) (gap_conductance.hpp).
  double gap_conducted = 0;

  /// Its history.csv columns heat_generated, heat_to_slave, heat_to_master, heat_conducted,
  /// each name followed by `suffix` (one pair among several); with `gap`, heat_gap_conducted
  /// too (a pair with a gap conductance: the histories of the others keep their columns).
  void register_history(History& h, const std::string& suffix = "", bool gap = false) const;
};

/// Heat lost through the film and the radiation boundaries of all bodies, cumulative from
/// t = 0 [J] (history.csv heat_film, heat_radiation): Σ_steps τ Σ h∫(θ − θ∞)dS and
/// Σ_steps τ Σ ∫εσ(θ⁴ − θ∞⁴)dS at t^{k+1} (negative when the body gained heat).
struct BoundaryHeat {
  double film = 0, radiation = 0;

  /// Adds one body's heat of the step that ended at t: τ h∫(θ − θ∞)dS and τ ∫εσ(θ⁴ − θ∞⁴)dS
  /// at t^{k+1} with θ^{k+1} (`film`, `radiation`: the powers, BodySystem::boundary_heat_loss),
  /// the terms of the backward Euler step, so that Δthermal_energy = heat in − heat_film −
  /// heat_radiation closes to the solver tolerance. Called for every body, in their order.
  void account_step(double film_power, double radiation_power, double tau);
  /// Its history.csv columns heat_film, heat_radiation.
  void register_history(History& h) const;
};

}  // namespace tc::physics
