// What a run leaves behind (case-format.md): result.pvd listing one .vtu per body and written
// step, history.csv with the contract's columns and one row per step, summary.json.
#include <gtest/gtest.h>

#include <regex>

#include "support/cli.hpp"
#include "support/problems.hpp"
#include "tc/io/output/output.hpp"
#include "tc/model/checks.hpp"

using namespace tc;

namespace {

physics::Problem small_case() {
  auto p =
      test::box_problem(3, {1, 1, 1}, {2, 2, 2}, test::steel(), physics::Scheme::dynamic, 1e-4, 5);
  p.boundaries.push_back(test::hold("zmin", {0, 1, 2}));
  physics::BoundaryCondition top;
  top.where = "zmax";
  top.traction[2] = core::TimeTable(-1e5);
  top.heat_flux = core::TimeTable(1e3);
  p.boundaries.push_back(top);
  return p;
}

TEST(Output, LeavesPvdVtuHistoryAndSummary) {
  const auto p = small_case();
  const auto dir = test::fresh_dir("output");
  physics::Simulation sim(p);
  io::OutputWriter writer(dir, 2);
  const auto status = sim.run(writer);
  ASSERT_TRUE(status.completed) << status.message;

  const auto history = test::read_file(dir / "history.csv");
  const std::string header = history.substr(0, history.find('\n'));
  for (const char* col : {"step",
                          "time",
                          "coupling_iterations",
                          "qp_iterations",
                          "operator_applications",
                          "kinetic_energy",
                          "strain_energy",
                          "thermal_energy",
                          "external_work",
                          "contact_normal_force",
                          "contact_tangential_force",
                          "frictional_dissipation",
                          "heat_generated",
                          "heat_to_slave",
                          "heat_to_master",
                          "heat_conducted",
                          "max_temperature",
                          "min_temperature",
                          "active_nodes",
                          "slip_nodes",
                          "wall_seconds",
                          "reaction_block_zmin_x",
                          "reaction_block_zmin_y",
                          "reaction_block_zmin_z"})
    EXPECT_NE(header.find(col), std::string::npos) << col;
  EXPECT_EQ(std::count(history.begin(), history.end(), '\n'), 1 + 6);  // header, t = 0..5

  // Steps 0, 2, 4 by `every`, and the last one (5) always.
  const auto pvd = test::read_file(dir / "result.pvd");
  for (const char* f :
       {"block_000000.vtu", "block_000002.vtu", "block_000004.vtu", "block_000005.vtu"}) {
    EXPECT_NE(pvd.find(f), std::string::npos) << f;
    const auto vtu = test::read_file(dir / f);
    EXPECT_NE(vtu.find("NumberOfPoints=\"27\" NumberOfCells=\"8\""), std::string::npos);
    for (const char* name :
         {"displacement", "velocity", "temperature", "von_mises_stress", "heat_flux", "subdomain"})
      EXPECT_NE(vtu.find(std::string("Name=\"") + name + "\""), std::string::npos) << name;
  }
  EXPECT_EQ(pvd.find("block_000001.vtu"), std::string::npos);

  const auto summary = test::read_file(dir / "summary.json");
  for (const char* key :
       {"\"status\": \"completed\"", "\"steps_done\": 5", "\"assembly\"", "\"mortar\"",
        "\"factorization\"", "\"heat_solve\"", "\"qp\"", "\"output\"", "\"coupling_iterations\"",
        "\"dofs\": 108", "\"multipliers\"", "\"ranks\"", "\"subdomains\"", "\"last\""})
    EXPECT_NE(summary.find(key), std::string::npos) << key;

  // The peak memory of the ranks (one here) and the phases' rises of it, which cannot add up
  // to more than the peak itself.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      summary, m,
      std::regex(
          R"re("peak_memory_gib": \{"largest_rank": ([0-9.]+), "smallest_rank": ([0-9.]+), "phases": \{(.*)\}\})re")));
  const double largest = std::stod(m[1]), smallest = std::stod(m[2]);
  EXPECT_GT(smallest, 0.0);
  EXPECT_EQ(largest, smallest);  // one rank
  double phases = 0;
  const std::string listed = m[3];
  const std::regex value(R"re(: ([0-9.]+))re");
  int n_phases = 0;
  for (auto it = std::sregex_iterator(listed.begin(), listed.end(), value);
       it != std::sregex_iterator(); ++it, ++n_phases)
    phases += std::stod((*it)[1]);
  EXPECT_EQ(n_phases, 7);
  EXPECT_LE(phases, largest + 0.004);  // each phase rounded to 0.001 GiB
}

TEST(Output, SupportHoldsTheLoadInStatics) {
  // Quasistatic: the reaction of the clamped base balances the traction on top exactly.
  auto p = small_case();
  p.time.scheme = physics::Scheme::quasistatic;
  p.physics.thermal_expansion = false;
  ASSERT_EQ(physics::free_rigid_modes(p, 0), 0);
  physics::Simulation sim(p);
  sim.advance();
  // Equilibrium of a direct solve: round-off relative to the load (1e5 N on 1 m²).
  EXPECT_NEAR(sim.history("reaction_block_zmin_z"), 1e5, 1e-6);
  EXPECT_NEAR(sim.history("reaction_block_zmin_x"), 0.0, 1e-6);
}

TEST(Output, FreeRigidModesAreCounted) {
  auto p = small_case();
  p.boundaries.clear();
  EXPECT_EQ(physics::free_rigid_modes(p, 0), 6);
  p.boundaries.push_back(test::hold("zmin", {2}));  // z, rot x, rot y held
  EXPECT_EQ(physics::free_rigid_modes(p, 0), 3);
  p.boundaries.push_back(test::hold("xmin", {0}));  // + x, rot z
  EXPECT_EQ(physics::free_rigid_modes(p, 0), 1);
  p.boundaries.push_back(test::hold("ymin", {1}));
  EXPECT_EQ(physics::free_rigid_modes(p, 0), 0);
}

TEST(Output, JsonStringsAreEscaped) {
  EXPECT_EQ(io::json_string("a\"b\\c\nd"), "\"a\\\"b\\\\c\\nd\"");
}

}  // namespace
