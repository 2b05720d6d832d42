// Issue 8's MPI deliverables through the command line at 2 ranks (labels verification, mpi):
// - collective errors: a failure on one rank stops both, each process exits with the same
//   non-zero code, rank 0 reports it once naming the failing rank and the phase, no hang;
// - .pvtu output: the pieces the ranks write have together exactly the cells of the 1-rank
//   run's .vtu, with the same point and cell values.
// The case is the thesis example (tests/cases/feti/thesis-coarse.toml) cut into 4 subdomains
// per body, 0.1 s: the slave is pressed onto the master, so the contact fields are non-zero.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <regex>
#include <set>

#include "support/cli.hpp"

namespace tc::test {
namespace {

const std::filesystem::path kCase =
    std::filesystem::path(TC_SOURCE_DIR) / "tests/cases/feti/thesis-coarse.toml";

struct Timed {
  CommandResult result;
  double seconds = 0;
};

/// `args` on 2 ranks, each rank's exit code left in <codes>_<rank> by a shell around it (the
/// launcher would report only one, or kill the other rank when one exits non-zero). `timeout`
/// turns a hang into exit code 124 instead of a stuck test.
Timed two_ranks(const std::string& args, const std::filesystem::path& codes) {
  const auto t0 = std::chrono::steady_clock::now();
  Timed t;
  // A clean environment: this process is an MPI singleton, and the launcher would take its
  // OMPI_/PMIX_ variables for a job it belongs to. CI runs as root (allowed here).
  t.result = run_command(
      fmt::format("env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
                  "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
                  "timeout 300 {} -n 2 sh -c '{} {}; echo $? > {}_$OMPI_COMM_WORLD_RANK'",
                  TC_MPIEXEC, TC_BINARY, args, codes.string()));
  t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

int exit_code_of(const std::filesystem::path& codes, int rank) {
  const auto text = read_file(fmt::format("{}_{}", codes.string(), rank));
  return text.empty() ? -1 : std::stoi(text);
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

class FetiMpiCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // ctest runs each test of the suite as its own process, possibly at the same time.
    dir_ = fresh_dir(fmt::format("feti-mpi-cli-{}", ::getpid()));
    auto text = replace_all(read_file(kCase), "subdomains = 1", "subdomains = 4");
    text = replace_all(text, "end = 0.3", "end = 0.1");
    std::ofstream(dir_ / "cut.toml") << text;
  }
  // Step cut-back off: an injected fault would otherwise be retried at τ/2 by fresh solvers,
  // which it no longer hits; these tests are of how a failure reaches both ranks.
  static std::string run_args(const std::string& out, const std::string& extra = "") {
    return fmt::format("run {} --set solver.max_cutbacks=0 --output {} {}",
                       (dir_ / "cut.toml").string(), (dir_ / out).string(), extra);
  }
  /// A run failing on rank 1 in `phase`: both ranks stop with exit code 1 at once, rank 0
  /// reports "rank 1: <named phase>" once.
  static void expect_collective_failure(const std::string& phase, const std::string& named,
                                        const std::string& extra = "") {
    const auto codes = dir_ / ("codes-" + phase);
    const auto t = two_ranks(
        run_args("fail-" + phase, "-tc_fail_on_rank 1 -tc_fail_phase " + phase + " " + extra),
        codes);
    EXPECT_NE(t.result.exit_code, 124) << "hang: the launcher's timeout\n" << t.result.output;
    EXPECT_LT(t.seconds, 120.0) << t.result.output;
    EXPECT_EQ(exit_code_of(codes, 0), 1) << t.result.output;
    EXPECT_EQ(exit_code_of(codes, 1), 1) << t.result.output;
    EXPECT_EQ(count(t.result.output, "rank 1: " + named), 1u) << t.result.output;
    EXPECT_NE(t.result.output.find("injected by -tc_fail_on_rank"), std::string::npos)
        << t.result.output;
  }
  static inline std::filesystem::path dir_;
};

TEST_F(FetiMpiCli, AFactorisationFailingOnOneRankStopsBothRanks) {
  expect_collective_failure("factorisation", "FETI subdomain assembly and factorisation: ");
}

TEST_F(FetiMpiCli, ASubdomainSolveFailingOnOneRankStopsBothRanks) {
  // After 8 solves of an operator on rank 1: within the first steps, past the set-up.
  expect_collective_failure("solve", "FETI subdomain solve: ", "-tc_fail_after_solves 8");
  // The run's own error path: the summary says stopped, with the message.
  const auto summary = read_file(dir_ / "fail-solve/summary.json");
  EXPECT_NE(summary.find("\"status\": \"stopped\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("rank 1: FETI subdomain solve"), std::string::npos) << summary;
}

TEST_F(FetiMpiCli, AnOutputPieceFailingOnOneRankStopsBothRanks) {
  expect_collective_failure("output", "output: ");
}

// ---------------------------------------------------------------------------- .pvtu

/// The arrays of one .vtu piece: points, cells (as point indices) and named data arrays.
struct Grid {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<int>> cells;
  std::map<std::string, std::vector<double>> point_data, cell_data;
  std::map<std::string, int> components;
};

std::vector<double> numbers(const std::string& text) {
  std::vector<double> v;
  const char* p = text.c_str();
  char* end = nullptr;
  for (double x = std::strtod(p, &end); end != p; x = std::strtod(p, &end)) {
    v.push_back(x);
    p = end;
  }
  return v;
}

/// The data arrays between `open` and `close` (e.g. <PointData> … </PointData>) by name.
void arrays(const std::string& xml, const std::string& open, const std::string& close,
            std::map<std::string, std::vector<double>>& out, std::map<std::string, int>& comps) {
  const auto a = xml.find(open), b = xml.find(close);
  ASSERT_NE(a, std::string::npos) << open;
  const std::string part = xml.substr(a, b - a);
  const std::regex head(
      R"re(<DataArray[^>]*Name="([^"]*)"[^>]*NumberOfComponents="(\d+)"[^>]*>)re");
  for (std::sregex_iterator it(part.begin(), part.end(), head), e; it != e; ++it) {
    const auto start = static_cast<size_t>(it->position() + it->length());
    const auto stop = part.find("</DataArray>", start);
    out[(*it)[1]] = numbers(part.substr(start, stop - start));
    comps[(*it)[1]] = std::stoi((*it)[2]);
  }
}

Grid read_vtu(const std::filesystem::path& file) {
  const auto xml = read_file(file);
  Grid g;
  // The numbers of the DataArray whose tag starts at `tag`.
  auto block = [&](size_t tag) {
    const auto a = xml.find('>', tag) + 1;
    return numbers(xml.substr(a, xml.find("</DataArray>", a) - a));
  };
  const auto named = [&](const std::string& name) {
    return block(xml.rfind("<DataArray", xml.find("Name=\"" + name + "\"")));
  };
  const auto p = block(xml.find("<DataArray", xml.find("<Points>")));
  for (size_t i = 0; i + 2 < p.size(); i += 3) g.points.push_back({p[i], p[i + 1], p[i + 2]});
  const auto conn = named("connectivity");
  const auto offs = named("offsets");
  size_t begin = 0;
  for (const double o : offs) {
    g.cells.emplace_back();
    for (auto i = begin; i < static_cast<size_t>(o); ++i)
      g.cells.back().push_back(static_cast<int>(conn[i]));
    begin = static_cast<size_t>(o);
  }
  arrays(xml, "<PointData>", "</PointData>", g.point_data, g.components);
  arrays(xml, "<CellData>", "</CellData>", g.cell_data, g.components);
  return g;
}

/// A point's key: its coordinates as printed (both runs print the same mesh the same way).
std::string key(const std::array<double, 3>& x) {
  return fmt::format("{:.9g} {:.9g} {:.9g}", x[0], x[1], x[2]);
}

std::string cell_key(const Grid& g, const std::vector<int>& cell) {
  std::vector<std::string> k;
  for (const int a : cell) k.push_back(key(g.points[static_cast<size_t>(a)]));
  std::sort(k.begin(), k.end());
  std::string out;
  for (const auto& s : k) out += s + ";";
  return out;
}

TEST_F(FetiMpiCli, PvtuPiecesHoldTheSerialCellsAndValues) {
  const auto one = thermocontact(run_args("np1"));
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto codes = dir_ / "codes-np2";
  const auto two = two_ranks(run_args("np2"), codes);
  ASSERT_EQ(exit_code_of(codes, 0), 0) << two.result.output;
  ASSERT_EQ(exit_code_of(codes, 1), 0) << two.result.output;
  // 1 rank: one .vtu per body and step as before; 2 ranks: a .pvtu listing pieces.
  const auto pvd_one = read_file(dir_ / "np1/result.pvd");
  const auto pvd_two = read_file(dir_ / "np2/result.pvd");
  EXPECT_EQ(pvd_one.find(".pvtu"), std::string::npos) << pvd_one;
  EXPECT_EQ(pvd_two.find(".vtu\""), std::string::npos) << pvd_two;
  for (const std::string body : {"master", "slave"}) {
    const std::string stem = body + "_000010";  // the last step
    EXPECT_NE(pvd_two.find(stem + ".pvtu"), std::string::npos) << pvd_two;
    const auto serial = read_vtu(dir_ / "np1" / (stem + ".vtu"));
    const auto pvtu = read_file(dir_ / "np2" / (stem + ".pvtu"));
    std::vector<std::string> sources;
    const std::regex piece(R"re(<Piece Source="([^"]*)"/>)re");
    for (std::sregex_iterator it(pvtu.begin(), pvtu.end(), piece), e; it != e; ++it)
      sources.push_back((*it)[1]);
    ASSERT_EQ(sources.size(), 2u) << pvtu;  // 4 subdomains: 2 on each rank
    for (const auto& [name, values] : serial.point_data) {
      (void)values;
      EXPECT_NE(pvtu.find("Name=\"" + name + "\""), std::string::npos) << name;
    }
    // The serial values by point and by cell.
    std::map<std::string, size_t> serial_point, serial_cell;
    for (size_t a = 0; a < serial.points.size(); ++a) serial_point[key(serial.points[a])] = a;
    for (size_t c = 0; c < serial.cells.size(); ++c)
      serial_cell[cell_key(serial, serial.cells[c])] = c;
    ASSERT_EQ(serial_cell.size(), serial.cells.size());
    auto scale = [](const std::vector<double>& v) {
      double m = 0;
      for (const double x : v) m = std::max(m, std::abs(x));
      return std::max(m, 1e-300);
    };
    // 1e-8 of the field's largest value: the two runs differ by the round-off of summing F·x
    // over the ranks in another order. Not so the fields that are small differences of
    // displacements or round-off themselves at 0.1 s (sticking, θ = θ₀): the velocities
    // (2Δu/τ − v, Newmark), the slip velocity and tangential traction of the sticking
    // interface (‖slip velocity‖ ≤ 2e-8 m/s, differing by 1e-4 of it) and the heat flux (the
    // gradient of θ's round-off): 1e-3 of their largest value. The writer is tested by the
    // others; those are the solvers' round-off (the history columns: feti_cli_test).
    auto tolerance = [&](const std::string& name, const std::vector<double>& values) {
      const bool noisy = name == "velocity" || name == "slip_velocity" ||
                         name == "tangential_traction" || name == "heat_flux";
      // The heat flux at θ = θ₀ is κ∇ of θ's round-off, 1e-12·θ₀ ≈ 3e-10 K over h = 0.05 m
      // with κ = 70 W/(m K): a few 1e-7 W/m², which the two runs need not share digit by
      // digit; 1e-6 W/m² bounds it.
      // The slip velocity Δu/τ of the sticking nodes (5e-11 m/s) carries the FETI solves'
      // error, relative 1e-10 of ‖u‖ ≈ 1e-4 m over τ = 0.01 s: 1e-12 m/s bounds it.
      const double floor = name == "heat_flux" ? 1e-6 : name == "slip_velocity" ? 1e-12 : 0.0;
      return std::max((noisy ? 1e-3 : 1e-8) * scale(values), floor);
    };
    std::map<std::string, int> seen;
    std::set<std::string> seen_points;
    for (const auto& source : sources) {
      const auto g = read_vtu(dir_ / "np2" / source);
      EXPECT_EQ(g.point_data.size(), serial.point_data.size()) << source;
      EXPECT_EQ(g.cell_data.size(), serial.cell_data.size()) << source;
      for (size_t a = 0; a < g.points.size(); ++a) {
        const auto it = serial_point.find(key(g.points[a]));
        ASSERT_NE(it, serial_point.end()) << source << " point " << a;
        seen_points.insert(it->first);
        for (const auto& [name, values] : serial.point_data) {
          const int k = serial.components.at(name);
          const auto& mine = g.point_data.at(name);
          for (int i = 0; i < k; ++i)
            EXPECT_NEAR(mine[k * a + i], values[k * it->second + i], tolerance(name, values))
                << source << " " << name << " point " << a;
        }
      }
      for (size_t c = 0; c < g.cells.size(); ++c) {
        const auto ck = cell_key(g, g.cells[c]);
        const auto it = serial_cell.find(ck);
        ASSERT_NE(it, serial_cell.end()) << source << " cell " << c;
        ++seen[ck];
        for (const auto& [name, values] : serial.cell_data) {
          const int k = serial.components.at(name);
          const auto& mine = g.cell_data.at(name);
          for (int i = 0; i < k; ++i)
            EXPECT_NEAR(mine[k * c + i], values[k * it->second + i], tolerance(name, values))
                << source << " " << name << " cell " << c;
        }
      }
    }
    // Every serial cell in exactly one piece, every point in some piece.
    EXPECT_EQ(seen.size(), serial.cells.size()) << body;
    for (const auto& [k, n] : seen) EXPECT_EQ(n, 1) << k;
    EXPECT_EQ(seen_points.size(), serial.points.size()) << body;
  }
}

}  // namespace
}  // namespace tc::test
