// thermocontact: the command line (case-format.md). Exit codes: 0 done; 1 stopped by a
// numerical failure or a signal (the steps done stay written); 2 invalid input.
#include <fmt/format.h>
#include <gmsh.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>

#include "tc/core/error.hpp"
#include "tc/core/petsc.hpp"
#include "tc/io/case_reader.hpp"
#include "tc/io/checkpoint.hpp"
#include "tc/io/geometry_checks.hpp"
#include "tc/io/output.hpp"
#include "tc/io/output_lock.hpp"
#include "tc/physics/simulation.hpp"

namespace {

std::atomic<int> g_stop{0};
extern "C" void on_signal(int sig) {
  g_stop.store(sig);
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

int report_input_error(const tc::InputError& e) {
  for (const auto& issue : e.issues()) fmt::print(stderr, "error: {}\n", issue.str());
  fmt::print(stderr, "{} error{} in the case file; nothing was run.\n", e.issues().size(),
             e.issues().size() == 1 ? "" : "s");
  return 2;
}

/// An error every rank threw together (core/collective.hpp) is printed once, by rank 0; one
/// of a single rank by that rank.
void report(const std::exception& e, const char* prefix) {
  if (tc::reported_here(e, tc::core::PetscSession::rank()))
    fmt::print(stderr, "{}: {}\n", prefix, e.what());
}

int run(const std::string& case_file, const std::string& output, const std::string& restart,
        int stop_after, std::vector<std::string> extra, const char* program) {
  std::vector<char*> args{const_cast<char*>(program)};
  for (auto& a : extra) args.push_back(a.data());
  int argc = static_cast<int>(args.size());
  args.push_back(nullptr);  // argv[argc] == nullptr: MPI_Init walks argv to it (it crashed)
  char** argv = args.data();
  tc::core::PetscSession session(&argc, &argv);
  try {
    auto problem = tc::io::read_case(case_file);
    if (!output.empty()) problem.output.directory = output;
    if (!restart.empty()) problem.output.directory = restart;  // continued where it stopped
    const auto warnings = tc::io::check_geometry(problem);
    if (tc::core::PetscSession::rank() == 0)
      for (const auto& w : warnings) fmt::print(stderr, "warning: {}\n", w);
    // Held until the run returns: a second run into the same directory is refused (exit 2)
    // before it sets anything up, instead of mixing its rows with this one's.
    const tc::io::OutputLock lock(problem.output.directory, restart.empty());
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    // Beyond a file-size limit (ulimit -f) a write then fails with EFBIG and the run stops
    // like on a full disk, with its output whole, instead of being killed by the signal.
    std::signal(SIGXFSZ, SIG_IGN);
    tc::physics::Simulation sim(problem);
    if (problem.contact) sim.enable_mortar_contact();
    const auto case_hash = tc::io::file_hash(case_file);
    tc::io::OutputWriter writer(problem.output.directory, problem.output.every);
    if (!restart.empty()) {
      const auto file = tc::io::checkpoint_file(restart);
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
    return status.exit_code;
  } catch (const tc::InputError& e) {
    return report_input_error(e);
  } catch (const tc::MeshError& e) {
    report(e, "error");
    return 2;
  } catch (const tc::io::CheckpointError& e) {
    report(e, "error");
    return 2;
  } catch (const tc::io::OutputInUse& e) {
    report(e, "error");
    return 2;
  } catch (const tc::Error& e) {
    report(e, "stopped");
    return 1;
  }
}

int check(const std::string& case_file, const char* program) {
  int argc = 1;
  char* args[] = {const_cast<char*>(program), nullptr};
  char** argv = args;
  tc::core::PetscSession session(&argc, &argv);  // the contact check builds the mortar rows
  try {
    const auto problem = tc::io::read_case(case_file);
    for (const auto& w : tc::io::check_geometry(problem)) fmt::print(stderr, "warning: {}\n", w);
    int nodes = 0, cells = 0;
    for (const auto& b : problem.bodies) nodes += b.mesh.n_nodes(), cells += b.mesh.n_cells();
    fmt::print("{}: valid ({}D, {} bod{}, {} nodes, {} cells, {} steps)\n", case_file,
               problem.dimension, problem.bodies.size(), problem.bodies.size() == 1 ? "y" : "ies",
               nodes, cells, problem.time.n_steps());
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
  std::string packages;
  for (const auto& p : tc::core::available_cholesky_packages())
    packages += (packages.empty() ? "" : ", ") + p;
  fmt::print("Cholesky factorizations: {}\n", packages);
  fmt::print("Gmsh: {}\n", GMSH_API_VERSION);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"thermocontact: dynamic thermo-mechanical contact with Coulomb friction"};
  app.require_subcommand(1);
  std::string case_file, output, restart;
  auto* run_cmd = app.add_subcommand("run", "run a case");
  run_cmd->add_option("case", case_file, "case file (TOML)")->required();
  auto* output_opt =
      run_cmd->add_option("--output", output, "output directory (overrides [output].directory)");
  run_cmd
      ->add_option("--restart", restart,
                   "continue the run whose output is in this directory from its last checkpoint")
      ->excludes(output_opt);
  int stop_after = -1;
  run_cmd->add_option("--stop-after", stop_after, "stop after this step as SIGTERM would")
      ->group("");          // for tests and batch jobs: undocumented in --help
  run_cmd->allow_extras();  // PETSc options, e.g. -tc_factor_package mumps
  auto* check_cmd = app.add_subcommand("check", "validate a case file only");
  check_cmd->add_option("case", case_file, "case file (TOML)")->required();
  app.add_subcommand("info", "version, PETSc/MPI configuration, factorizations");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (run_cmd->parsed())
      return run(case_file, output, restart, stop_after, run_cmd->remaining(), argv[0]);
    if (check_cmd->parsed()) return check(case_file, argv[0]);
    return info(argv[0]);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
}
