// `[output] format = "vtkhdf"` on 2 ranks through the command line (labels system, mpi): the
// thesis example cut into 4 subdomains per body (tests/cases/feti/thesis-coarse.toml, 0.1 s,
// the slave pressed onto the master) run on 1 rank and on 2. Each 2-rank .vtkhdf holds one
// piece per rank (the cells of its 2 subdomains), written collectively into one file that
// result.pvd names (no .pvtu, no per-rank files), and its fields read back equal the serial
// run's at the same points and cells (matched by coordinates) to the solvers' round-off.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "support/cli.hpp"
#include "support/history.hpp"
#include "support/vtk_files.hpp"

namespace tc::test {
namespace {

#if TC_HAVE_HDF5

const std::filesystem::path kCase =
    std::filesystem::path(TC_SOURCE_DIR) / "tests/cases/feti/thesis-coarse.toml";

/// `args` on 2 ranks (a clean environment: this process is an MPI singleton, whose variables
/// the launcher would take for a job it belongs to); `timeout` turns a hang into exit 124.
CommandResult two_ranks(const std::string& args) {
  return run_command(
      fmt::format("env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
                  "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
                  "OPENBLAS_NUM_THREADS=1 timeout 300 {} -n 2 {} {}",
                  TC_MPIEXEC, TC_BINARY, args));
}

/// A point's key: its coordinates' bytes (both runs build the same mesh).
std::string key(const VtkArray& points, size_t i) {
  return std::string(reinterpret_cast<const char*>(&points.bytes[24 * i]), 24);
}

std::string cell_key(const VtkArrays& g, size_t c) {
  const auto& conn = g.at("Cells/connectivity");
  const auto& ends = g.at("Cells/offsets");
  std::vector<std::string> keys;
  for (auto i = c ? static_cast<size_t>(ends.value(c - 1)) : 0;
       i < static_cast<size_t>(ends.value(c)); ++i)
    keys.push_back(key(g.at("Points"), static_cast<size_t>(conn.value(i))));
  std::sort(keys.begin(), keys.end());
  std::string out;
  for (const auto& k : keys) out += k;
  return out;
}

/// The field's tolerance against the serial run, as for the .pvtu pieces of the same runs
/// (feti_mpi_cli_test.cpp, where each is argued): 1e-8 of the field's largest value, the
/// round-off of summing F·x over the ranks in another order; 1e-3 for the fields that are
/// round-off themselves at 0.1 s (the velocities, the sticking interface's slip and traction,
/// the heat flux at θ = θ₀), with absolute floors for the last two.
double tolerance(const std::string& name, const VtkArray& values) {
  double scale = 1e-300;
  for (size_t i = 0; i < values.rows() * static_cast<size_t>(values.components); ++i)
    scale = std::max(scale, std::abs(values.value(i)));
  const auto field = name.substr(name.find('/') + 1);
  const bool noisy = field == "velocity" || field == "slip_velocity" ||
                     field == "tangential_traction" || field == "heat_flux";
  const double floor = field == "heat_flux" ? 1e-6 : field == "slip_velocity" ? 1e-12 : 0.0;
  return std::max((noisy ? 1e-3 : 1e-8) * scale, floor);
}

TEST(VtkHdfMpiCli, TwoRanksWriteOneFileWhoseFieldsAreTheSerialRuns) {
  const auto dir = fresh_dir(fmt::format("vtkhdf-mpi-{}", ::getpid()));
  auto text = replace_all(read_file(kCase), "subdomains = 1", "subdomains = 4");
  text = replace_all(text, "end = 0.3", "end = 0.1");
  std::ofstream(dir / "cut.toml") << text;
  const auto args = [&](const std::string& out) {
    return fmt::format("run {} --set output.format=vtkhdf --output {}", (dir / "cut.toml").string(),
                       (dir / out).string());
  };
  const auto one = thermocontact(args("np1"));
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto two = two_ranks(args("np2"));
  ASSERT_EQ(two.exit_code, 0) << two.output;
  EXPECT_EQ(read_collection(dir / "np1/result.pvd").files,
            read_collection(dir / "np2/result.pvd").files);
  for (const auto& e : std::filesystem::directory_iterator(dir / "np2"))
    for (const char* other : {".vtu", ".pvtu", ".tmp"})
      EXPECT_NE(e.path().extension().string(), other) << e.path().string();
  for (const std::string body : {"master", "slave"}) {
    const std::string file = body + "_000010.vtkhdf";  // the last step
    const auto serial = read_vtkhdf(dir / "np1" / file);
    ASSERT_EQ(serial.n_cells.size(), 1u);
    const auto whole = serial.piece(0);
    const auto parallel = read_vtkhdf(dir / "np2" / file);
    ASSERT_EQ(parallel.n_cells.size(), 2u) << "one piece per rank";
    std::map<std::string, size_t> serial_point, serial_cell;
    for (size_t a = 0; a < whole.at("Points").rows(); ++a)
      serial_point[key(whole.at("Points"), a)] = a;
    for (size_t c = 0; c < whole.at("Cells/types").rows(); ++c) serial_cell[cell_key(whole, c)] = c;
    std::set<size_t> cells_seen, points_seen;
    for (size_t p = 0; p < 2; ++p) {
      const auto piece = parallel.piece(p);
      EXPECT_EQ(piece.size(), whole.size()) << "the same arrays";
      for (size_t a = 0; a < piece.at("Points").rows(); ++a) {
        const auto it = serial_point.find(key(piece.at("Points"), a));
        ASSERT_NE(it, serial_point.end()) << body << " piece " << p << " point " << a;
        points_seen.insert(it->second);
        for (const auto& [name, values] : whole) {
          if (name.rfind("PointData/", 0) != 0) continue;
          const auto k = static_cast<size_t>(values.components);
          for (size_t i = 0; i < k; ++i)
            EXPECT_NEAR(piece.at(name).value(k * a + i), values.value(k * it->second + i),
                        tolerance(name, values))
                << body << " " << name << " piece " << p << " point " << a;
        }
      }
      for (size_t c = 0; c < piece.at("Cells/types").rows(); ++c) {
        const auto it = serial_cell.find(cell_key(piece, c));
        ASSERT_NE(it, serial_cell.end()) << body << " piece " << p << " cell " << c;
        EXPECT_TRUE(cells_seen.insert(it->second).second) << "a cell in two pieces";
        for (const auto& [name, values] : whole) {
          if (name.rfind("CellData/", 0) != 0) continue;
          const auto k = static_cast<size_t>(values.components);
          // The subdomain's number is the same cut on both runs: exact.
          const double tol = name == "CellData/subdomain" ? 0.0 : tolerance(name, values);
          for (size_t i = 0; i < k; ++i)
            EXPECT_NEAR(piece.at(name).value(k * c + i), values.value(k * it->second + i), tol)
                << body << " " << name << " piece " << p << " cell " << c;
        }
      }
    }
    EXPECT_EQ(cells_seen.size(), whole.at("Cells/types").rows()) << body;
    EXPECT_EQ(points_seen.size(), whole.at("Points").rows()) << body;
  }
}

#else

TEST(VtkHdfMpiCli, NotBuilt) {
  GTEST_SKIP() << "built without HDF5";
}

#endif

}  // namespace
}  // namespace tc::test
