#pragma once
// The BLAS (and OpenMP) thread policy (issue 39, docs/choices.md "BLAS threads only inside
// large kernels"). OpenBLAS's threads spin while they wait: with one thread per CPU and the
// CPUs not all free, every small dense product waits for a descheduled thread (5–17× slower
// runs beside a build). So a rank runs its BLAS on one thread, and only a large kernel — a
// factorisation, the compliance columns that form the explicit dual F, F's bands, the QP's
// products with a large explicit F — asks for more, through KernelThreads: it gets at most
// the CPUs this rank may use (affinity, cgroup quota, shared with the ranks on its node), and
// only as many as other processes left free since the last look (/proc/stat). A user's
// OPENBLAS_NUM_THREADS (or OMP_NUM_THREADS) fixes the number everywhere instead.
//
// Not thread-safe: kernels are entered from the rank's main thread.
#include <string>

namespace tc::core {

/// The CPUs a rank may use: its affinity mask, the cgroup's CPU quota, shared by the ranks of
/// its node (at least one).
struct CpuBudget {
  int affinity = 1;       // CPUs in sched_getaffinity's mask
  double quota = 0;       // the cgroup's cpu.max (v2) or cfs quota/period (v1), in CPUs; 0: none
  int ranks_on_node = 1;  // MPI_Comm_split_type(SHARED)
  [[nodiscard]] int per_rank() const;
};

/// The quota of a cgroup v2 cpu.max ("max 100000" → 0, "150000 100000" → 1.5), or of v1's
/// cpu.cfs_quota_us and cpu.cfs_period_us ("-1" → 0); 0 when unlimited or unreadable.
[[nodiscard]] double parse_cpu_max(const std::string& text);
[[nodiscard]] double parse_cfs_quota(const std::string& quota, const std::string& period);

/// How many threads a large kernel gets: `free_cpus` (the CPUs of the budget that other
/// processes left idle, fractional), rounded to the nearest, between 1 and `budget`.
[[nodiscard]] int threads_for(int budget, double free_cpus);

/// What to tell a user whose MPI ranks share their CPUs with other work, or "": `ranks_on_node`
/// ranks on `cpus` CPUs with the machine's load average `others` before they started. Ranks
/// wait for each other at every collective, so a rank descheduled by another process holds
/// up all of them (a 2-rank run on the busy 2-CPU VM took 6.5 min against 18 s on one rank:
/// docs/robustness.md). Said when the ranks and that load need a CPU more than there are.
[[nodiscard]] std::string oversubscription_warning(double others, int ranks_on_node, int cpus);

/// The rank's thread policy; started by PetscSession.
class ThreadPolicy {
 public:
  /// Reads the budget, sets BLAS and OpenMP to one thread (or to the environment's number)
  /// and takes the first sample of the CPUs' use. With more than one rank in the run
  /// (`ranks`), a large kernel gets the budget without looking at the load: the ranks compute
  /// replicated values that must agree to the bit, and the threads change the bits, so every
  /// rank must choose alike, without a collective call (kernels are not all collective).
  static void start(int ranks_on_node, int ranks = 1);
  /// Threads outside large kernels: 1, or OPENBLAS_NUM_THREADS / OMP_NUM_THREADS.
  [[nodiscard]] static int outside_kernels();
  /// The most a kernel may use (the budget per rank; the environment's number when it is set).
  [[nodiscard]] static int budget();
  [[nodiscard]] static const CpuBudget& cpus();
  /// Whether OPENBLAS_NUM_THREADS or OMP_NUM_THREADS fixed the number.
  [[nodiscard]] static bool from_environment();
  /// Whether openblas_set_num_threads was found (another BLAS: one thread, as it was built).
  [[nodiscard]] static bool settable();
  /// Large kernels so far, those that ran on more than one thread, and the most threads any had.
  [[nodiscard]] static long kernels();
  [[nodiscard]] static long threaded_kernels();
  [[nodiscard]] static int most_threads();
  /// "auto", "environment" or "fixed" (no settable BLAS).
  [[nodiscard]] static std::string name();
};

/// A kernel that may use more than one thread: for its lifetime BLAS and OpenMP run on
/// threads() threads, chosen by the policy when `flops` (the kernel's estimated work) reaches
/// kParallelFlops, 1 otherwise; back to ThreadPolicy::outside_kernels() at the end.
class KernelThreads {
 public:
  /// Work below which one thread is kept: about 0.1 s on one core of the 2-core VM at the
  /// level-3 rate (bench/threads), where waking and joining threads no longer shows.
  static constexpr double kParallelFlops = 2e8;
  explicit KernelThreads(double flops);
  ~KernelThreads();
  KernelThreads(const KernelThreads&) = delete;
  KernelThreads& operator=(const KernelThreads&) = delete;
  [[nodiscard]] int threads() const { return threads_; }

 private:
  int threads_ = 1;
};

}  // namespace tc::core
