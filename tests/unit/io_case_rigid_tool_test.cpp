// read_case on a rigid tool as a contact pair's master (`master = { rigid = "plane", … }`): the
// tool's settings land in ContactSettings::rigid_master, and its held body is placed
// (physics::place_rigid_tools): one massless cell whose face lies in the plane, faces the slave
// and covers its shadow, every node held on the tool's motion and temperature.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <string>

#include "support/case_text.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/model/rigid_tool.hpp"

namespace {

namespace fs = std::filesystem;
using tc::io::read_case;
using tc::physics::Problem;

const std::string kCase = std::string(R"(dimension = 3
[time]
scheme = "quasistatic"
step = 0.1
end = 2.0
)") + tc::test::kSteelToml +
                          R"([[bodies]]
name = "block"
material = "steel"
mesh = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.5], cells = [2, 2, 1] } }
[[boundary]]
body = "block"
where = "zmax"
displacement = [0.0, 0.0, -1.0e-5]
[contact]
slave = { body = "block", where = "zmin" }
friction = 0.3
)";

Problem read_with(const std::string& name, const std::string& rest) {
  const auto dir = fs::temp_directory_path() / ("tc_rigid_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const auto file = dir / name;
  std::ofstream(file) << kCase << rest << "\n";
  auto p = read_case(file);
  fs::remove_all(dir);
  return p;
}

TEST(CaseRigidTool, APlaneAtATemperatureBecomesAHeldMasslessBody) {
  const auto p = read_with("hot.toml",
                           "master = { rigid = \"plane\", point = [0.0, 0.0, -0.001], "
                           "normal = [0.0, 0.0, 3.0], velocity = [0.02, 0.0, 0.0], "
                           "temperature = 400.0 }\n"
                           "conductance = { slave = 1e-3, master = 2e-3 }");
  ASSERT_EQ(p.bodies.size(), 2u);
  ASSERT_EQ(p.contacts.size(), 1u);
  const auto& c = p.contacts[0];
  ASSERT_TRUE(c.rigid_master.has_value());
  EXPECT_EQ(c.master_body, 1);
  EXPECT_EQ(c.master_where, tc::physics::kRigidToolFace);
  const auto& tool = *c.rigid_master;
  EXPECT_DOUBLE_EQ(tool.normal[2], 1.0);        // made unit
  EXPECT_DOUBLE_EQ(tool.motion[0](1.5), 0.03);  // v t
  EXPECT_DOUBLE_EQ(tool.motion[1](1.5), 0.0);
  EXPECT_DOUBLE_EQ(c.conductance_master(400.0), 2e-3);  // kept: the tool conducts
  EXPECT_TRUE(c.heat_conduction);
  const auto& b = p.bodies[1];
  EXPECT_EQ(b.name, "tool");
  EXPECT_TRUE(b.rigid_tool);
  EXPECT_FALSE(p.bodies[0].rigid_tool);
  EXPECT_EQ(b.material.density, 0.0);
  EXPECT_DOUBLE_EQ(b.initial_temperature, 400.0);
  EXPECT_EQ(b.mesh.n_cells(), 1);
  // The face lies in the plane z = −0.001 and covers the slave's shadow [0,1]² with room for
  // the travel (0.04 m).
  const auto face = b.mesh.boundary_nodes(tc::physics::kRigidToolFace);
  ASSERT_EQ(face.size(), 4u);
  double lo = 1e9, hi = -1e9;
  for (const int a : face) {
    EXPECT_NEAR(b.mesh.point(a)[2], -0.001, 1e-15);
    lo = std::min(lo, b.mesh.point(a)[0]);
    hi = std::max(hi, b.mesh.point(a)[0]);
  }
  EXPECT_LT(lo, -1.0);
  EXPECT_GT(hi, 2.0);
  // Its outward normal is the plane's: the other nodes lie behind it (z < −0.001).
  for (int a = 0; a < b.mesh.n_nodes(); ++a) EXPECT_LE(b.mesh.point(a)[2], -0.001 + 1e-15);
  // Every node held on the motion and the temperature.
  const auto& held = p.boundaries.back();
  EXPECT_EQ(held.body, 1);
  EXPECT_EQ(b.mesh.boundary_nodes(held.where).size(), 8u);
  ASSERT_TRUE(held.displacement[0] && held.displacement[1] && held.displacement[2]);
  EXPECT_DOUBLE_EQ((*held.displacement[0])(1.0), 0.02);
  ASSERT_TRUE(held.temperature.has_value());
  EXPECT_DOUBLE_EQ((*held.temperature)(0.0), 400.0);
}

TEST(CaseRigidTool, AnAdiabaticToolGivesAllFrictionalHeatToTheSlave) {
  const auto p = read_with("cold.toml",
                           "master = { rigid = \"plane\", point = [0.5, 0.5, 0.0], "
                           "normal = [0.0, 0.0, 1.0], displacement = [{ t = [0.0, 2.0], "
                           "value = [0.0, 0.1] }, 0.0, 0.0] }");
  const auto& c = p.contacts.at(0);
  ASSERT_TRUE(c.rigid_master.has_value());
  EXPECT_FALSE(c.rigid_master->temperature.has_value());
  EXPECT_DOUBLE_EQ(c.rigid_master->motion[0](1.0), 0.05);
  // δ_C = γ_s/(γ_s + γ_m) = 1, β_C = 0, and no conduction.
  EXPECT_EQ(c.conductance_slave(300.0), 1.0);
  EXPECT_EQ(c.conductance_master(300.0), 0.0);
  EXPECT_FALSE(c.heat_conduction);
  EXPECT_DOUBLE_EQ(p.bodies.at(1).initial_temperature, p.physics.reference_temperature);
}

}  // namespace
