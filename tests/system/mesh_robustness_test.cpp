// Meshes that cannot be used, or only with care (docs/robustness.md): inverted and zero-area
// cells, coincident nodes, contact surfaces that overlap at t = 0, that do not face each
// other, or that name an empty group. Each is an error (exit code 2, naming the file and what
// is wrong) or a warning, never a crash; checked through the command line.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "support/cli.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/io/checks/geometry_checks.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

/// A 2D .msh (format 2.2) of two unit squares side by side, Quad4, with the physical lines
/// "left" (x = 0) and "top" (y = 1, both squares) and an empty physical group "nothing".
/// `middle` gives the nodes of the shared edge x = 1 as the right square uses them: 2 3 (the
/// left square's: connected), or 7 8 (coincident copies: not connected). `right` is the node
/// order of the right quad; node 9 at (1.8, 0.5) is used by none unless `right` names it.
std::string two_squares(const std::string& middle, const std::string& right) {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
         "$PhysicalNames\n4\n1 1 \"left\"\n1 2 \"top\"\n1 3 \"nothing\"\n2 4 \"domain\"\n"
         "$EndPhysicalNames\n"
         "$Nodes\n9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n6 2 1 0\n7 1 0 0\n8 1 1 0\n"
         "9 1.8 0.5 0\n"
         "$EndNodes\n"
         "$Elements\n5\n"
         "1 1 2 1 1 1 4\n"
         "2 1 2 2 2 4 3\n"
         "3 1 2 2 2 " +
         middle.substr(middle.find(' ') + 1) + " 6\n" +
         "4 3 2 4 1 1 2 3 4\n"
         "5 3 2 4 1 " +
         right + "\n$EndElements\n";
}

std::string case_with_mesh(const std::string& extra = "") {
  return R"(dimension = 2
[time]
scheme = "quasistatic"
step = 1.0
end = 1.0
[materials.m]
density = 7850.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1.2e-5
specific_heat = 450.0
thermal_conductivity = 50.0
[[bodies]]
name = "plate"
material = "m"
mesh = { file = "plate.msh" }
[[boundary]]
body = "plate"
where = "left"
displacement = [0.0, 0.0]
)" + extra;
}

struct Written {
  fs::path dir, case_file;
};

Written write_case(const std::string& name, const std::string& msh, const std::string& toml) {
  const auto dir = tc::test::fresh_dir(name);
  std::ofstream(dir / "plate.msh") << msh;
  std::ofstream(dir / "case.toml") << toml;
  return {dir, dir / "case.toml"};
}

TEST(MeshRobustness, ANonConvexCellIsAnErrorNamingTheFileAndTheCell) {
  // The right quad (1, 0), (2, 0), (2, 1), (1.8, 0.5): positive area, but its Jacobian is
  // negative at the reflex corner. (A 2D cell numbered clockwise as a whole is turned by the
  // reader: gmsh writes them for surfaces whose normal is −z; gmsh_reader.cpp.)
  const auto w = write_case("mesh-inverted", two_squares("2 3", "2 5 6 9"), case_with_mesh());
  const auto r = thermocontact("check " + w.case_file.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* part : {"plate.msh", "non-convex or inverted", "cell 1"})
    EXPECT_NE(r.output.find(part), std::string::npos) << part << "\n" << r.output;
  EXPECT_EQ(thermocontact("run " + w.case_file.string() + " --output " + (w.dir / "out").string())
                .exit_code,
            2);
}

TEST(MeshRobustness, AZeroAreaCellIsAnErrorNamingTheFile) {
  // The right square's nodes 3 and 6 replaced by 2 and 5: a flat cell along y = 0.
  const auto w = write_case("mesh-flat", two_squares("2 3", "2 5 5 2"), case_with_mesh());
  const auto r = thermocontact("check " + w.case_file.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* part : {"plate.msh", "degenerate"})
    EXPECT_NE(r.output.find(part), std::string::npos) << part << "\n" << r.output;
}

TEST(MeshRobustness, CoincidentNodesAreAWarningNamingTheNodes) {
  // The right square on copies 7, 8 of the shared edge's nodes: the two squares are not
  // connected. Valid (exit 0), with a warning that says where.
  const auto w = write_case("mesh-coincident", two_squares("7 8", "7 5 6 8"), case_with_mesh());
  const auto r = thermocontact("check " + w.case_file.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex("warning: .*case.toml: body 'plate': 2 pairs "
                                                     "of coincident nodes .*at \\(1, 0, 0\\)")))
      << r.output;
  // Connected, the same mesh has no warning.
  const auto ok = write_case("mesh-connected", two_squares("2 3", "2 5 6 3"), case_with_mesh());
  const auto r2 = thermocontact("check " + ok.case_file.string());
  EXPECT_EQ(r2.exit_code, 0) << r2.output;
  EXPECT_EQ(r2.output.find("warning"), std::string::npos) << r2.output;
}

std::string two_blocks(double upper_min_y, const std::string& slave_where = "ymin") {
  // tests/cases/valid/contact-patch-2d.toml with the upper block's bottom at upper_min_y.
  auto text =
      tc::test::read_file(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/contact-patch-2d.toml");
  const std::string box = "min = [0.0, 1.0], max = [1.0, 1.5]";
  text.replace(text.find(box), box.size(),
               "min = [0.0, " + std::to_string(upper_min_y) + "], max = [1.0, 1.5]");
  const std::string slave = "slave = { body = \"upper\", where = \"ymin\" }";
  text.replace(text.find(slave), slave.size(),
               "slave = { body = \"upper\", where = \"" + slave_where + "\" }");
  return text;
}

TEST(MeshRobustness, ContactSurfacesOverlappingAtTheStartAreAnError) {
  // The upper block reaches 0.01 m into the lower one.
  const auto dir = tc::test::fresh_dir("mesh-overlap");
  std::ofstream(dir / "case.toml") << two_blocks(0.99);
  const auto r = thermocontact("check " + (dir / "case.toml").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* part : {"case.toml", "overlap", "body 'upper'", "body 'lower'", "0.01 m inside"})
    EXPECT_NE(r.output.find(part), std::string::npos) << part << "\n" << r.output;
  const auto run =
      thermocontact("run " + (dir / "case.toml").string() + " --output " + (dir / "out").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
}

TEST(MeshRobustness, ABodyDeepInsideTheOtherIsAnError) {
  // Deeper than the contact search reaches (about one element of the master surface), the
  // overlap showed no facing nodes: a warning ("do not face each other") and a run without
  // contact force (issue 20, #4). The upper block with its bottom 0.6 m inside the lower one,
  // and with the lower one's own box.
  for (const double bottom : {0.4, 0.0}) {
    const auto dir = tc::test::fresh_dir("mesh-deep-overlap");
    std::ofstream(dir / "case.toml") << two_blocks(bottom);
    for (const std::string& options : {std::string(), " --output " + (dir / "out").string()}) {
      const auto command = options.empty() ? "check " : "run ";
      const auto r = thermocontact(command + (dir / "case.toml").string() + options);
      EXPECT_EQ(r.exit_code, 2) << command << bottom << "\n" << r.output;
      for (const char* part : {"case.toml", "overlap at t = 0", "lies inside cell"})
        EXPECT_NE(r.output.find(part), std::string::npos) << part << "\n" << r.output;
    }
  }
}

TEST(MeshRobustness, TouchingSurfacesPassAndTheExamplesStartApartOrTouching) {
  // The contact patch touches exactly (gap 0, to round-off); the curved Hertz surfaces and the
  // 3D examples start apart or touching within the tolerance (1e-6 of a facet).
  for (const char* c :
       {"tests/cases/valid/contact-patch-2d.toml", "examples/03-hertz-2d/case.toml",
        "examples/04-sliding-block-3d/case.toml", "examples/05-thesis-heat-transfer/case.toml"}) {
    const auto p = tc::io::read_case(fs::path(TC_SOURCE_DIR) / c);
    const auto ic = tc::io::initial_contact(p);
    EXPECT_GT(ic.contact_nodes, 0) << c;
    EXPECT_GE(ic.smallest_gap, -ic.tolerance) << c;
    std::printf("%s: %d contact nodes, smallest gap %.3e m (tolerance %.3e m)\n", c,
                ic.contact_nodes, ic.smallest_gap, ic.tolerance);
    EXPECT_NO_THROW((void)tc::io::check_geometry(p)) << c;
  }
  const auto p =
      tc::io::read_case(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/contact-patch-2d.toml");
  EXPECT_NEAR(tc::io::initial_contact(p).smallest_gap, 0.0, 1e-12);
}

TEST(MeshRobustness, ContactSurfacesThatDoNotFaceEachOtherAreAWarning) {
  // The upper block 0.5 m above the lower one: farther than an element, no contact node.
  const auto dir = tc::test::fresh_dir("mesh-apart");
  std::ofstream(dir / "case.toml")
      << two_blocks(1.5).replace(two_blocks(1.5).find("max = [1.0, 1.5]"), 16, "max = [1.0, 2.0]");
  const auto r = thermocontact("check " + (dir / "case.toml").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("do not face each other"), std::string::npos) << r.output;
}

TEST(MeshRobustness, EveryContactPairIsCheckedAndNamedWhenThereAreSeveral) {
  // tests/cases/several-pairs/three-blocks-2d.toml: top on middle ("upper"), middle on base
  // ("lower"), all touching: valid, no warning of the geometry (the top starts sliding at once:
  // the dynamic scheme's warning of a velocity jump is the only one). Checked only.
  const auto valid = fs::path(TC_SOURCE_DIR) / "tests/cases/several-pairs/three-blocks-2d.toml";
  auto r = thermocontact("check " + valid.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("valid (2D, 3 bodies"), std::string::npos) << r.output;
  const auto first = r.output.find("warning");
  EXPECT_NE(r.output.find("jumps in velocity"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning", first + 1), std::string::npos) << r.output;
  const auto p = tc::io::read_case(valid);
  for (size_t i = 0; i < 2; ++i) {
    const auto ic = tc::io::initial_contact(p, i);
    EXPECT_GT(ic.contact_nodes, 0) << i;
    EXPECT_NEAR(ic.smallest_gap, 0.0, 1e-12) << i;
  }
  const auto text = tc::test::read_file(valid);
  const auto variant = [&](const std::string& name, const std::string& from,
                           const std::string& to) {
    const auto dir = tc::test::fresh_dir(name);
    auto t = text;
    t.replace(t.find(from), from.size(), to);
    std::ofstream(dir / "case.toml") << t;
    return thermocontact("check " + (dir / "case.toml").string());
  };
  // The base 0.5 m lower: the lower pair does not face, the upper one does.
  r = variant("pairs-apart", "min = [0.0, 0.0], max = [1.0, 1.0]",
              "min = [0.0, -0.5], max = [1.0, 0.5]");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("contact 'lower': the slave surface 'ymin' of body 'middle'"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("contact 'upper'"), std::string::npos) << r.output;
  // The top block 0.3 m into the middle one: the upper pair overlaps, an error naming it.
  r = variant("pairs-overlap", "min = [0.0, 2.0], max = [1.0, 2.5]",
              "min = [0.0, 1.7], max = [1.0, 2.2]");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("contact 'upper': body 'top' and body 'middle' overlap at t = 0"),
            std::string::npos)
      << r.output;
}

TEST(MeshRobustness, AnEmptyContactSurfaceIsAnErrorNamingFileLineAndKey) {
  // "nothing" is a physical group of the .msh without elements: no boundary of that name.
  const auto w =
      write_case("mesh-empty-group", two_squares("2 3", "2 5 6 3"), case_with_mesh(R"([[bodies]]
name = "block"
material = "m"
mesh = { box = { min = [0.0, 1.0], max = [2.0, 1.5], cells = [2, 1] } }
[[boundary]]
body = "block"
where = "ymax"
displacement = [0.0, -1.0e-4]
[contact]
slave = { body = "plate", where = "nothing" }
master = { body = "block", where = "ymin" }
)"));
  const auto r = thermocontact("check " + w.case_file.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex("case.toml:[0-9]+: contact.slave.where: "
                                                     "found \"nothing\"")))
      << r.output;
}

}  // namespace
