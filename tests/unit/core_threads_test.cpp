// The BLAS thread policy (core/numeric/threads.hpp) and the checkpoint policy
// (io/restart/checkpoint.hpp): the budget from the affinity mask, the cgroup quota and the ranks of
// a node; the threads a large kernel gets from the CPUs other processes left free; when a
// checkpoint is due.
#include <gtest/gtest.h>

#include "tc/core/numeric/threads.hpp"
#include "tc/io/restart/checkpoint.hpp"

using namespace tc;

TEST(CpuBudget, CgroupQuotasAreReadInCpus) {
  EXPECT_EQ(core::parse_cpu_max("max 100000\n"), 0.0);  // v2, unlimited
  EXPECT_EQ(core::parse_cpu_max("150000 100000\n"), 1.5);
  EXPECT_EQ(core::parse_cpu_max(""), 0.0);                    // no such file
  EXPECT_EQ(core::parse_cfs_quota("-1\n", "100000\n"), 0.0);  // v1, unlimited
  EXPECT_EQ(core::parse_cfs_quota("200000\n", "100000\n"), 2.0);
  EXPECT_EQ(core::parse_cfs_quota("", ""), 0.0);
}

TEST(CpuBudget, IsTheSmallerOfAffinityAndQuotaOverTheRanksOfTheNode) {
  EXPECT_EQ((core::CpuBudget{8, 0.0, 1}).per_rank(), 8);
  EXPECT_EQ((core::CpuBudget{8, 2.5, 1}).per_rank(), 3);  // a part of a CPU is a thread's share
  EXPECT_EQ((core::CpuBudget{8, 2.0, 1}).per_rank(), 2);
  EXPECT_EQ((core::CpuBudget{8, 0.0, 4}).per_rank(), 2);
  EXPECT_EQ((core::CpuBudget{2, 0.0, 4}).per_rank(), 1);  // never none
  EXPECT_EQ((core::CpuBudget{1, 0.0, 1}).per_rank(), 1);
}

TEST(KernelThreads, GetTheFreeCpusWithinTheBudget) {
  EXPECT_EQ(core::threads_for(2, 2.0), 2);  // an idle 2-CPU machine
  EXPECT_EQ(core::threads_for(2, 1.7), 2);
  EXPECT_EQ(core::threads_for(2, 1.2), 1);   // one CPU busy elsewhere
  EXPECT_EQ(core::threads_for(2, 0.0), 1);   // both busy: never fewer than one
  EXPECT_EQ(core::threads_for(4, 10.0), 4);  // never more than the budget
  EXPECT_EQ(core::threads_for(1, 2.0), 1);
}

TEST(KernelThreads, ASmallKernelKeepsOneThreadAndTheScopeRestoresIt) {
  // The test runner sets OPENBLAS_NUM_THREADS=1 (tests/support/main.cpp): the environment's
  // number everywhere, whatever the kernel's size.
  const int outside = core::ThreadPolicy::outside_kernels();
  {
    const core::KernelThreads small(1.0);
    EXPECT_EQ(small.threads(), outside);
  }
  {
    const core::KernelThreads large(1e12);
    EXPECT_GE(large.threads(), 1);
    EXPECT_LE(large.threads(), core::ThreadPolicy::budget());
  }
  const core::KernelThreads after(1.0);
  EXPECT_EQ(after.threads(), outside);
}

TEST(Oversubscription, IsSaidWhenRanksAndOtherWorkNeedACpuMoreThanThereAre) {
  // One rank is never held up by a partner; 2 ranks on the 2-CPU VM beside a build (load
  // ≥ 1) are (the 20× of docs/robustness.md), beside background noise (0.3) not.
  EXPECT_EQ(tc::core::oversubscription_warning(12.0, 1, 2), "");
  EXPECT_EQ(tc::core::oversubscription_warning(0.3, 2, 2), "");
  EXPECT_EQ(tc::core::oversubscription_warning(1.0, 2, 2), "");  // exactly one CPU more: not yet
  const auto w = tc::core::oversubscription_warning(2.2, 2, 2);
  EXPECT_NE(w.find("2 MPI ranks on 2 CPUs"), std::string::npos) << w;
  EXPECT_NE(w.find("load average 2.2"), std::string::npos) << w;
  EXPECT_EQ(tc::core::oversubscription_warning(2.5, 4, 64), "");  // a cluster node's daemons
  EXPECT_NE(tc::core::oversubscription_warning(2.5, 64, 64), "");
}

TEST(CheckpointPolicy, DueByStepsOrWallTimeNeverBelowFiftyTimesItsCost) {
  const io::CheckpointPolicy by_steps{4, 0.0};
  EXPECT_FALSE(by_steps.due(3, 1e6, 0.0));
  EXPECT_TRUE(by_steps.due(4, 0.0, 0.0));
  const io::CheckpointPolicy by_time{0, 10.0};
  EXPECT_FALSE(by_time.due(1000, 9.9, 0.01));
  EXPECT_TRUE(by_time.due(1, 10.0, 0.01));
  EXPECT_FALSE(by_time.due(1, 10.0, 0.5));  // a 0.5 s checkpoint: every 25 s at the most
  EXPECT_TRUE(by_time.due(1, 25.0, 0.5));
  const io::CheckpointPolicy never{0, 0.0};  // only at the start, a stop and the end
  EXPECT_FALSE(never.due(1000000, 1e9, 0.0));
  const io::CheckpointPolicy every_step{1, 0.0};
  EXPECT_TRUE(every_step.due(1, 0.0, 1.0));
}
