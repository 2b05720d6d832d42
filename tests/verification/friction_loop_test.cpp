// The Tresca → Coulomb updates γ = λ_n of (6.3) nested in the mechanical half (the default)
// against the staggered loop as (6.3) writes it (docs/choices.md): both must stop at the same
// fixed point of every step, and the nested one with fewer heat–mechanics iterations. The same
// for the order of the two halves (heat first, as the thesis, or mechanics first).
//
// The case is the thesis example of ch. 7 on the coarse mesh of tests/cases/feti (0.3 s:
// approach, pressing, the start of sliding), here with conduction across the contact as well
// as frictional heating and thermal expansion: all three couplings at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "support/history.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

struct Rows : physics::Observer {
  History h;
  void start(const physics::Simulation& sim) override { h.columns = sim.history_columns(); }
  void step(const physics::Simulation& sim) override { h.rows.push_back(sim.history_row()); }
};

struct Run {
  History history;
  long coupling = 0;
  long updates = 0;
};

Run run(physics::FrictionLoop loop,
        physics::CouplingOrder order = physics::CouplingOrder::automatic,
        bool thermoelastic_heating = false, double coupling_tolerance = 1e-6,
        double qp_tolerance = 1e-8) {
  auto p =
      io::read_case(std::filesystem::path(TC_SOURCE_DIR) / "tests/cases/feti/thesis-coarse.toml");
  p.contacts.at(0).heat_conduction = true;
  // The defaults of case-format.md, not the FETI test's tight ones: what users run.
  p.solver.coupling_tolerance = coupling_tolerance;
  p.solver.qp_tolerance = qp_tolerance;
  p.solver.friction_loop = loop;
  p.solver.coupling_order = order;
  p.physics.thermoelastic_heating = thermoelastic_heating;
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  Rows rows;
  const auto status = sim.run(rows);
  EXPECT_TRUE(status.completed) << status.message;
  Run r{rows.h, sim.total_coupling_iterations(), 0};
  for (const double u : column(r.history, "friction_iterations")) r.updates += std::lround(u);
  return r;
}

TEST(FrictionLoop, NestedAndStaggeredStopAtTheSameFixedPoint) {
  const auto nested = run(physics::FrictionLoop::nested);
  const auto staggered = run(physics::FrictionLoop::staggered);
  ASSERT_EQ(nested.history.rows.size(), staggered.history.rows.size());
  ASSERT_GT(column(nested.history, "heat_generated").back(), 0.0);  // sliding was reached
  ASSERT_GT(std::abs(column(nested.history, "heat_conducted").back()), 0.0);
  // Each scheme stops within coupling_tolerance = 1e-6 of the step's fixed point (the
  // staggered loop on the last change, the nested one on the distance estimated from the
  // sweep's contraction, docs/choices.md), relative to ‖λ‖ and ‖θ‖, and the state carries the
  // remainder on: over 30 steps the columns may drift apart by up to 30 · 1e-6 (the heat
  // columns, sums of per-step heats, the most: 1.1e-5 measured; strain energy 4.3e-6).
  // heat_conducted, Σ β_C λ_n [θ] τ, carries the jump [θ] = θ_s − θ_m, a small difference of
  // temperatures near 293 K: an error of tol·‖θ‖ in θ is amplified by θ/[θ] in it (5.8e-5
  // measured with the modified mass, 1.1e-5 with the contact-stabilised scheme), so it gets
  // 100 · 1e-6.
  const double bound = 30 * 1e-6;
  for (const auto& [name, d] : column_differences(staggered.history, nested.history)) {
    if (name == "slip_nodes" || name == "active_nodes" || name == "friction_iterations") continue;
    EXPECT_LT(d, name == "heat_conducted" ? 100e-6 : bound) << name;
  }
  // Which nodes touch must not depend on the scheme. Which of them slide is decided at the
  // friction circle, |λ_τ| ≥ 𝔉λ_n(1 − 1e-6), where nodes sit on the edge while sliding sets
  // in: a change of summation order in the Dirichlet lifting alone flipped 3 of 20, so the
  // slip count is compared to 5 nodes (5 seen at step 30 with the modified mass, when sliding
  // sets in).
  EXPECT_EQ(column(staggered.history, "active_nodes"), column(nested.history, "active_nodes"));
  const auto slip_s = column(staggered.history, "slip_nodes");
  const auto slip_n = column(nested.history, "slip_nodes");
  for (size_t k = 0; k < slip_s.size(); ++k)
    EXPECT_LE(std::abs(slip_s[k] - slip_n[k]), 5.0) << "slip_nodes at step " << k + 1;
  // What the nesting is for: the heat and mechanical solves go with the outer iterations.
  EXPECT_LT(nested.coupling, staggered.coupling);
  // In the staggered loop every heat–mechanics iteration makes one update.
  EXPECT_EQ(staggered.updates, staggered.coupling);
  EXPECT_GE(nested.updates, nested.coupling);
  std::printf("coupling iterations nested %ld / staggered %ld; γ updates %ld / %ld\n",
              nested.coupling, staggered.coupling, nested.updates, staggered.updates);
}

TEST(CouplingOrder, HeatFirstAndMechanicsFirstStopAtTheSameFixedPoint) {
  // With the thermoelastic term the heat step reads u̇ = (u − u^k)/τ of the current iterate, so
  // heat first starts from the predictor's error over τ, mechanics first from θ^k's
  // (docs/choices.md, "The order of the staggered fixed point"). Both stop within
  // coupling_tolerance of each step's fixed point. At the default 1e-6 heat first ends each step
  // on a mechanical half, so its heat was made with the previous iterate's u, off the fixed
  // point by ε‖u‖ — and ‖u‖ holds the 5 cm slide, so that is θ₀K_uθᵀδu of up to 3.6e-4 of the
  // thermal energy (a mean 2e-5 K) over 30 steps, far below ε‖θ‖ per node but above 30 · ε
  // of the column. The same fixed point shows as the differences falling with the tolerance:
  // at 1e-8 the bounds of the nested/staggered comparison above, scaled (30 steps, 30 · 1e-8;
  // heat_conducted, a small jump of temperatures near 293 K, 100 · 1e-8).
  const double tol = 1e-8;
  const auto heat =
      run(physics::FrictionLoop::nested, physics::CouplingOrder::heat_first, true, tol, 1e-2 * tol);
  const auto mech = run(physics::FrictionLoop::nested, physics::CouplingOrder::mechanics_first,
                        true, tol, 1e-2 * tol);
  ASSERT_EQ(heat.history.rows.size(), mech.history.rows.size());
  ASSERT_GT(column(heat.history, "heat_generated").back(), 0.0);
  for (const auto& [name, d] : column_differences(heat.history, mech.history)) {
    if (name == "slip_nodes" || name == "active_nodes" || name == "friction_iterations") continue;
    EXPECT_LT(d, name == "heat_conducted" ? 100 * tol : 30 * tol) << name;
  }
  EXPECT_EQ(column(heat.history, "active_nodes"), column(mech.history, "active_nodes"));
  // What the order is for: one heat–mechanics iteration less in most steps (here 151 → 104).
  // The default picks mechanics first here.
  EXPECT_LT(mech.coupling, heat.coupling);
  EXPECT_FALSE(physics::heat_before_mechanics(physics::CouplingOrder::automatic, true));
  EXPECT_TRUE(physics::heat_before_mechanics(physics::CouplingOrder::automatic, false));
  std::printf("coupling iterations heat first %ld / mechanics first %ld\n", heat.coupling,
              mech.coupling);
}

}  // namespace
}  // namespace tc::test
