#include "tc/core/numeric/threads.hpp"

#include <dlfcn.h>
#include <fmt/format.h>
#include <sched.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

namespace tc::core {

int CpuBudget::per_rank() const {
  double cpus = affinity;
  if (quota > 0) cpus = std::min(cpus, std::ceil(quota - 1e-9));
  return std::max(1, static_cast<int>(cpus) / std::max(1, ranks_on_node));
}

double parse_cpu_max(const std::string& text) {
  std::istringstream in(text);
  std::string quota;
  double period = 0;
  if (!(in >> quota >> period) || quota == "max" || period <= 0) return 0;
  char* end = nullptr;
  const double q = std::strtod(quota.c_str(), &end);
  return end != quota.c_str() && q > 0 ? q / period : 0;
}

double parse_cfs_quota(const std::string& quota, const std::string& period) {
  const double q = std::atof(quota.c_str()), p = std::atof(period.c_str());
  return q > 0 && p > 0 ? q / p : 0;
}

int threads_for(int budget, double free_cpus) {
  return std::clamp(static_cast<int>(std::lround(free_cpus)), 1, std::max(1, budget));
}

namespace {

using SetThreads = void (*)(int);

std::string read_text(const std::string& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The cgroup directory of this process for `controller` ("" for v2's unified line).
std::string cgroup_path(const std::string& controller) {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    const auto a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const auto names = line.substr(a + 1, b - a - 1);
    std::istringstream list(names);
    std::string name;
    bool match = controller.empty() && names.empty();
    while (!match && std::getline(list, name, ',')) match = name == controller;
    if (match) return line.substr(b + 1);
  }
  return {};
}

/// The CPU quota of this process's cgroup (v2 cpu.max, else v1 cfs), in CPUs; 0 when none.
/// A container sees its own cgroup as the root of the mount, a host process its full path:
/// both are tried.
double cgroup_quota() {
  for (const auto& dir : {cgroup_path(""), std::string()}) {
    const double q = parse_cpu_max(read_text("/sys/fs/cgroup" + dir + "/cpu.max"));
    if (q > 0) return q;
  }
  for (const char* mount : {"/sys/fs/cgroup/cpu", "/sys/fs/cgroup/cpu,cpuacct"})
    for (const auto& dir : {cgroup_path("cpu"), std::string()}) {
      const std::string base = std::string(mount) + dir;
      const double q = parse_cfs_quota(read_text(base + "/cpu.cfs_quota_us"),
                                       read_text(base + "/cpu.cfs_period_us"));
      if (q > 0) return q;
    }
  return 0;
}

/// The busy time of the allowed CPUs (/proc/stat, all but idle and iowait), this process's
/// CPU time (all its threads) and the wall clock, at one moment.
struct CpuSample {
  double busy = 0;  // seconds, summed over the allowed CPUs
  double own = 0;   // seconds
  double wall = 0;  // seconds
  bool valid = false;
};

CpuSample sample_cpus(const cpu_set_t& allowed) {
  CpuSample s;
  s.wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  timespec t{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) == 0) s.own = t.tv_sec + 1e-9 * t.tv_nsec;
  std::ifstream in("/proc/stat");
  const double tick = static_cast<double>(sysconf(_SC_CLK_TCK));
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("cpu", 0) != 0 || line.size() < 4 || line[3] < '0' || line[3] > '9') continue;
    std::istringstream f(line.substr(3));
    int cpu = -1;
    unsigned long long v[8] = {};
    f >> cpu;
    for (auto& x : v) f >> x;  // user nice system idle iowait irq softirq steal
    if (cpu < 0 || cpu >= CPU_SETSIZE || !CPU_ISSET(cpu, &allowed)) continue;
    const unsigned long long busy = v[0] + v[1] + v[2] + v[5] + v[6] + v[7];
    s.busy += static_cast<double>(busy) / (tick > 0 ? tick : 100.0);
    s.valid = true;
  }
  return s;
}

struct State {
  CpuBudget cpus;
  cpu_set_t allowed{};
  int outside = 1;
  int budget = 1;
  bool environment = false;
  SetThreads blas = nullptr;
  SetThreads omp = nullptr;
  CpuSample last;   // the start of the current measuring window
  int decided = 0;  // the last decision (0: none yet)
  long kernels = 0, threaded = 0;
  int most = 1;
  int depth = 0;        // nested kernels keep the outer one's threads
  int current = 1;      // the threads in effect
  bool by_load = true;  // one rank: the free CPUs decide; more: the budget (see start)
};

State& state() {
  static State s;
  return s;
}

void set_threads(int n) {
  auto& s = state();
  s.current = n;
  if (s.blas) s.blas(n);
  if (s.omp) s.omp(n);
}

/// The CPUs of the budget that other processes left idle since the window began. Windows
/// shorter than a tenth of a second are too coarse for /proc/stat's ticks (1/100 s per CPU):
/// the last decision stands, and the first waits the rest of that tenth.
int decide() {
  auto& s = state();
  constexpr double window = 0.1;
  auto now = sample_cpus(s.allowed);
  if (!now.valid || !s.last.valid) return s.budget;  // no /proc/stat: trust the budget
  if (now.wall - s.last.wall < window) {
    if (s.decided > 0) return s.decided;
    std::this_thread::sleep_for(std::chrono::duration<double>(window - (now.wall - s.last.wall)));
    now = sample_cpus(s.allowed);
  }
  const double span = now.wall - s.last.wall;
  const double others = std::max(0.0, (now.busy - s.last.busy) - (now.own - s.last.own)) / span;
  const double free = std::min<double>(s.cpus.per_rank(), CPU_COUNT(&s.allowed) - others);
  s.last = now;
  s.decided = threads_for(s.budget, free);
  return s.decided;
}

}  // namespace

std::string oversubscription_warning(double others, int ranks_on_node, int cpus) {
  if (ranks_on_node <= 1 || others + ranks_on_node <= cpus + 1.0) return "";
  return fmt::format(
      "{} MPI ranks on {} CPU{} that other work already uses (load average {:.1f}): the ranks "
      "wait for each other at every collective, so one descheduled rank holds up all; fewer "
      "ranks, or one, may be many times faster here (docs/robustness.md, \"A busy machine\")",
      ranks_on_node, cpus, cpus == 1 ? "" : "s", others);
}

void ThreadPolicy::start(int ranks_on_node, int ranks) {
  auto& s = state();
  CPU_ZERO(&s.allowed);
  if (sched_getaffinity(0, sizeof s.allowed, &s.allowed) != 0) CPU_SET(0, &s.allowed);
  s.cpus.affinity = std::max(1, CPU_COUNT(&s.allowed));
  s.cpus.quota = cgroup_quota();
  s.cpus.ranks_on_node = std::max(1, ranks_on_node);
  s.by_load = ranks <= 1;
  s.blas = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  s.omp = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "omp_set_num_threads"));
  int n = 0;
  for (const char* name : {"OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"})
    if (const char* v = std::getenv(name); v && n <= 0) n = std::atoi(v);
  s.environment = n > 0;
  s.outside = s.environment ? n : 1;
  s.budget = s.environment ? n : s.blas ? s.cpus.per_rank() : 1;
  // OpenBLAS sized its pool from the environment when it was loaded, and OpenMP's default is
  // every CPU: both told the number explicitly.
  set_threads(s.outside);
  s.most = s.outside;
  s.last = sample_cpus(s.allowed);
  s.decided = 0;
}

int ThreadPolicy::outside_kernels() {
  return state().outside;
}
int ThreadPolicy::budget() {
  return state().budget;
}
const CpuBudget& ThreadPolicy::cpus() {
  return state().cpus;
}
bool ThreadPolicy::from_environment() {
  return state().environment;
}
bool ThreadPolicy::settable() {
  return state().blas != nullptr;
}
long ThreadPolicy::kernels() {
  return state().kernels;
}
long ThreadPolicy::threaded_kernels() {
  return state().threaded;
}
int ThreadPolicy::most_threads() {
  return state().most;
}
std::string ThreadPolicy::name() {
  const auto& s = state();
  return s.environment ? "environment" : s.blas ? "auto" : "fixed";
}

KernelThreads::KernelThreads(double flops) {
  auto& s = state();
  threads_ = s.current;
  if (s.depth++ > 0 || flops < kParallelFlops) return;
  ++s.kernels;
  if (!s.environment && s.budget > 1) threads_ = s.by_load ? decide() : s.budget;
  if (threads_ > 1) ++s.threaded;
  s.most = std::max(s.most, threads_);
  if (threads_ != s.outside) set_threads(threads_);
}

KernelThreads::~KernelThreads() {
  auto& s = state();
  if (--s.depth == 0 && s.current != s.outside) set_threads(s.outside);
}

}  // namespace tc::core
