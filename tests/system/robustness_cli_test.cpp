// Issue 20: inputs that the command line took in silently or reported wrongly, each through the
// binary as a user meets it (docs/robustness.md, "Bad input, issue 20").
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <map>
#include <regex>

#include "support/cli.hpp"
#include "tc/io/case/auto_subdomains.hpp"
#include "tc/mesh/box.hpp"

namespace fs = std::filesystem;
using tc::test::replace_all;

namespace {

/// A small valid case (one dynamic 2D body, 2 steps) for the variants below.
const std::string kCase = R"(dimension = 2
[time]
step = 0.001
end = 0.002
[materials.m]
density = 7850.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1e-5
specific_heat = 450.0
thermal_conductivity = 50.0
[[bodies]]
name = "b"
material = "m"
mesh = { box = { min = [0.0, 0.0], max = [0.01, 0.01], cells = [2, 2] } }
)";

/// Writes `text` as case.toml in a fresh directory named after the test.
fs::path write_case(const std::string& name, const std::string& text) {
  const auto file = tc::test::fresh_dir(name) / "case.toml";
  std::ofstream(file) << text;
  return file;
}

/// Whether `output` reports an issue as `FILE:LINE: KEY: ...TEXT...`.
bool reports(const std::string& output, const fs::path& file, const std::string& key,
             const std::string& text) {
  const auto escaped =
      std::regex_replace(file.string(), std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)");
  const std::regex located(escaped + R"(:[1-9][0-9]*: )" +
                           std::regex_replace(key, std::regex(R"([.\[\]])"), R"(\$&)") + ": ");
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line))
    if (std::regex_search(line, located) && line.find(text) != std::string::npos) return true;
  return false;
}

/// Runs the binary under a time limit: the old code ran some of these inputs for hours (1e8
/// steps) or waited for ever (a FIFO as checkpoint), and a regression should fail the test,
/// not hang it. SIGKILL 10 s after the SIGTERM: the run takes SIGTERM as "stop after the step".
const std::string kTimeLimit = "timeout -k 10 120 ";

tc::test::CommandResult limited(const std::string& args) {
  return tc::test::run_command(kTimeLimit + TC_BINARY + " " + args);
}

/// `check` and `run` both refuse `file` with exit code 2, reporting KEY with TEXT.
void expect_refused(const fs::path& file, const std::string& key, const std::string& text) {
  const auto c = limited("check " + file.string());
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_TRUE(reports(c.output, file, key, text)) << key << " / " << text << "\n" << c.output;
  const auto r =
      limited("run " + file.string() + " --output " + (file.parent_path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(reports(r.output, file, key, text)) << key << " / " << text << "\n" << r.output;
  EXPECT_FALSE(fs::exists(file.parent_path() / "out")) << "a refused case wrote output";
}

// #5: end/step was rounded into an int, so it wrapped round: 4294967301 steps ran as 5,
// 2147483649 became negative, 1e300 "done: 0 steps".
TEST(Issue20, AStepCountBeyondTheLimitIsRefusedNamingTimeStep) {
  for (const auto& [end, step] :
       std::vector<std::pair<std::string, std::string>>{{"4294967.301", "0.001"},
                                                        {"2147483.649", "0.001"},
                                                        {"1.0", "1e-300"},
                                                        {"1e308", "1e-308"},
                                                        {"100000.001", "0.001"}}) {
    const auto file =
        write_case("steps", replace_all(replace_all(kCase, "end = 0.002", "end = " + end),
                                        "step = 0.001", "step = " + step));
    expect_refused(file, "time.step", "expected at most 100000000 steps");
  }
}

TEST(Issue20, AStepCountAtTheLimitIsAccepted) {
  const auto file = write_case("steps-limit", replace_all(kCase, "end = 0.002", "end = 100000.0"));
  const auto c = limited("check " + file.string());
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("100000000 steps"), std::string::npos) << c.output;
}

// #6: body names became file names (<name>_<step>.vtu, in result.pvd's XML) and history.csv
// columns unescaped: "../../evil" wrote outside the output directory, "a,b" split a column.
TEST(Issue20, ABodyNameOutsideTheSafeSetIsRefused) {
  for (const std::string& name :
       std::vector<std::string>{R"(../../evil)", R"(a/b)", R"(a,b)", R"(a\nb)", R"(a&b<c>\"q)",
                                R"(.hidden)", R"()", R"(a b)", std::string(65, 'n')}) {
    const auto file =
        write_case("name", replace_all(kCase, "name = \"b\"", "name = \"" + name + "\""));
    expect_refused(file, "bodies[0].name", "expected 1 to 64 letters, digits");
  }
}

TEST(Issue20, ABoundaryNameInAReactionColumnOutsideTheSafeSetIsRefused) {
  // A displacement boundary's `where` is in the column reaction_<body>_<where>_x: a Gmsh group
  // named "x,min" made one column two. tests/cases/valid/gmsh-file.toml with its group "left"
  // so renamed.
  const auto valid = fs::path(TC_SOURCE_DIR) / "tests/cases/valid";
  const auto file = write_case(
      "where", replace_all(tc::test::read_file(valid / "gmsh-file.toml"), "\"left\"", "\"x,min\""));
  std::ofstream(file.parent_path() / "square.msh")
      << replace_all(tc::test::read_file(valid / "square.msh"), "\"left\"", "\"x,min\"");
  expect_refused(file, "boundary[0].where", "found \"x,min\", a name with the character ','");
  // Only where it reaches a column: the same group with a heat flux is fine.
  const auto text = tc::test::read_file(file);  // before the ofstream truncates it
  std::ofstream(file) << replace_all(text, "displacement = [0.0, 0.0]", "heat_flux = 0.0");
  const auto c = limited("check " + file.string());
  EXPECT_EQ(c.exit_code, 0) << c.output;
}

TEST(Issue20, SafeNamesAreAccepted) {
  const auto file =
      write_case("safe-name", replace_all(kCase, "name = \"b\"", "name = \"Block-1_a.2\"") +
                                  "[[boundary]]\nbody = \"Block-1_a.2\"\nwhere = \"xmin\"\n"
                                  "displacement = [0.0, 0.0]\n");
  const auto r =
      limited("run " + file.string() + " --output " + (file.parent_path() / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(file.parent_path() / "out/Block-1_a.2_000002.vtu"));
  EXPECT_NE(tc::test::read_file(file.parent_path() / "out/history.csv")
                .find("reaction_Block-1_a.2_xmin_x"),
            std::string::npos);
}

// #7: an empty --restart or --output was taken for an absent option: the run started from step
// 0 (or wrote) into the case's [output].directory.
TEST(Issue20, AnEmptyRestartOrOutputPathIsRefused) {
  const auto file = write_case("empty-path", kCase);
  for (const std::string option : {"--restart", "--output"}) {
    const auto r = limited("run " + file.string() + " " + option + " ''");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("error: " + option + ": found an empty path"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(file.parent_path() / "out")) << option << " \"\" ran:\n" << r.output;
  }
}

// #14: misleading messages. An integer beyond the limit was "expected an integer ≥ 1".
TEST(Issue20, AnIntegerBeyondTheLimitIsSaidToBeTooLarge) {
  const std::string too_large = "which is too large; expected an integer from 1 to 1000000000";
  for (const auto& [from, to, key] : std::vector<std::array<std::string, 3>>{
           {"cells = [2, 2]", "cells = [4294967297, 2]", "bodies[0].mesh.box.cells[0]"},
           {"[[bodies]]", "[solver]\nmax_coupling_iterations = 3000000000\n[[bodies]]",
            "solver.max_coupling_iterations"},
           {"[[bodies]]", "[output]\nevery = 1e12\n[[bodies]]", "output.every"}}) {
    const auto file = write_case("too-large", replace_all(kCase, from, to));
    expect_refused(file, key, too_large);
  }
}

TEST(Issue20, ABoxWithTooManyCellsInAllIsRefused) {
  // Each count within the limit, their product 10¹⁰: beyond make_box's int counters.
  const auto file =
      write_case("box-cells", replace_all(kCase, "cells = [2, 2]", "cells = [100000, 100000]"));
  expect_refused(file, "bodies[0].mesh.box.cells",
                 "found 10000000000 cells in all, which is too many; expected at most 100000000");
}

TEST(Issue20, ABoxBeyondTheMachinesMemoryIsRefusedBeforeItIsBuilt) {
  // #3: [30000, 30000] (9e8 cells, under the old limits) took 23 GB in a minute, then the OOM
  // killer (exit 137, no message). [10000, 10000] is at the cell limit (10⁸); its mesh and
  // five matrices need about 136 GiB, beyond the machines this runs on. The time limit of
  // `limited` turns an attempt to build it into a failure, not a hang.
  const auto file =
      write_case("box-memory", replace_all(kCase, "cells = [2, 2]", "cells = [10000, 10000]"));
  expect_refused(file, "bodies[0].mesh.box.cells", "GiB (before any factorisation)");
}

// A directory or a device given as the mesh file "does not exist".
TEST(Issue20, AMeshFileThatIsADirectoryOrADeviceIsSaidToBeSo) {
  auto file = write_case("mesh-dir", replace_all(kCase,
                                                 "mesh = { box = { min = [0.0, 0.0], "
                                                 "max = [0.01, 0.01], cells = [2, 2] } }",
                                                 "mesh = { file = \"dir.msh\" }"));
  fs::create_directories(file.parent_path() / "dir.msh");
  expect_refused(file, "bodies[0].mesh.file", "which is a directory; expected a Gmsh 4 file");
  file = write_case("mesh-dev", replace_all(tc::test::read_file(file), "dir.msh", "/dev/zero"));
  expect_refused(file, "bodies[0].mesh.file", "which is not a regular file");
  file = write_case("mesh-none", replace_all(tc::test::read_file(file), "/dev/zero", "no.msh"));
  expect_refused(file, "bodies[0].mesh.file", "which does not exist");
}

TEST(Issue20, ACaseFileThatIsADirectoryIsSaidToBeSo) {
  const auto dir = tc::test::fresh_dir("case-dir");
  const auto r = limited("check " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("cannot read the case file: it is a directory"), std::string::npos)
      << r.output;
}

// `thermocontact frobnicate` said "A subcommand is required".
TEST(Issue20, AnUnknownSubcommandIsNamed) {
  const auto r = limited("frobnicate");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(
                "unknown subcommand 'frobnicate', expected one of: run, check, stability, info"),
            std::string::npos)
      << r.output;
}

// `run A.toml B.toml` ran A and ignored B (passed on to PETSc with the options).
TEST(Issue20, AnExtraArgumentOfRunIsRefused) {
  const auto file = write_case("extra-argument", kCase);
  const auto out = (file.parent_path() / "out").string();
  for (const std::string& args : std::vector<std::string>{
           file.string() + " B.toml --output " + out,
           file.string() + " --output " + out + " -tc_fail_on_rank 5 B.toml"}) {
    const auto r = limited("run " + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("error: run: found the extra argument 'B.toml'"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(out)) << args << " ran";
  }
  const auto c = limited("check " + file.string() + " B.toml");  // refused by CLI11 already
  EXPECT_EQ(c.exit_code, 2) << c.output;
  // A PETSc option's value is not an extra argument.
  const auto r = limited("run " + file.string() + " --output " + out + " -tc_factor_package petsc");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// #17: a checkpoint.bin linked to /dev/zero or /dev/urandom was read on --restart until memory
// ran out. The restarts run under a 4 GB address-space limit and a time limit, so that a
// regression fails the test instead of exhausting the machine.
TEST(Issue20, ACheckpointThatIsNotARegularFileIsRefusedWithExitTwo) {
  const auto file = write_case("checkpoint-device", kCase);
  const auto dir = file.parent_path() / "out";
  ASSERT_EQ(limited("run " + file.string() + " --output " + dir.string()).exit_code, 0);
  const auto checkpoint = dir / "checkpoint.bin";
  const auto saved = dir / "saved.bin";
  fs::rename(checkpoint, saved);
  const auto restart = [&] {
    return tc::test::run_command("ulimit -v 4000000; " + kTimeLimit + TC_BINARY + " run " +
                                 file.string() + " --restart " + dir.string());
  };
  for (const std::string target : {"/dev/zero", "/dev/urandom", "fifo", "directory"}) {
    fs::remove_all(checkpoint);
    if (target == "fifo")
      ASSERT_EQ(::mkfifo(checkpoint.c_str(), 0600), 0);
    else if (target == "directory")
      fs::create_directory(checkpoint);
    else
      fs::create_symlink(target, checkpoint);
    const auto r = restart();
    EXPECT_EQ(r.exit_code, 2) << target << "\n" << r.output;
    EXPECT_NE(r.output.find("error: checkpoint " + checkpoint.string() + ": is "),
              std::string::npos)
        << target << "\n"
        << r.output;
  }
  // The history a restart keeps is read line by line too.
  fs::remove_all(checkpoint);
  fs::rename(saved, checkpoint);
  fs::rename(dir / "history.csv", dir / "saved.csv");
  fs::create_symlink("/dev/zero", dir / "history.csv");
  auto r = restart();
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("history.csv is not a regular file"), std::string::npos) << r.output;
  // Put back, the restart goes through.
  fs::remove(dir / "history.csv");
  fs::rename(dir / "saved.csv", dir / "history.csv");
  r = restart();
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// #12: `subdomains = 11` on a 10-cell box passed `check`; `run` then failed with "cannot cut 10
// cells into 11 subdomains" and no FILE:LINE:KEY. METIS also leaves parts of small meshes empty
// (10 cells into 7), which `check` did not find either.
TEST(Issue20, SubdomainsTheMeshCannotBeCutIntoAreRefusedByCheckAndRun) {
  const auto with = [](int n) {
    return replace_all(kCase, "cells = [2, 2] } }",
                       "cells = [10, 1] } }\nsubdomains = " + std::to_string(n));
  };
  expect_refused(write_case("subdomains", with(11)), "bodies[0].subdomains",
                 "found 11, more than the 10 cells of the body's mesh; expected 1 to 10");
  expect_refused(write_case("subdomains", with(7)), "bodies[0].subdomains",
                 "found 7, which the body's mesh cannot be cut into: METIS left a subdomain empty");
  const auto file = write_case("subdomains", with(5));
  const auto r =
      limited("run " + file.string() + " --output " + (file.parent_path() / "out").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

}  // namespace

namespace {

/// `count` of `needle` in `text`.
size_t occurrences(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1)) ++n;
  return n;
}

}  // namespace

TEST(Issue20, InputErrorsUnderMpiAreSaidOnceNotOncePerRank) {
  // #13: every rank reads the same case and failed on it alike, and each printed it. A clean
  // environment for the launcher, as in feti_cli_test (this process is an MPI singleton).
  const auto dir = tc::test::fresh_dir("issue20-mpi-once");
  const std::string launcher =
      "env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
      "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
      "OMPI_MCA_rmaps_base_oversubscribe=1 " +
      std::string(TC_MPIEXEC) + " -n 2 " + TC_BINARY;
  const auto several =
      fs::path(TC_SOURCE_DIR) / "tests/cases/invalid/27-several-errors.toml";  // 3 issues
  const auto r = tc::test::run_command(kTimeLimit + launcher + " run " + several.string() +
                                       " --output " + (dir / "out").string());
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_EQ(occurrences(r.output, "error: "), 3u) << r.output;
  EXPECT_EQ(occurrences(r.output, "in the case file; nothing was run"), 1u) << r.output;
  // A geometry error (bodies overlapping at t = 0) likewise.
  const auto overlap = dir / "overlap.toml";
  std::ofstream(overlap) << replace_all(
      tc::test::read_file(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/contact-patch-2d.toml"),
      "min = [0.0, 1.0], max = [1.0, 1.5]", "min = [0.0, 0.0], max = [1.0, 1.5]");
  const auto m = tc::test::run_command(kTimeLimit + launcher + " run " + overlap.string() +
                                       " --output " + (dir / "out2").string());
  EXPECT_NE(m.exit_code, 0) << m.output;
  EXPECT_EQ(occurrences(m.output, "overlap at t = 0"), 1u) << m.output;
}

TEST(Issue20, BadPetscOptionsAreRefusedBeforeTheRunAndHelpReachesPetsc) {
  // #15: an unknown factorisation package failed in the first factorisation (exit 1, with the
  // build machine's source path); a missing -options_file stopped MPI_Init with PETSc's trace,
  // /dev/zero crashed PETSc; -help was CLI11's, so PETSc's options were unreachable.
  const auto file = write_case("petsc-options", kCase);
  const auto out = (file.parent_path() / "out").string();
  const auto run = "run " + file.string() + " --output " + out;
  auto r = limited(run + " -tc_factor_package nonexistent");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("option -tc_factor_package: found 'nonexistent', expected one of"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find(TC_SOURCE_DIR), std::string::npos) << r.output;
  r = limited(run + " -tc_forward_compliance sometimes");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("option -tc_forward_compliance: found 'sometimes', expected nothing, "
                          "true or false"),
            std::string::npos)
      << r.output;
  for (const std::string bad : {"/nonexistent/options", "/dev/zero"}) {
    r = limited(run + " -options_file " + bad);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("option -options_file: found " + bad), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(out)) << "a refused run wrote output";
  r = limited(run + " -help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("The PETSc Team"), std::string::npos) << r.output;
}

TEST(Issue20, AnEarlierRunInTheOutputDirectoryIsRefusedUnlessForced) {
  // #7: a new run into a directory holding another run's output overwrote its history and
  // checkpoint and left its stale .vtu pieces lying beside (and listed with) its own.
  const auto file = write_case("earlier-run", kCase);
  const auto out = file.parent_path() / "out";
  const auto run = "run " + file.string() + " --output " + out.string();
  auto r = limited(run);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "b_000002.vtu"));
  const auto history = tc::test::read_file(out / "history.csv");
  r = limited(run);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds the output of an earlier run"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
  EXPECT_EQ(tc::test::read_file(out / "history.csv"), history) << "the refusal touched it";
  // Forced, with fields every 2 steps: the earlier run's step-1 piece is gone, not listed.
  std::ofstream(file) << kCase << "[output]\nevery = 2\n";
  r = limited(run + " --force");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out / "b_000001.vtu"));
  EXPECT_TRUE(fs::exists(out / "b_000002.vtu"));
  EXPECT_EQ(tc::test::read_file(out / "result.pvd").find("b_000001"), std::string::npos);
  // --force and --restart exclude each other.
  EXPECT_EQ(limited("run " + file.string() + " --restart " + out.string() + " --force").exit_code,
            2);
}

TEST(Startup, ASerialRunNeedsNoOpenMpiSessionDirectory) {
  // Serial runs started together (a parameter sweep, ctest -j) shared one Open MPI session
  // directory, /tmp/ompi.<host>.<uid>/jf.0/1, since every isolated singleton takes the job name
  // [0,1]; one run removing it at MPI_Finalize as another created it aborted MPI_Init (2 of 320
  // concurrent `info` runs). A run must need no such directory at all: here its place is taken
  // by a file, so a run that makes one fails at MPI_Init. A clean environment, since this
  // process is itself a singleton whose defaults its children would inherit.
  const auto tmp = tc::test::fresh_dir("startup-session-dir");
  std::array<char, 256> host{};
  ASSERT_EQ(gethostname(host.data(), host.size() - 1), 0);
  std::string short_host = host.data();
  short_host = short_host.substr(0, short_host.find('.'));
  std::ofstream(tmp / ("ompi." + short_host + "." + std::to_string(getuid()))) << "in the way\n";
  const auto r = tc::test::run_command(kTimeLimit + "env -i PATH=/usr/bin:/bin HOME=/tmp TMPDIR=" +
                                       tmp.string() + " " + TC_BINARY + " info");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("MPI ranks: 1"), std::string::npos) << r.output;
}

TEST(Startup, BlasThreadsAreOneOutsideLargeKernelsAndTheCpusOfTheRunInside) {
  // issue 39: one BLAS thread by default (spinning threads made small products 5–17× slower
  // beside busy processes); large kernels get up to the CPUs the run may use (its affinity
  // mask: taskset, a batch system's cpuset) while they are free; OPENBLAS_NUM_THREADS fixes
  // the number everywhere. `env -u`: this test process sets OPENBLAS_NUM_THREADS=1 for its
  // children (tests/support/main.cpp).
  cpu_set_t cpus;
  CPU_ZERO(&cpus);
  ASSERT_EQ(sched_getaffinity(0, sizeof cpus, &cpus), 0);
  const std::string unset = "env -u OPENBLAS_NUM_THREADS -u OMP_NUM_THREADS ";
  const std::string info = std::string(" ") + TC_BINARY + " info";
  for (const auto& [command, line] :
       {std::pair{unset + "taskset -c 0" + info,
                  std::string("BLAS threads per rank: 1, up to 1 inside large kernels")},
        {unset + info,
         fmt::format("BLAS threads per rank: 1, up to {} inside large kernels", CPU_COUNT(&cpus))},
        {"env OPENBLAS_NUM_THREADS=3" + info,
         std::string("BLAS threads per rank: 3 everywhere")}}) {
    const auto r = tc::test::run_command(kTimeLimit + command);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(line), std::string::npos) << command << "\n" << r.output;
  }
}

TEST(Issue39, SummaryPhasesAddUpToTheWallTimeOfTheRun) {
  // issue 39: summary.json's phases summed to 2.1 s of a 2.8–4.0 s run (start-up, reading,
  // checkpoint and history were in none). Now every phase is exclusive and `total` is the
  // process's time since it started: the phases and `unaccounted` sum to it, `unaccounted`
  // is small, and `total` is the run's wall time as measured from outside, but for what
  // follows the last summary (PetscFinalize, exit) and the shell's own start.
  const auto dir = tc::test::fresh_dir("issue39-phases");
  const auto start = std::chrono::steady_clock::now();
  const auto r = tc::test::thermocontact(
      "run " +
      (std::filesystem::path(TC_SOURCE_DIR) / "tests/cases/verification/section-2d.toml").string() +
      " --output " + (dir / "out").string());
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = tc::test::read_file(dir / "out" / "summary.json");
  const auto at = summary.find("\"wall_seconds\": {");
  ASSERT_NE(at, std::string::npos) << summary;
  const auto body = summary.substr(at, summary.find('}', at) - at);
  std::map<std::string, double> phases;
  const std::regex entry(R"re("(\w+)": ([-+0-9.eE]+))re");
  for (std::sregex_iterator m(body.begin(), body.end(), entry), end; m != end; ++m)
    phases[(*m)[1]] = std::stod((*m)[2]);
  for (const char* p : {"startup", "reading", "setup", "assembly", "factorization", "mortar",
                        "dual_setup", "qp", "mechanical_solve", "heat_solve", "step_other",
                        "history", "output", "checkpoint", "progress", "unaccounted", "total"})
    EXPECT_EQ(phases.count(p), 1u) << p << "\n" << summary;
  double sum = 0;
  for (const auto& [name, seconds] : phases)
    if (name != "total") sum += seconds;
  // The sum is the total by construction, to the printed digits (17 significant).
  EXPECT_NEAR(sum, phases["total"], 1e-9 * phases["total"]);
  // What no phase holds: a few calls between them. The issue's bound, 5 % of the wall, is a
  // benchmark's on the idle machine (bench/RESULTS.md, "summary.json phases"); here, on a
  // machine that may be busy, a descheduled process lands tens of milliseconds between two
  // phases (8 % of this 1.5 s run under load 12), so the test bounds it by 20 %: a large phase
  // left out (start-up, or the steps' own work outside the solvers: a third of this run each)
  // still fails it; the small ones are bounded by the benchmark.
  EXPECT_LE(std::abs(phases["unaccounted"]), 0.20 * phases["total"]) << summary;
  // The total is the process's wall time until the summary: within the wall measured here,
  // and most of it (the shell's start and the process's exit are outside; 0.5 s for them
  // under load). The process's start is known to a clock tick (/proc/self/stat's starttime,
  // core::seconds_since_process_start), so the total may exceed this wall by up to one tick
  // (it did by 1.5 and 3.5 ms).
  const double tick = 1.0 / static_cast<double>(sysconf(_SC_CLK_TCK));
  EXPECT_LE(phases["total"], wall + tick);
  EXPECT_GE(phases["total"], wall - 0.5) << "wall " << wall;
}

TEST(Issue22, CheckSaysWhenABodyIsTooLargeToSolveDirectlyAndCutsIt) {
  // subdomains = "auto" (the default): a 3D box of 2.17 M dofs would need ~86 GiB solved
  // directly (io::body_costs), so it is cut into FETI subdomains of about 40 k dofs, and
  // `check` says so before anything runs. The count follows this machine's memory
  // (io::kMemoryShare of it for the bodies): the expected line is computed from the same rule.
  const auto file = write_case(
      "auto-subdomains",
      replace_all(replace_all(kCase, "dimension = 2", "dimension = 3"),
                  "min = [0.0, 0.0], max = [0.01, 0.01], cells = [2, 2]",
                  "min = [0.0, 0.0, 0.0], max = [0.01, 0.01, 0.007], cells = [100, 100, 70]"));
  const auto r = limited("check " + file.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const auto box = tc::mesh::make_box(3, {0, 0, 0}, {0.01, 0.01, 0.007}, {100, 100, 70});
  const int n =
      tc::io::choose_subdomains({tc::io::body_costs(box, 3, 1, 0)},
                                tc::io::kMemoryShare * static_cast<double>(pages) * page, 2)
          .subdomains[0];
  if (n > 1)
    EXPECT_NE(r.output.find("body \"b\": " + std::to_string(n) + " FETI subdomains"),
              std::string::npos)
        << r.output;
  else
    EXPECT_EQ(r.output.find("FETI subdomains"), std::string::npos) << r.output;
  std::printf("check: %s", r.output.c_str());
}

TEST(Issue22, RanksOnOneNodeShareItsMemoryWhenSubdomainsAreChosen) {
  // Every rank holds every body's matrices and its share of the direct factors (docs/choices.md,
  // "Replicated state"), so "auto" gives each rank its share of the node's memory: a cube whose
  // direct solve over 2 ranks (the fit, io::direct_memory: MUMPS spreads the factor) does not
  // fit half the budget is cut on two ranks, with the count of the same rule on half the
  // budget. (On one rank the same cube is estimated by CHOLMOD's analysis, tens of seconds for
  // such a cube: its one-rank choice is AutoSubdomains' in io_case_reader_test.)
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const double budget = tc::io::kMemoryShare * static_cast<double>(pages) * page;
  int n = 8;
  const auto dofs = [](int c) { return 3.0 * (c + 1.0) * (c + 1.0) * (c + 1.0); };
  while (tc::io::direct_memory(3, dofs(n), 2) <= budget / 2) ++n;
  if (dofs(n) > 2.5e6) GTEST_SKIP() << "no cube below 2.5 M dofs cut on two ranks here";
  const auto cube = tc::mesh::make_box(3, {0, 0, 0}, {0.01, 0.01, 0.01}, {n, n, n});
  const auto cells = std::to_string(n);
  const auto file =
      write_case("auto-subdomains-ranks",
                 replace_all(replace_all(kCase, "dimension = 2", "dimension = 3"),
                             "min = [0.0, 0.0], max = [0.01, 0.01], cells = [2, 2]",
                             "min = [0.0, 0.0, 0.0], max = [0.01, 0.01, 0.01], cells = [" + cells +
                                 ", " + cells + ", " + cells + "]"));
  const std::string launcher =
      "env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
      "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 " +
      std::string(TC_MPIEXEC) + " -n 2 " + TC_BINARY;
  const auto two = tc::test::run_command(kTimeLimit + launcher + " check " + file.string());
  ASSERT_EQ(two.exit_code, 0) << two.output;
  const int k =
      tc::io::choose_subdomains({tc::io::body_costs(cube, 3, 2, 0)}, budget / 2, 2).subdomains[0];
  ASSERT_GT(k, 1);
  EXPECT_NE(two.output.find("body \"b\": " + std::to_string(k) + " FETI subdomains"),
            std::string::npos)
      << two.output;
  EXPECT_NE(two.output.find("on each of the 2 ranks of this node"), std::string::npos)
      << two.output;
  EXPECT_EQ(occurrences(two.output, ": valid ("), 1u) << two.output;  // said once, by rank 0
  std::printf("%d³ cells, two ranks\n%s", n, two.output.c_str());
}
