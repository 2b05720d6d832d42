#pragma once
// What a restart needs (io/restart/checkpoint.hpp writes and reads it; Simulation::checkpoint and
// restore in checkpoint.cpp fill and replay it, each component its own part).
#include <vector>

#include "tc/record/ledger.hpp"

namespace tc::physics {

/// Everything the steps after `step` depend on, for a restart (io/restart/checkpoint.hpp writes
/// it): the state of every body, the multipliers and their slave nodes (the next step's warm
/// start), and the cumulative ledger behind the history.csv columns.
struct Checkpoint {
  struct Body {
    std::vector<double> u, v, a, theta;
    std::vector<double> force;  // f_ext + reactions at t^step (trapezoidal external work)
    std::vector<double> g_free;  // f − K u − K_uθ(θ − θ₀) (dynamic runs; contact-stabilised)
  };
  int step = 0;
  std::vector<Body> bodies;
  /// Per contact pair: what its multipliers refer to (the next step's warm start) and its
  /// ledger.
  struct Pair {
    std::vector<int> lambda_nodes;        // slave mesh node of each contact node of the pair
    std::vector<double> lambda_tangents;  // 3D mortar: t_1 then t_2 of each node, xyz
    ContactStatistics contact;
    ContactHeat heat;
  };
  std::vector<double> lambda;  // node-major multipliers of the last step, pair after pair
  std::vector<Pair> pairs;
  // The compliance records (linalg::Compliance::dofs, chunks) of each contact body of the contact
  // solver, then of the stabiliser's: replayed on restore, so F has the same bits.
  std::vector<std::vector<int>> compliance, stabiliser_compliance;
  // The same for the interface heat solver's S (InterfaceHeatSolver: each contact body's
  // temperature dofs on Γ that carried conductance; empty before the first such heat step).
  std::vector<std::vector<int>> heat_compliance;
  std::vector<double> slip, heat_flux;
  std::vector<double> row;  // the history row of `step`
  double external_work = 0;
  long total_coupling = 0, total_qp = 0, total_applications = 0;
  int last_coupling = 0;
  // The combined contact dual's warm start (gluing and Dirichlet λ, μ) and SMALBE's outer
  // iterations so far (empty and 0 with the nested dual).
  std::vector<double> feti_body_lambda, feti_mu;
  long total_smalbe_outer = 0;
  BoundaryHeat boundary_heat;
};

}  // namespace tc::physics
