#pragma once
// Collective errors (issue 8): a failure on one rank must stop every rank, with the rank named,
// never leave the others waiting in the next MPI_Allreduce. A rank-local phase (a subdomain's
// assembly or factorisation, a rank's output piece) runs inside collective_check: every rank
// catches its own exception, the ranks agree on the lowest failing one, and every rank throws
// the same error, "rank r: <phase>: <message>", of the same type (so the exit code is the
// same), marked Collective so that the app reports it once, on rank 0.
#include <mpi.h>

#include <functional>
#include <string>

namespace tc::core {

/// Runs the rank-local `phase` on every rank of `comm` and throws on every rank if it threw on
/// any. `phase` must not itself call collectives on `comm` (a rank that threw would leave the
/// others in them). Collective on `comm`; with one rank it only calls `phase`.
void collective_check(MPI_Comm comm, const char* what, const std::function<void()>& phase);

/// Throws tc::Error "<call> failed" unless `rc` is MPI_SUCCESS.
void check_mpi(int rc, const char* call);

/// data[0 … n) ← its sum over the ranks of `comm` (in place; nothing to do on one rank).
/// `who` names the caller in the error thrown if MPI fails.
void sum_over_ranks(MPI_Comm comm, double* data, long n, const char* who);

/// Test-only fault injection (docs/robustness.md): true on the rank given by the PETSc option
/// -tc_fail_on_rank when -tc_fail_phase (default "factorisation") is `phase`. Lets the tests
/// make one rank fail in a chosen phase and check that all stop.
[[nodiscard]] bool injected_failure(const char* phase);

}  // namespace tc::core
