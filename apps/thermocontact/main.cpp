// thermocontact: the command line (case-format.md). Exit codes: 0 done; 1 stopped by a
// numerical failure or a signal (the steps done stay written); 2 invalid input.
#include <fcntl.h>
#include <fmt/format.h>
#include <gmsh.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string_view>

#include "stability_command.hpp"
#include "tc/core/error.hpp"
#include "tc/core/numeric/collective.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/core/stop.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/io/checks/data_checks.hpp"
#include "tc/io/checks/geometry_checks.hpp"
#include "tc/io/files/files.hpp"
#include "tc/io/files/output_lock.hpp"
#include "tc/io/output/output.hpp"
#include "tc/io/restart/checkpoint.hpp"
#include "tc/io/vtk/vtkhdf.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/linalg/cholmod/cholmod_factor.hpp"
#include "tc/linalg/compliance.hpp"
#include "tc/run/simulation.hpp"

namespace {

// The first stop signal on this rank (or --stop-after): core/stop.hpp's flag, which the mesh
// reader's wait reads too.
std::atomic<int>& g_stop = tc::core::stop_signal;
// What the run acts on: g_stop of any rank, agreed after every step (AgreeOnStop), so that
// every rank leaves the step loop after the same step. A signal reaches the ranks of an
// mpirun at slightly different times; a rank that stopped alone left the others in a
// collective of the next step.
std::atomic<int> g_stop_agreed{0};
// A descriptor of the run's output directory (rank 0), for on_signal: summary.stopped.json is
// renamed over summary.json in the directory the run writes into, whatever its path names now.
std::atomic<int> g_output_directory{-1};

/// The signals that ask a run to stop: Ctrl-C, kill, a dropped terminal or ssh session, and the
/// warnings batch systems send before they kill (SIGUSR1/2, SIGXCPU on a CPU-time limit).
constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGUSR2, SIGXCPU};

/// The first stop signal lets the step under way finish, then the run stops with its output
/// whole (exit 1, summary "stopped"); a second one ends the process at once with the
/// signal's default action (the user insists, e.g. during a long factorisation).
///
/// At the first signal summary.stopped.json (the state after the last written step) is also
/// renamed over summary.json at once: mpirun, on SIGTERM, sends SIGTERM to the ranks and
/// SIGKILL about a second later, before a long step can end, and summary.json said "running"
/// (issue 41, point 6). The run that stops in order writes the real summary over it.
extern "C" void on_signal(int sig) {
  const bool second = g_stop.exchange(sig) != 0;
  if (const int dir = g_output_directory.load(); dir >= 0)
    (void)::renameat(dir, "summary.stopped.json", dir, "summary.json");
  if (second) {
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

/// Makes the stop of a run collective: after every step each rank's g_stop is combined
/// (MPI_MAX: a signal number) and the result is what Simulation::run reads (g_stop_agreed).
class AgreeOnStop : public tc::physics::Observer {
 public:
  void step(const tc::physics::Simulation&) override {
    int local = g_stop.load(), any = local;
    if (tc::core::PetscSession::size() > 1)
      tc::core::check_mpi(MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD),
                          "MPI_Allreduce");
    if (any != 0) g_stop_agreed.store(any);
  }
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

/// Whether this process says what is wrong with the command line. Every rank of an MPI launch
/// parses the same command line and finds the same fault before MPI starts, so rank 0 alone
/// prints it, and every rank exits with the same code (each message stood once per rank; issue
/// 42, D17). The rank comes from the launcher's environment (Open MPI, PMIx, MPICH's PMI); a
/// process started without a launcher is rank 0.
bool command_line_reporter() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* rank = std::getenv(name)) return std::atoi(rank) == 0;
  return true;
}

/// The address space this process needs beyond what it has mapped when main() starts (its
/// libraries, OpenBLAS's thread pool): a 128 MiB buffer per BLAS thread, which OpenBLAS maps
/// at its first call in each thread and, when the mapping fails, retries for ever (a run under
/// `ulimit -v 500000` spun at 100 % CPU in blas_memory_alloc; issue 42, D19). MPI's and
/// PETSc's own start-up fitted in what is left on the 2-core machine (measured: refused at
/// 500 000 kB with 2 threads, where the run hung; runs at 560 000 kB).
std::string address_space_shortfall() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return {};
  std::ifstream status("/proc/self/status");
  double mapped = 0;  // kB
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmSize:", 0) == 0) mapped = std::atof(line.c_str() + 7);
  int threads = 0;
  for (const char* name : {"OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"})
    if (const char* v = std::getenv(name); v && threads <= 0) threads = std::atoi(v);
  if (threads <= 0) {
    cpu_set_t cpus;
    CPU_ZERO(&cpus);
    threads = sched_getaffinity(0, sizeof cpus, &cpus) == 0 ? CPU_COUNT(&cpus) : 1;
  }
  constexpr double mib = 1024.0;  // kB
  const double need = mapped + 128 * mib * threads;
  const double have = static_cast<double>(limit.rlim_cur) / 1024.0;
  if (have >= need) return {};
  return fmt::format(
      "error: the address-space limit (ulimit -v) is {:.0f} kB; thermocontact needs more than "
      "{:.0f} kB here (its libraries {:.0f} kB, and {} BLAS thread{} with a {:.0f} kB buffer "
      "each). Raise the limit (ulimit -v unlimited) or use fewer BLAS threads "
      "(OPENBLAS_NUM_THREADS=1); nothing was run.\n",
      have, need, mapped, threads, threads == 1 ? "" : "s", 128 * mib);
}

/// PETSc 3.18 keeps at most this many distinct option names (MAXOPTIONS in its options.c);
/// one more made PetscInitialize fail with a 530-line "Out of memory" trace, exit 1 (issue 42,
/// D16).
constexpr std::size_t kPetscMaxOptions = 512;

/// The option names (a '-' then a letter; PETSc compares them ignoring case) among `words`.
void add_option_names(const std::vector<std::string>& words, std::set<std::string>& names) {
  for (const auto& w : words) {
    if (w.size() < 2 || w[0] != '-' || std::isalpha(static_cast<unsigned char>(w[1])) == 0)
      continue;
    std::string name = w;
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    names.insert(name);
  }
}

std::vector<std::string> words_of(std::istream& in) {
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

/// The PETSc options of the command line, of PETSC_OPTIONS and of the -options_file files
/// (comments from '#' left out), counted before PETSc is given them: more than PETSc can hold
/// is refused with exit 2. (~/.petscrc and ./.petscrc, which PETSc also reads, are not
/// counted.) The -options_file files must have passed bad_options_file first.
std::string too_many_options(const std::vector<std::string>& extra) {
  std::set<std::string> names;
  add_option_names(extra, names);
  if (const char* env = std::getenv("PETSC_OPTIONS")) {
    std::istringstream in(env);
    add_option_names(words_of(in), names);
  }
  for (size_t i = 0; i + 1 < extra.size(); ++i) {
    if (extra[i] != "-options_file") continue;
    std::ifstream file(extra[i + 1]);
    std::string text;
    for (std::string line; std::getline(file, line);) text += line.substr(0, line.find('#')) + '\n';
    std::istringstream in(text);
    add_option_names(words_of(in), names);
  }
  if (names.size() <= kPetscMaxOptions) return {};
  return fmt::format(
      "error: found {} distinct PETSc options (command line, PETSC_OPTIONS and -options_file "
      "together), expected at most {}, as many as this PETSc can hold\n",
      names.size(), kPetscMaxOptions);
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
  const auto opt = tc::linalg::requested_factor_package();
  PetscBool given = PETSC_FALSE;
  TC_PETSC(PetscOptionsHasName(nullptr, nullptr, "-tc_factor_package", &given));
  if (opt.empty() && !given) return {};
  const auto known = tc::linalg::available_cholesky_packages();
  if (std::find(known.begin(), known.end(), opt) != known.end()) return {};
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  // No value (`-tc_factor_package` last, or before another option) or "" was ignored: the
  // case's package ran where the user asked for another (issue 42, D15).
  return fmt::format(
      "error: option -tc_factor_package: found {}, expected one of this PETSc's Cholesky "
      "packages: {}\n",
      opt.empty() ? std::string("no value") : "'" + opt + "'", list);
}

/// -tc_forward_compliance (linalg::CholmodFactor::forward_compliance_pays) takes a logical
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
/// The reader's warnings, then those of the checks that need the whole case: the geometry (which
/// throws on overlapping contact surfaces, on every rank) and the time data against the scheme.
void print_warnings(const tc::physics::Problem& problem) {
  auto more = tc::io::check_geometry(problem);
  for (auto& w : tc::io::check_time_data(problem)) more.push_back(std::move(w));
  for (auto& w : tc::io::check_lumped_capacity(problem)) more.push_back(std::move(w));
  if (tc::core::PetscSession::rank() != 0) return;
  for (const auto& w : problem.warnings) fmt::print(stderr, "warning: {}\n", w);
  for (const auto& w : more) fmt::print(stderr, "warning: {}\n", w);
  // The ranks' own start is a fraction of a second of the 1-minute average: what it says is
  // the other work's.
  double load = 0;
  if (std::ifstream loadavg("/proc/loadavg"); loadavg >> load) {
    const auto busy =
        tc::core::oversubscription_warning(load, tc::core::ThreadPolicy::cpus().ranks_on_node,
                                           static_cast<int>(sysconf(_SC_NPROCESSORS_ONLN)));
    if (!busy.empty()) fmt::print(stderr, "warning: {}\n", busy);
  }
}

int run(const std::string& case_file, const std::vector<std::string>& overrides,
        const std::string& output, const std::string& restart, bool force, int stop_after,
        std::vector<std::string> extra, const char* program) {
  // In this order: the options files are read for counting only once they are known to be
  // regular files of at most 1 MiB (/dev/zero was read for ever).
  auto why = bad_options_file(extra);
  if (why.empty()) why = too_many_options(extra);
  if (!why.empty()) {
    if (command_line_reporter()) fmt::print(stderr, "{}nothing was run.\n", why);
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
    // summary.json's "startup": the process until here (loader, MPI, PETSc, the options).
    const double startup = tc::core::seconds_since_process_start();
    auto field_files = tc::io::FieldFiles::vtu;
    auto problem = tc::io::read_case(case_file, overrides, field_files);
    if (!output.empty()) problem.output.directory = output;
    if (!restart.empty()) problem.output.directory = restart;  // continued where it stopped
    print_warnings(problem);
    // Held until the run returns: a second run into the same directory is refused (exit 2)
    // before it sets anything up, instead of mixing its rows with this one's.
    const auto earlier = !restart.empty() ? tc::io::EarlierRun::keep
                         : force          ? tc::io::EarlierRun::replace
                                          : tc::io::EarlierRun::refuse;
    const tc::io::OutputLock lock(problem.output.directory, restart.empty(), earlier);
    double reading = tc::core::seconds_since_process_start() - startup;
    tc::physics::Simulation sim(problem);
    if (!problem.contacts.empty()) sim.enable_mortar_contact();
    const double hashing = tc::core::seconds_since_process_start();
    const auto case_hash = tc::io::input_hash(problem);  // the case and mesh files read again
    reading += tc::core::seconds_since_process_start() - hashing;
    tc::io::OutputWriter writer(problem.output.directory, problem.output.every,
                                tc::io::OutputWriter::encoding_of(problem.output), field_files);
    if (tc::core::PetscSession::rank() == 0)  // held open until the process ends
      g_output_directory.store(
          ::open(problem.output.directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    writer.phases().add("startup", startup);
    writer.phases().add("reading", reading);
    if (!restart.empty()) {
      auto restarting = writer.phases().scope("reading");
      const auto file = tc::io::checkpoint_file(restart);
      tc::io::check_restart_outputs(restart);
      try {
        sim.restore(tc::io::read_checkpoint(file, sim, case_hash));
      } catch (const tc::io::CheckpointError&) {
        throw;
      } catch (const tc::Error& e) {  // sizes that passed the header but not the problem
        throw tc::io::CheckpointError(
            fmt::format("checkpoint {}: {}", tc::io::printable(file), e.what()));
      }
      tc::io::check_restart_history(restart, sim);  // before a row is written: exit 2
      writer.resume();
      if (tc::core::PetscSession::rank() == 0)
        fmt::print("restarting from step {} (t = {:g} s) of {}\n", sim.step(), sim.time(),
                   tc::io::printable(file));
    }
    tc::io::CheckpointWriter checkpoint(problem.output.directory, case_hash,
                                        tc::io::CheckpointPolicy::of(problem.output));
    tc::io::ProgressLine progress(isatty(STDERR_FILENO) != 0);
    StopAfter stop(stop_after);
    AgreeOnStop agree;
    writer.watch_stop(&g_stop);
    tc::io::TimedObserver timed_checkpoint(checkpoint, writer.phases(), "checkpoint");
    tc::io::TimedObserver timed_progress(progress, writer.phases(), "progress");
    tc::io::Observers observers({&writer, &timed_checkpoint, &timed_progress, &stop, &agree});
    const auto status = sim.run(observers, &g_stop_agreed);
    if (tc::core::PetscSession::rank() == 0) {
      warn_unused_options();
      if (status.completed)
        fmt::print("done: {} steps; output in {}\n", status.steps_done,
                   tc::io::printable(problem.output.directory));
      else
        fmt::print(stderr, "stopped: {}\noutput of the {} completed step(s) is in {}\n",
                   status.message, writer.steps_written(),
                   tc::io::printable(problem.output.directory));
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
  } catch (const tc::Interrupted& e) {  // mpirun passes the signal to every rank: said once
    if (input_reporter()) fmt::print(stderr, "stopped: {}\n", e.what());
    return 1;
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
  install_signal_handlers();                     // a stop signal ends a long mesh read (exit 1)
  try {
    const auto problem = tc::io::read_case(case_file, overrides);
    print_warnings(problem);
    if (tc::core::PetscSession::rank() != 0) return 0;  // every rank read it; one reports
    int nodes = 0, cells = 0;
    for (const auto& b : problem.bodies) nodes += b.mesh.n_nodes(), cells += b.mesh.n_cells();
    fmt::print("{}: valid ({}D, {} bod{}, {} nodes, {} cells, {} steps)\n", case_file,
               problem.dimension, problem.bodies.size(), problem.bodies.size() == 1 ? "y" : "ies",
               nodes, cells, problem.time.n_steps());
    const int node = tc::core::PetscSession::node_size();
    const auto each = node > 1 ? fmt::format(" on each of the {} ranks of this node", node) : "";
    // Every body's count, 1 included, and what "auto" weighed (case-format.md: `check` prints
    // what "auto" chose and why).
    for (const auto& b : problem.bodies) {
      const auto why = b.subdomains_reason.empty()
                           ? std::string()
                           : fmt::format(" ({}{})", b.subdomains_reason, each);
      if (b.subdomains > 1)
        fmt::print("  body \"{}\": {} FETI subdomains{}\n", b.name, b.subdomains, why);
      else
        fmt::print("  body \"{}\": 1 subdomain, solved directly{}\n", b.name, why);
    }
    return 0;
  } catch (const tc::InputError& e) {
    return report_input_error(e);
  } catch (const tc::MeshError& e) {
    return report_bad_input(e);
  } catch (const tc::Interrupted& e) {  // mpirun passes the signal to every rank: said once
    if (input_reporter()) fmt::print(stderr, "stopped: {}\n", e.what());
    return 1;
  }
}

/// `info`'s line on the thread policy (core/threads.hpp): one thread outside the large
/// kernels, up to the budget inside them while the CPUs are free; or the environment's number.
void print_thread_policy() {
  using tc::core::ThreadPolicy;
  const auto& cpus = ThreadPolicy::cpus();
  std::string limits =
      fmt::format("{} CPU{} in the affinity mask", cpus.affinity, cpus.affinity == 1 ? "" : "s");
  if (cpus.quota > 0) limits += fmt::format(", cgroup quota {:g} CPUs", cpus.quota);
  if (cpus.ranks_on_node > 1) limits += fmt::format(", {} ranks on this node", cpus.ranks_on_node);
  if (ThreadPolicy::from_environment())
    fmt::print(
        "BLAS threads per rank: {} everywhere (set by OPENBLAS_NUM_THREADS or OMP_NUM_THREADS)\n",
        ThreadPolicy::outside_kernels());
  else if (!ThreadPolicy::settable())
    fmt::print("BLAS threads per rank: 1 (this BLAS has no openblas_set_num_threads)\n");
  else
    fmt::print(
        "BLAS threads per rank: 1, up to {} inside large kernels while the CPUs are free ({}; "
        "OPENBLAS_NUM_THREADS fixes the number)\n",
        ThreadPolicy::budget(), limits);
}

int info(const char* program) {
  int argc = 1;
  char* args[] = {const_cast<char*>(program), nullptr};
  char** argv = args;
  tc::core::PetscSession session(&argc, &argv);
  char version[256];
  TC_PETSC(PetscGetVersion(version, sizeof version));
  if (tc::core::PetscSession::rank() != 0) return 0;  // the same on every rank: said once
  fmt::print("thermocontact {}\n", THERMOCONTACT_VERSION);
  fmt::print("PETSc: {}\n", version);
  fmt::print("MPI ranks: {}\n", tc::core::PetscSession::size());
  print_thread_policy();
  std::string packages;
  for (const auto& p : tc::linalg::available_cholesky_packages())
    packages += (packages.empty() ? "" : ", ") + p;
  fmt::print("Cholesky factorizations: {}\n", packages);
  fmt::print("CHOLMOD: {}\n", tc::linalg::cholmod_path());
  // What this build can take for a contact body's compliance (A⁻¹)_TT (linalg/compliance.hpp);
  // summary.json's "compliance" says what a run took per body.
  std::string paths;
  for (const auto& p : tc::linalg::compliance_paths()) paths += (paths.empty() ? "" : ", ") + p;
  fmt::print(
      "Compliance paths: {} (CHOLMOD's on one rank, forward solves where they cost fewer "
      "flops; MUMPS's for a factor over the ranks; FETI for a decomposed body)\n",
      paths);
  fmt::print("Gmsh: {}\n", GMSH_API_VERSION);
  fmt::print("VTKHDF output (format = \"vtkhdf\"): {}\n", tc::io::vtkhdf_library());
  return 0;
}

/// Whether a path option was given with an empty value. Such a value is refused: it was taken
/// for an absent option (`--restart ""` ran from step 0, `--output ""` wrote into the case's
/// [output].directory).
bool empty_path(const CLI::Option* option, const std::string& value, std::string_view expected) {
  if (option->count() == 0 || !value.empty()) return false;
  if (command_line_reporter())
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

/// The number of single-character edits between a and b (Levenshtein), for "did you mean".
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// An argument of `run` that looks like one of thermocontact's own options but is none. The
/// rule (case-format.md, "The command line"): thermocontact's options begin with "--", PETSc's
/// with a single '-'. So an unknown "--word" is a mistyped option of ours, refused before
/// anything runs (`--restrat DIR` ran from step 0 and `--forse` was ignored, both passed to
/// PETSc and reported only at the end; issue 42, D14), and so is one of our names with a
/// single dash (`-restart DIR`), which PETSc would have ignored the same way.
std::string unknown_long_option(const std::vector<std::string>& extra,
                                const std::vector<std::string>& known) {
  for (const auto& word : extra) {
    if (word.rfind('-', 0) != 0 || word == "-" || word == "--") continue;
    const std::string name = word.substr(0, word.find('='));
    const bool long_form = name.rfind("--", 0) == 0;
    const std::string as_long = long_form ? name : "-" + name;
    if (!long_form && std::find(known.begin(), known.end(), as_long) == known.end()) continue;
    std::string best;
    std::size_t distance = 3;  // at most two edits away: a typo, not another word
    for (const auto& k : known)
      if (const auto d = edit_distance(as_long, k); d < distance) best = k, distance = d;
    return fmt::format(
        "error: run: found the option '{}', which thermocontact does not have{}; expected one "
        "of {} (thermocontact's options begin with '--', PETSc's with a single '-'); nothing "
        "was run.\n",
        name, best.empty() ? "" : fmt::format(" (did you mean '{}'?)", best),
        fmt::join(known, ", "));
  }
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  install_signal_handlers();  // a signal during start-up too; again after PetscInitialize
  if (const auto why = address_space_shortfall(); !why.empty()) {
    if (command_line_reporter()) fmt::print(stderr, "{}", why);
    // The environment, not the input: exit 1. Without exit handlers: OpenBLAS's joins its
    // threads, which may be stuck mapping their buffers under the limit (it hung there).
    std::fflush(nullptr);
    std::_Exit(1);
  }
  CLI::App app{"thermocontact: dynamic thermo-mechanical contact with Coulomb friction"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "thermocontact " THERMOCONTACT_VERSION);
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
  auto* stability_cmd =
      app.add_subcommand("stability",
                         "linear stability of the case's steady sliding: growth rates, modes, the "
                         "critical speed ([stability])");
  stability_cmd->add_option("case", case_file, "case file (TOML)")->required();
  std::string stability_output;
  auto* stability_output_opt = stability_cmd->add_option(
      "--output", stability_output, "output directory (overrides [output].directory)");
  stability_cmd->add_option("--set", overrides, set_help)->allow_extra_args(false);
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
  const bool reporter = command_line_reporter();
  if (const auto message = unknown_subcommand(app, argc, argv); !message.empty()) {
    if (reporter) fmt::print(stderr, "{}", message);
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::ostream none(nullptr);  // the other ranks of an MPI launch say nothing
    return app.exit(e, reporter ? std::cout : none, reporter ? std::cerr : none) == 0 ? 0 : 2;
  }
  if (empty_path(output_opt, output, "an output directory (or no --output: [output].directory)") ||
      empty_path(stability_output_opt, stability_output,
                 "an output directory (or no --output: [output].directory)") ||
      empty_path(restart_opt, restart, "the output directory of the run to continue"))
    return 2;
  if (const auto why =
          unknown_long_option(run_cmd->remaining(), {"--output", "--restart", "--force", "--help"});
      !why.empty()) {
    if (reporter) fmt::print(stderr, "{}", why);
    return 2;
  }
  if (const auto extra = stray_argument(run_cmd->remaining()); !extra.empty()) {
    if (reporter)
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
    if (stability_cmd->parsed())
      return stability_command(case_file, overrides, stability_output, argv[0]);
    return info(argv[0]);
  } catch (const std::bad_alloc&) {
    rlimit limit{};
    const bool limited = getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY;
    fmt::print(stderr, "stopped: out of memory{}\n",
               limited ? fmt::format(" under the address-space limit (ulimit -v) of {} kB",
                                     limit.rlim_cur / 1024)
                       : "");
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
}
