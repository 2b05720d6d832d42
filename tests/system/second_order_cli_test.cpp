// Second-order cells through the command line (issue 37, bulk): a dynamic Hex20 box with a
// film and a heat flux, cut into FETI subdomains, runs, writes VTK's quadratic hexahedra and
// restarts to the same history; a lumped heat capacity on cells whose row sums are not positive
// is refused, saying what it refuses; the contact patch test runs on quadratic surfaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

const std::string kMaterial = R"(
[materials.steel]
density = 7850.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1.2e-5
specific_heat = 450.0
thermal_conductivity = 50.0
)";

/// A 3D bar of `element` cells, clamped at xmin, pushed at xmax, heated at zmax, cooled by a
/// film at zmin, dynamic, 4 steps.
std::string bar(const std::string& element, const std::string& extra) {
  return R"(dimension = 3
[time]
scheme = "dynamic"
step = 1e-4
end = 4e-4
)" + extra +
         kMaterial +
         R"(
[[bodies]]
name = "bar"
material = "steel"
mesh = { box = { min = [0.0, 0.0, 0.0], max = [0.4, 0.1, 0.1], cells = [4, 1, 1], element = ")" +
         element + R"(" } }
subdomains = 2

[[boundary]]
body = "bar"
where = "xmin"
displacement = [0.0, 0.0, 0.0]

[[boundary]]
body = "bar"
where = "xmax"
traction = [1.0e6, 0.0, -1.0e5]

[[boundary]]
body = "bar"
where = "zmax"
heat_flux = 1.0e5

[[boundary]]
body = "bar"
where = "zmin"
film = { coefficient = 50.0, ambient = 280.0 }
)";
}

fs::path write_case(const std::string& name, const std::string& text) {
  const auto dir = tc::test::fresh_dir(name);
  const auto file = dir / "case.toml";
  std::ofstream(file) << text;
  return file;
}

}  // namespace

TEST(SecondOrderCli, Hex20BarRunsWithFetiFilmsAndRestarts) {
  const auto c = write_case("order2-bar", bar("Hex20", ""));
  const auto full = tc::test::fresh_dir("order2-bar-full");
  auto r = thermocontact("run " + c.string() + " --output " + full.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // VTK_QUADRATIC_HEXAHEDRON = 25, one per cell (ASCII: one value a line).
  const auto vtu = tc::test::read_file(full / "bar_000004.vtu");
  EXPECT_NE(vtu.find("Name=\"types\" format=\"ascii\">\n25\n25\n25\n25\n"), std::string::npos)
      << vtu.substr(0, 2000);
  const auto check = thermocontact("check " + c.string());
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_NE(check.output.find("2 FETI subdomains"), std::string::npos) << check.output;
  const auto split = tc::test::fresh_dir("order2-bar-split");
  r = thermocontact("run " + c.string() + " --output " + split.string() + " --stop-after 2");
  ASSERT_EQ(r.exit_code, 1) << r.output;
  r = thermocontact("run " + c.string() + " --restart " + split.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto a = tc::test::read_history(full / "history.csv");
  const auto b = tc::test::read_history(split / "history.csv");
  ASSERT_EQ(a.rows.size(), 5u);
  EXPECT_LE(tc::test::max_relative_difference(a, b, {"wall_seconds"}), 1e-12);
}

TEST(SecondOrderCli, LumpedHeatCapacityIsRefusedOnTet10AndTakenOnHex27) {
  const std::string lumped = "[physics]\nheat_capacity = \"lumped\"\n";
  auto r =
      thermocontact("check " + write_case("order2-lumped-tet10", bar("Tet10", lumped)).string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("physics.heat_capacity"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Tet10"), std::string::npos) << r.output;
  r = thermocontact("check " + write_case("order2-lumped-hex27", bar("Hex27", lumped)).string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(SecondOrderCli, ContactPatchOnQuadraticFacesCarriesTheUniaxialPressure) {
  // tests/cases/valid/contact-patch-2d.toml with Quad8 cells in the upper (slave) body and
  // Quad9 in the lower: uniaxial, the normal force on the 1 m wide face is the pressure
  // E/(1 − ν²)·δ/(h_s + h_m) = 2e11/0.91 × 1e-4/1.5 N (the case's comment), to the QP's 1e-12
  // amplified by cond(F): 1e-8.
  const auto source = fs::path(TC_SOURCE_DIR) / "tests/cases/valid/contact-patch-2d.toml";
  std::string text =
      tc::test::replace_all(tc::test::read_file(source), "max = [1.0, 1.5], cells = [5, 2] }",
                            "max = [1.0, 1.5], cells = [5, 2], element = \"Quad8\" }");
  text = tc::test::replace_all(text, "max = [1.0, 1.0], cells = [7, 3] }",
                               "max = [1.0, 1.0], cells = [7, 3], element = \"Quad9\" }");
  ASSERT_NE(text.find("Quad8"), std::string::npos);
  ASSERT_NE(text.find("Quad9"), std::string::npos);
  const auto c = write_case("order2-contact", text);
  const auto check = thermocontact("check " + c.string());
  EXPECT_EQ(check.exit_code, 0) << check.output;
  const auto out = tc::test::fresh_dir("order2-contact-out");
  const auto r = thermocontact("run " + c.string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto h = tc::test::read_history(out / "history.csv");
  ASSERT_EQ(h.rows.size(), 2u);
  const auto at = std::find(h.columns.begin(), h.columns.end(), "contact_normal_force");
  ASSERT_NE(at, h.columns.end());
  const double pressure = 2e11 / (1 - 0.3 * 0.3) * 1e-4 / 1.5;
  EXPECT_NEAR(h.rows[1][static_cast<size_t>(at - h.columns.begin())], pressure, 1e-8 * pressure);
}
