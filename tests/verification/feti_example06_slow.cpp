// Example 06 (the ch. 7.2.2 frictional heating, all 100 steps, the default dynamic contact
// scheme) with each body cut into 4 subdomains (FETI) must reproduce the undecomposed history
// to 1e-6, on one rank and through the MPI launcher on two (issue 18: with the contact-
// stabilised scheme the same comparison drifted by up to 87 % in thermal energy, the sliding
// being chaotic; the modified mass is not). The solver tolerances are tightened as in
// tests/cases/feti/thesis-coarse.toml (QP 1e-11, coupling 1e-10, FETI 1e-12) so that the
// solver paths' differences stay far below 1e-6 (4e-8 measured, the vertical reactions).
// Slow: about a minute per decomposed run on the 2-core machine.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

std::string tight(std::string text) {
  text =
      replace_all(text, "[solver]\n", "[solver]\nqp_tolerance = 1e-11\nfeti_tolerance = 1e-12\n");
  text = replace_all(text, "coupling_tolerance = 1e-6", "coupling_tolerance = 1e-10");
  return replace_all(text, "every = 25", "every = 1000");
}

TEST(FetiExample06, FourSubdomainsPerBodyReproduceTheUndecomposedHistory) {
  const auto dir = fresh_dir("feti-example06");
  const auto text = tight(read_file(std::filesystem::path(TC_SOURCE_DIR) /
                                    "examples/06-thesis-frictional-heating/case.toml"));
  ASSERT_NE(text.find("qp_tolerance = 1e-11"), std::string::npos);
  ASSERT_NE(text.find("coupling_tolerance = 1e-10"), std::string::npos);
  std::ofstream(dir / "whole.toml") << text;
  std::ofstream(dir / "cut.toml") << replace_all(text, "initial_temperature = 293.15\n",
                                                 "initial_temperature = 293.15\nsubdomains = 4\n");
  const auto whole = thermocontact(
      fmt::format("run {} --output {}", (dir / "whole.toml").string(), (dir / "whole").string()));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto one = thermocontact(
      fmt::format("run {} --output {}", (dir / "cut.toml").string(), (dir / "np1").string()));
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_NE(read_file(dir / "np1/summary.json").find("\"subdomains\": 8"), std::string::npos);
  const auto two = run_command(
      fmt::format("env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
                  "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
                  "{} -n 2 {} run {} --output {}",
                  TC_MPIEXEC, TC_BINARY, (dir / "cut.toml").string(), (dir / "np2").string()));
  ASSERT_EQ(two.exit_code, 0) << two.output;
  const auto a = read_history(dir / "whole/history.csv");
  ASSERT_EQ(a.rows.size(), 101u);
  ASSERT_GT(column(a, "heat_generated").back(), 0.0);
  for (const char* run : {"np1", "np2"}) {
    const auto b = read_history(dir / run / "history.csv");
    ASSERT_EQ(a.rows.size(), b.rows.size()) << run;
    for (const auto& [name, d] : column_differences(a, b)) EXPECT_LT(d, 1e-6) << run << " " << name;
    EXPECT_EQ(column(a, "active_nodes"), column(b, "active_nodes")) << run;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tc::test
