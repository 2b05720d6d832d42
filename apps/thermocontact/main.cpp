// thermocontact: the command line (case-format.md). Exit codes: 0 done; 1 stopped by a
// numerical failure or a signal (the steps done stay written); 2 invalid input.
#include <fmt/format.h>
#include <gmsh.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "tc/core/error.hpp"
#include "tc/core/petsc.hpp"
#include "tc/io/auto_subdomains.hpp"
#include "tc/io/case_reader.hpp"
#include "tc/io/checkpoint.hpp"
#include "tc/io/files.hpp"
#include "tc/io/geometry_checks.hpp"
#include "tc/io/output.hpp"
#include "tc/io/output_lock.hpp"
#include "tc/physics/simulation.hpp"

namespace {

std::atomic<int> g_stop{0};
// OutputWriter::stopped_summary and summary.json of the run (rank 0), for on_signal.
char g_stopped_summary[4096] = {}, g_summary[4096] = {};

/// The signals that ask a run to stop: Ctrl-C, kill, a dropped terminal or ssh session, and the
/// warnings batch systems send before they kill (SIGUSR1/2, SIGXCPU on a CPU-time limit).
constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGUSR2, SIGXCPU};

/// The first stop signal lets the step under way finish, then the run stops with its output
/// whole (exit 1, summary "stopped"); a second one ends the process at once with the
/// signal's default action (the user insists, e.g. during a long factorisation).
extern "C" void on_signal(int sig) {
  if (g_stop.exchange(sig) != 0) {
    if (g_summary[0] != '\0') (void)std::rename(g_stopped_summary, g_summary);
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

/// Installed after PetscInitialize, whose handler took SIGHUP, SIGPIPE, SIGQUIT … for its own
/// (exit 59, summary.json left "running"; issue 20, #11). SIGPIPE is ignored: a reader that
/// closes the pipe (`thermocontact run … | head -2`) makes writes to stdout fail, not the run.
/// SIGQUIT keeps its default: quit now, with a core dump.
void install_signal_handlers() {
  for (const int sig : kStopSignals) std::signal(sig, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  std::signal(SIGQUIT, SIG_DFL);
  // Beyond a file-size limit (ulimit -f) a write then fails with EFBIG and the run stops like
  // on a full disk, with its output whole, instead of being killed by the signal.
  std::signal(SIGXFSZ, SIG_IGN);
}

/// --stop-after N (tests, batch jobs): raises the stop flag after step N as SIGTERM would, so
/// that a run stops at a chosen step deterministically (restart_test).
class StopAfter : public tc::physics::Observer {
 public:
  explicit StopAfter(int steps) : steps_(steps) {}
  void step(const tc::physics::Simulation& sim) override {
    if (steps_ >= 0 && sim.step() >= steps_) g_stop.store(SIGTERM);
  }

 private:
  int steps_;
};

/// The options on the command line that nothing read: `-o dir` (for --output) or a mistyped
/// PETSc option would otherwise pass silently to PETSc's database and be ignored. Printed after
/// the run, when every option that the run could query has been queried (PETSc's
/// -options_left, as a warning).
void warn_unused_options() {
  PetscInt n = 0;
  char** names = nullptr;
  char** values = nullptr;
  if (PetscOptionsLeftGet(nullptr, &n, &names, &values) != 0) return;
  for (PetscInt i = 0; i < n; ++i)
    fmt::print(stderr, "warning: option -{}{}{} was not used (run options: --output, --restart)\n",
               names[i], values[i] ? " " : "", values[i] ? values[i] : "");
  PetscOptionsLeftRestore(nullptr, &n, &names, &values);
}

/// Every rank reads the same case, meshes and checkpoint and fails on them alike: rank 0
/// alone says so (with mpirun each message stood once per rank, sometimes interleaved).
bool input_reporter() {
  return tc::core::PetscSession::rank() == 0;
}

int report_input_error(const tc::InputError& e) {
  if (!input_reporter()) return 2;
  for (const auto& issue : e.issues()) fmt::print(stderr, "error: {}\n", issue.str());
  fmt::print(stderr, "{} error{} in the case file; nothing was run.\n", e.issues().size(),
             e.issues().size() == 1 ? "" : "s");
  return 2;
}

int report_bad_input(const std::exception& e) {
  if (input_reporter()) fmt::print(stderr, "error: {}\n", e.what());
  return 2;
}

/// An error every rank threw together (core/collective.hpp) is printed once, by rank 0; one
/// of a single rank by that rank.
void report(const std::exception& e, const char* prefix) {
  if (tc::reported_here(e, tc::core::PetscSession::rank()))
    fmt::print(stderr, "{}: {}\n", prefix, e.what());
}

/// PETSc reads -options_file itself, at MPI_Init time: a missing file stopped the run with
/// PETSc's trace and the build machine's source path, and /dev/zero crashed PETSc (issue 20,
/// #15). The file is checked first: a regular file, readable, of at most 1 MiB.
std::string bad_options_file(const std::vector<std::string>& extra) {
  for (size_t i = 0; i + 1 < extra.size(); ++i) {
    if (extra[i] != "-options_file") continue;
    const std::filesystem::path f(extra[i + 1]);
    std::error_code ec;
    std::string why = tc::io::not_a_file(f);
    if (why.empty() && std::filesystem::file_size(f, ec) > (std::size_t{1} << 20))
      why = "is larger than 1 MiB";
    else if (why.empty() && !std::ifstream(f))
      why = "cannot be read";
    if (!why.empty())
      return fmt::format(
          "error: option -options_file: found {}, which {}; expected a readable file of "
          "PETSc options\n",
          f.string(), why);
  }
  return {};
}

/// The factorisation package of -tc_factor_package, checked against those this PETSc has
/// before anything is assembled (it failed in the first factorisation, exit 1).
std::string bad_factor_package() {
  const auto opt = tc::core::requested_factor_package();
  if (opt.empty()) return {};
  const auto known = tc::core::available_cholesky_packages();
  if (std::find(known.begin(), known.end(), opt) != known.end()) return {};
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  return fmt::format(
      "error: option -tc_factor_package: found '{}', expected one of this PETSc's Cholesky "
      "packages: {}\n",
      opt, list);
}

/// -tc_forward_compliance (core::CholeskySolver::forward_compliance_pays) takes a logical
/// value or none; PETSc would reject another only at the first contact step, with its trace.
std::string bad_forward_compliance() {
  char opt[64] = {};
  PetscBool set = PETSC_FALSE;
  TC_PETSC(
      PetscOptionsGetString(nullptr, nullptr, "-tc_forward_compliance", opt, sizeof opt, &set));
  if (!set) return {};
  std::string v(opt);
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* ok : {"", "true", "false", "yes", "no", "on", "off", "1", "0"})
    if (v == ok) return {};
  return fmt::format(
      "error: option -tc_forward_compliance: found '{}', expected nothing, true or false\n", opt);
}

/// The case's warnings (implausible in SI) and the geometric ones, by rank 0.
void print_warnings(const tc::physics::Problem& problem, const std::vector<std::string>& more) {
  if (tc::core::PetscSession::rank() != 0) return;
  for (const auto& w : problem.warnings) fmt::print(stderr, "warning: {}\n", w);
  for (const auto& w : more) fmt::print(stderr, "warning: {}\n", w);
}

int run(const std::string& case_file, const std::vector<std::string>& overrides,
        const std::string& output, const std::string& restart, bool force, int stop_after,
        std::vector<std::string> extra, const char* program) {
  if (const auto why = bad_options_file(extra); !why.empty()) {
    fmt::print(stderr, "{}nothing was run.\n", why);
    return 2;
  }
  std::vector<char*> args{const_cast<char*>(program)};
  for (auto& a : extra) args.push_back(a.data());
  int argc = static_cast<int>(args.size());
  args.push_back(nullptr);  // argv[argc] == nullptr: MPI_Init walks argv to it (it crashed)
  char** argv = args.data();
  tc::core::PetscSession session(&argc, &argv);
  install_signal_handlers();
  if (auto why = bad_factor_package() + bad_forward_compliance(); !why.empty()) {
    if (input_reporter()) fmt::print(stderr, "{}nothing was run.\n", why);
    return 2;
  }
  try {
    auto problem = tc::io::read_case(case_file, overrides);
    if (!output.empty()) problem.output.directory = output;
    if (!restart.empty()) problem.output.directory = restart;  // continued where it stopped
    print_warnings(problem, tc::io::check_geometry(problem));
    // Held until the run returns: a second run into the same directory is refused (exit 2)
    // before it sets anything up, instead of mixing its rows with this one's.
    const auto earlier = !restart.empty() ? tc::io::EarlierRun::keep
                         : force          ? tc::io::EarlierRun::replace
                                          : tc::io::EarlierRun::refuse;
    const tc::io::OutputLock lock(problem.output.directory, restart.empty(), earlier);
    tc::physics::Simulation sim(problem);
    if (!problem.contacts.empty()) sim.enable_mortar_contact();
    const auto case_hash = tc::io::input_hash(problem);
    tc::io::OutputWriter writer(problem.output.directory, problem.output.every);
    if (tc::core::PetscSession::rank() == 0) {
      const auto from = tc::io::OutputWriter::stopped_summary(problem.output.directory).string();
      const auto to = (problem.output.directory / "summary.json").string();
      if (from.size() < sizeof g_stopped_summary) {
        std::snprintf(g_stopped_summary, sizeof g_stopped_summary, "%s", from.c_str());
        std::snprintf(g_summary, sizeof g_summary, "%s", to.c_str());
      }
    }
    if (!restart.empty()) {
      const auto file = tc::io::checkpoint_file(restart);
      tc::io::check_restart_outputs(restart);
      try {
        sim.restore(tc::io::read_checkpoint(file, sim, case_hash));
      } catch (const tc::io::CheckpointError&) {
        throw;
      } catch (const tc::Error& e) {  // sizes that passed the header but not the problem
        throw tc::io::CheckpointError(fmt::format("checkpoint {}: {}", file.string(), e.what()));
      }
      writer.resume();
      if (tc::core::PetscSession::rank() == 0)
        fmt::print("restarting from step {} (t = {:g} s) of {}\n", sim.step(), sim.time(),
                   file.string());
    }
    tc::io::CheckpointWriter checkpoint(problem.output.directory, case_hash);
    tc::io::ProgressLine progress(isatty(STDERR_FILENO) != 0);
    StopAfter stop(stop_after);
    tc::io::Observers observers({&writer, &checkpoint, &progress, &stop});
    const auto status = sim.run(observers, &g_stop);
    if (tc::core::PetscSession::rank() == 0) {
      warn_unused_options();
      if (status.completed)
        fmt::print("done: {} steps; output in {}\n", status.steps_done,
                   problem.output.directory.string());
      else
        fmt::print(stderr, "stopped: {}\noutput of the {} completed step(s) is in {}\n",
                   status.message, writer.steps_written(), problem.output.directory.string());
    }
    // Flushed while SIGPIPE is still ignored: PetscFinalize restores its default, and a reader
    // gone from the pipe would kill the process at exit's flush (exit 141 after a whole run).
    std::fflush(stdout);
    return status.exit_code;
  } catch (const tc::InputError& e) {
    return report_input_error(e);
  } catch (const tc::MeshError& e) {
    return report_bad_input(e);
  } catch (const tc::io::CheckpointError& e) {
    return report_bad_input(e);
  } catch (const tc::io::OutputInUse& e) {
    report(e, "error");
    return 2;
  } catch (const tc::Error& e) {
    report(e, "stopped");
    return 1;
  }
}

int check(const std::string& case_file, const std::vector<std::string>& overrides,
          const char* program) {
  int argc = 1;
  char* args[] = {const_cast<char*>(program), nullptr};
  char** argv = args;
  tc::core::PetscSession session(&argc, &argv);  // the contact check builds the mortar rows
  try {
    const auto problem = tc::io::read_case(case_file, overrides);
    print_warnings(problem, tc::io::check_geometry(problem));
    if (tc::core::PetscSession::rank() != 0) return 0;  // every rank read it; one reports
    int nodes = 0, cells = 0;
    for (const auto& b : problem.bodies) nodes += b.mesh.n_nodes(), cells += b.mesh.n_cells();
    fmt::print("{}: valid ({}D, {} bod{}, {} nodes, {} cells, {} steps)\n", case_file,
               problem.dimension, problem.bodies.size(), problem.bodies.size() == 1 ? "y" : "ies",
               nodes, cells, problem.time.n_steps());
    const int node = tc::core::PetscSession::node_size();
    const auto each = node > 1 ? fmt::format(" on each of the {} ranks of this node", node) : "";
    for (const auto& b : problem.bodies)
      if (b.subdomains > 1)
        fmt::print(
            "  body \"{}\": {} FETI subdomains (solved directly it would need about {:.1f} "
            "GiB{})\n",
            b.name, b.subdomains,
            tc::io::direct_memory(problem.dimension,
                                  static_cast<double>(b.mesh.n_nodes()) * problem.dimension) /
                (1024.0 * 1024.0 * 1024.0),
            each);
    return 0;
  } catch (const tc::InputError& e) {
    return report_input_error(e);
  } catch (const tc::MeshError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
}

int info(const char* program) {
  int argc = 1;
  char* args[] = {const_cast<char*>(program), nullptr};
  char** argv = args;
  tc::core::PetscSession session(&argc, &argv);
  char version[256];
  TC_PETSC(PetscGetVersion(version, sizeof version));
  fmt::print("thermocontact {}\n", THERMOCONTACT_VERSION);
  fmt::print("PETSc: {}\n", version);
  fmt::print("MPI ranks: {}\n", tc::core::PetscSession::size());
  fmt::print("BLAS threads per rank: {} (OPENBLAS_NUM_THREADS sets them)\n",
             tc::core::PetscSession::blas_threads());
  std::string packages;
  for (const auto& p : tc::core::available_cholesky_packages())
    packages += (packages.empty() ? "" : ", ") + p;
  fmt::print("Cholesky factorizations: {}\n", packages);
  fmt::print("Gmsh: {}\n", GMSH_API_VERSION);
  return 0;
}

/// Whether a path option was given with an empty value. Such a value is refused: it was taken
/// for an absent option (`--restart ""` ran from step 0, `--output ""` wrote into the case's
/// [output].directory).
bool empty_path(const CLI::Option* option, const std::string& value, std::string_view expected) {
  if (option->count() == 0 || !value.empty()) return false;
  fmt::print(stderr, "error: {}: found an empty path, expected {}; nothing was run.\n",
             option->get_name(), expected);
  return true;
}

/// The first word of the command line when it is not a subcommand (CLI11 says "A subcommand
/// is required" of `thermocontact frobnicate`), or "".
std::string unknown_subcommand(CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  std::vector<std::string> names;
  for (const auto* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    if (sub->get_name() == argv[1]) return "";
    names.push_back(sub->get_name());
  }
  return fmt::format("error: unknown subcommand '{}', expected one of: {}\n", argv[1],
                     fmt::join(names, ", "));
}

/// An argument of `run` after the case file that is neither a PETSc option nor an option's
/// value: `run A.toml B.toml` ran A and ignored B (CLI11 passes it on with the PETSc options).
std::string stray_argument(const std::vector<std::string>& extra) {
  for (size_t i = 0; i < extra.size(); ++i)
    if (extra[i].rfind('-', 0) != 0 && (i == 0 || extra[i - 1].rfind('-', 0) != 0)) return extra[i];
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  install_signal_handlers();  // a signal during start-up too; again after PetscInitialize
  CLI::App app{"thermocontact: dynamic thermo-mechanical contact with Coulomb friction"};
  app.require_subcommand(1);
  std::string case_file, output, restart;
  auto* run_cmd = app.add_subcommand("run", "run a case");
  run_cmd->add_option("case", case_file, "case file (TOML)")->required();
  auto* output_opt =
      run_cmd->add_option("--output", output, "output directory (overrides [output].directory)");
  auto* restart_opt =
      run_cmd
          ->add_option("--restart", restart,
                       "continue the run whose output is in this directory from its last "
                       "checkpoint")
          ->excludes(output_opt);
  bool force = false;
  run_cmd
      ->add_flag("--force", force,
                 "replace the output of an earlier run in the output directory (its history, "
                 "checkpoint and fields are removed first)")
      ->excludes(restart_opt);
  int stop_after = -1;
  run_cmd->add_option("--stop-after", stop_after, "stop after this step as SIGTERM would")
      ->group("");  // for tests and batch jobs: undocumented in --help
  std::vector<std::string> overrides;
  const char* set_help =
      "KEY=VALUE: set a key of the case file before it is validated (repeatable), e.g. "
      "--set contact.friction=0.5, --set time.end=1.0, --set 'bodies[0].material=\"steel\"'";
  run_cmd->add_option("--set", overrides, set_help)->allow_extra_args(false);
  run_cmd->allow_extras();  // PETSc options, e.g. -tc_factor_package mumps
  auto* check_cmd = app.add_subcommand("check", "validate a case file only");
  check_cmd->add_option("case", case_file, "case file (TOML)")->required();
  check_cmd->add_option("--set", overrides, set_help)->allow_extra_args(false);
  app.add_subcommand("info", "version, PETSc/MPI configuration, factorizations");
  // PETSc's -help (one dash) after `run` goes to PETSc, not to CLI11's -h: CLI11 took it for
  // its own help, so PETSc's list of options was unreachable.
  std::vector<char*> kept;
  bool petsc_help = false;
  for (int i = 0; i < argc; ++i) {
    if (std::string_view(argv[i]) == "-help" && i > 1 && std::string_view(argv[1]) == "run")
      petsc_help = true;
    else
      kept.push_back(argv[i]);
  }
  argc = static_cast<int>(kept.size());
  argv = kept.data();
  if (const auto message = unknown_subcommand(app, argc, argv); !message.empty()) {
    fmt::print(stderr, "{}", message);
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (empty_path(output_opt, output, "an output directory (or no --output: [output].directory)") ||
      empty_path(restart_opt, restart, "the output directory of the run to continue"))
    return 2;
  if (const auto extra = stray_argument(run_cmd->remaining()); !extra.empty()) {
    fmt::print(stderr,
               "error: run: found the extra argument '{}' after the case file {}, expected one "
               "case file (PETSc options begin with '-'); nothing was run.\n",
               extra, case_file);
    return 2;
  }
  try {
    if (run_cmd->parsed()) {
      auto extra = run_cmd->remaining();
      if (petsc_help) extra.emplace_back("-help");
      return run(case_file, overrides, output, restart, force, stop_after, extra, argv[0]);
    }
    if (check_cmd->parsed()) return check(case_file, overrides, argv[0]);
    return info(argv[0]);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
}
