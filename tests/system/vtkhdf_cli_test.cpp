// `[output] format = "vtkhdf"` through the command line (case-format.md, "What a run leaves"):
// - a run of a small contact case (tests/cases/restart/sliding-2d.toml: two bodies, friction,
//   heating, contact fields on both sides) leaves result.pvd listing one .vtkhdf per body and
//   written step, at the times and parts its ASCII run lists .vtu files, and each file holds
//   the ASCII .vtu's arrays bit for bit (every point and cell array, points, connectivity);
// - `check` refuses an unknown format and zlib with vtkhdf, naming file:line:key;
// - a run stopped and restarted goes on writing .vtkhdf frames, and its result.pvd lists
//   those of the uninterrupted run, each whole and equal to it.
// The 2-rank run is vtkhdf_mpi_cli_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "support/cli.hpp"
#include "support/history.hpp"
#include "support/vtk_files.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

const fs::path sliding = fs::path(TC_SOURCE_DIR) / "tests/cases/restart/sliding-2d.toml";

std::string run_args(const fs::path& out, const std::string& extra = "") {
  return "run " + sliding.string() + " --output " + out.string() + " " + extra;
}

#if TC_HAVE_HDF5

/// Every array of a .vtu in the VTKHDF file's single piece, same bytes.
void expect_same_frame(const fs::path& vtu, const fs::path& vtkhdf) {
  const auto a = tc::test::read_ascii_vtu(vtu);
  const auto h = tc::test::read_vtkhdf(vtkhdf);
  ASSERT_EQ(h.n_cells.size(), 1u) << vtkhdf.string();
  const auto b = h.piece(0);
  EXPECT_EQ(a.size(), b.size()) << vtkhdf.string();
  for (const auto& [key, array] : a) {
    ASSERT_EQ(b.count(key), 1u) << vtkhdf.string() << ": " << key;
    EXPECT_EQ(array.components, b.at(key).components) << vtkhdf.string() << ": " << key;
    EXPECT_TRUE(array.bytes == b.at(key).bytes) << vtkhdf.string() << ": " << key;
  }
}

TEST(VtkHdfCli, ARunWritesTheAsciiFramesValuesListedInResultPvd) {
  const auto dir = tc::test::fresh_dir("vtkhdf-cli");
  auto r = thermocontact(run_args(dir / "ascii"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = thermocontact(run_args(dir / "hdf", "--set output.format=vtkhdf"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto pa = tc::test::read_collection(dir / "ascii/result.pvd");
  const auto ph = tc::test::read_collection(dir / "hdf/result.pvd");
  ASSERT_TRUE(ph.whole);
  // The same data sets (every 3rd step and the last, both bodies), the same times.
  ASSERT_EQ(pa.files.size(), ph.files.size());
  EXPECT_EQ(pa.times, ph.times);
  EXPECT_GE(ph.files.size(), 2u * 14);
  for (size_t i = 0; i < ph.files.size(); ++i) {
    const auto stem = pa.files[i].substr(0, pa.files[i].size() - 4);  // without ".vtu"
    EXPECT_EQ(ph.files[i], stem + ".vtkhdf");
    expect_same_frame(dir / "ascii" / pa.files[i], dir / "hdf" / ph.files[i]);
  }
  // The contact fields are there on both sides (the slave's and the master's through the
  // mortar), and non-zero: the comparison above is of a contact, not of zeros.
  const auto last = tc::test::read_vtkhdf(dir / "hdf" / ph.files.back());
  const auto& p = last.arrays.at("PointData/contact_pressure");
  double most = 0;
  for (size_t i = 0; i < p.rows(); ++i) most = std::max(most, p.value(i));
  EXPECT_GT(most, 0.0);
  // No .vtu and no temporary file beside them.
  for (const auto& e : fs::directory_iterator(dir / "hdf")) {
    EXPECT_NE(e.path().extension().string(), ".vtu") << e.path().string();
    EXPECT_NE(e.path().extension().string(), ".tmp") << e.path().string();
  }
}

/// The uninterrupted run's data sets with those of step 17, where the split runs stop, after
/// step 15's (both bodies, in the case's order).
std::vector<std::string> with_stopped_step(std::vector<std::string> files) {
  const auto at = std::find(files.begin(), files.end(), "upper_000018.vtkhdf");
  EXPECT_NE(at, files.end());
  files.insert(at, {"upper_000017.vtkhdf", "lower_000017.vtkhdf"});
  return files;
}

TEST(VtkHdfCli, ARestartGoesOnWritingVtkhdfFrames) {
  const auto dir = tc::test::fresh_dir("vtkhdf-restart");
  const std::string vtkhdf = "--set output.format=vtkhdf";
  auto r = thermocontact(run_args(dir / "full", vtkhdf));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Stopped at step 17, between two outputs (every = 3), and restarted.
  r = thermocontact(run_args(dir / "split", vtkhdf + " --stop-after 17"));
  ASSERT_EQ(r.exit_code, 1) << r.output;
  r = thermocontact("run " + sliding.string() + " --restart " + (dir / "split").string() + " " +
                    vtkhdf);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // result.pvd lists the uninterrupted run's data sets, in its order, and the last state of
  // the stopped run (step 17, written when it stopped: case-format.md keeps it listed), all
  // of them whole and equal to the uninterrupted run's where it has them.
  const auto full = tc::test::read_collection(dir / "full/result.pvd");
  const auto c = tc::test::read_collection(dir / "split/result.pvd");
  ASSERT_TRUE(c.whole);
  EXPECT_EQ(c.files, with_stopped_step(full.files));
  for (const auto& f : c.files) {
    ASSERT_EQ(fs::path(f).extension().string(), ".vtkhdf") << f;
    const auto b = tc::test::read_vtkhdf(dir / "split" / f);
    if (f.find("_000017.") != std::string::npos) continue;  // not in the uninterrupted run
    // The restart reproduces the run bit for bit (restart_test.cpp): so do its frames.
    const auto a = tc::test::read_vtkhdf(dir / "full" / f);
    EXPECT_EQ(a.arrays.size(), b.arrays.size()) << f;
    for (const auto& [key, array] : a.arrays)
      EXPECT_TRUE(b.arrays.count(key) && array.bytes == b.arrays.at(key).bytes) << f << ": " << key;
  }
}

TEST(VtkHdfCli, ARestartRebuildsAMissingResultPvdFromTheVtkhdfFiles) {
  const auto dir = tc::test::fresh_dir("vtkhdf-rebuild");
  const std::string vtkhdf = "--set output.format=vtkhdf";
  auto r = thermocontact(run_args(dir / "full", vtkhdf));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = thermocontact(run_args(dir / "split", vtkhdf + " --stop-after 17"));
  ASSERT_EQ(r.exit_code, 1) << r.output;
  fs::remove(dir / "split/result.pvd");
  r = thermocontact("run " + sliding.string() + " --restart " + (dir / "split").string() + " " +
                    vtkhdf);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("rebuilt from the"), std::string::npos) << r.output;
  EXPECT_EQ(tc::test::read_collection(dir / "split/result.pvd").files,
            with_stopped_step(tc::test::read_collection(dir / "full/result.pvd").files));
}

#endif

/// `[output]` of the sliding case with `lines` instead of its own.
fs::path variant(const fs::path& dir, const std::string& lines) {
  auto text = tc::test::read_file(sliding);
  const auto at = text.find("[output]\n");
  EXPECT_NE(at, std::string::npos);
  text = text.substr(0, at) + "[output]\n" + lines + "\n";
  std::ofstream(dir / "case.toml") << text;
  return dir / "case.toml";
}

TEST(VtkHdfCli, CheckRefusesAnUnknownFormatAndZlibWithVtkhdf) {
  const auto dir = tc::test::fresh_dir("vtkhdf-check");
  auto c = variant(dir, "format = \"hdf5\"");
  auto r = thermocontact("check " + c.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(c.string() + ":"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("output.format: found \"hdf5\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"vtkhdf\""), std::string::npos) << r.output;  // among the choices
  c = variant(dir, "format = \"vtkhdf\"\ncompression = \"zlib\"");
  r = thermocontact("check " + c.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("output.compression: found \"zlib\" with format = \"vtkhdf\""),
            std::string::npos)
      << r.output;
  // And through --set, as a run takes it.
  r = thermocontact("check " + sliding.string() + " --set output.format=vtk");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("output.format: found \"vtk\""), std::string::npos) << r.output;
#if TC_HAVE_HDF5
  r = thermocontact("check " + sliding.string() + " --set output.format=vtkhdf");
  EXPECT_EQ(r.exit_code, 0) << r.output;
#else
  r = thermocontact("check " + sliding.string() + " --set output.format=vtkhdf");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("built without HDF5"), std::string::npos) << r.output;
#endif
}

}  // namespace
