#include "tc/core/numeric/collective.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"

namespace tc::core {

namespace {

/// The exception types the ranks agree on; the type decides the exit code (case-format.md).
enum Kind : int { other = 0, numerical, petsc, mesh, generic, output };

// MPI failures of the check itself name it.
void check_mpi_of_check(int rc, const char* call) {
  if (rc != MPI_SUCCESS) check_mpi(rc, fmt::format("collective error check: {}", call).c_str());
}

}  // namespace

void check_mpi(int rc, const char* call) {
  if (rc != MPI_SUCCESS) throw Error(fmt::format("{} failed", call));
}

void sum_over_ranks(MPI_Comm comm, double* data, long n, const char* who) {
  int size = 1;
  if (MPI_Comm_size(comm, &size) != MPI_SUCCESS)
    throw Error(fmt::format("{}: MPI_Comm_size failed", who));
  if (size == 1) return;
  // In pieces of 8 MB: MPI's own buffers for a large sum would be as large as the data (an
  // explicit F of 3 000 rows is 72 MB), and a count must fit an int.
  constexpr long piece = 1L << 20;
  for (long at = 0; at < n; at += piece)
    if (MPI_Allreduce(MPI_IN_PLACE, data + at, static_cast<int>(std::min(piece, n - at)),
                      MPI_DOUBLE, MPI_SUM, comm) != MPI_SUCCESS)
      throw Error(fmt::format("{}: MPI_Allreduce failed", who));
}

void collective_check(MPI_Comm comm, const char* what, const std::function<void()>& phase) {
  int size = 1, rank = 0;
  check_mpi_of_check(MPI_Comm_size(comm, &size), "MPI_Comm_size");
  if (size == 1) {
    phase();
    return;
  }
  check_mpi_of_check(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
  int kind = other;
  std::string message;
  double numbers[4] = {0, 0, 0, 0};  // step, iteration, residual (numerical); PETSc code
  bool failed = true;
  bool already_collective = false;  // nested checks: the inner one has named the rank
  try {
    phase();
    failed = false;
  } catch (const NumericalError& e) {
    kind = numerical, message = e.what();
    numbers[0] = e.step(), numbers[1] = e.iteration(), numbers[2] = e.residual();
    already_collective = dynamic_cast<const Collective*>(&e) != nullptr;
  } catch (const PetscError& e) {
    kind = petsc, message = e.what(), numbers[3] = e.code();
    already_collective = dynamic_cast<const Collective*>(&e) != nullptr;
  } catch (const MeshError& e) {
    kind = mesh, message = e.what();
    already_collective = dynamic_cast<const Collective*>(&e) != nullptr;
  } catch (const OutputError& e) {
    kind = output, message = e.what();
    already_collective = dynamic_cast<const Collective*>(&e) != nullptr;
  } catch (const Error& e) {
    kind = generic, message = e.what();
    already_collective = dynamic_cast<const Collective*>(&e) != nullptr;
  } catch (const std::exception& e) {
    kind = other, message = e.what();
  } catch (...) {  // anything else must not leave this rank alone either
    kind = other, message = "unknown exception";
  }
  // The lowest failing rank (INT_MAX if none): one integer, the only cost when all went well.
  int first = failed ? rank : INT_MAX;
  check_mpi_of_check(MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm),
                     "MPI_Allreduce");
  if (first == INT_MAX) return;
  // Its type, numbers and message to every rank.
  int header[3] = {kind, static_cast<int>(message.size()), already_collective ? 1 : 0};
  check_mpi_of_check(MPI_Bcast(header, 3, MPI_INT, first, comm), "MPI_Bcast");
  check_mpi_of_check(MPI_Bcast(numbers, 4, MPI_DOUBLE, first, comm), "MPI_Bcast");
  std::vector<char> text(static_cast<size_t>(header[1]) + 1, '\0');
  if (rank == first) std::memcpy(text.data(), message.data(), message.size());
  check_mpi_of_check(MPI_Bcast(text.data(), header[1], MPI_CHAR, first, comm), "MPI_Bcast");
  const std::string named = header[2] != 0
                                ? std::string(text.data())
                                : fmt::format("rank {}: {}: {}", first, what, text.data());
  switch (header[0]) {
    case numerical:
      throw CollectiveError<NumericalError>(NumericalError::preformatted(
          named, static_cast<int>(numbers[0]), static_cast<int>(numbers[1]), numbers[2]));
    case petsc:
      throw CollectiveError<PetscError>(PetscError(static_cast<int>(numbers[3]), named));
    case mesh:
      throw CollectiveError<MeshError>(MeshError(named));
    case output:
      throw CollectiveError<OutputError>(OutputError(named));
    case generic:  // InputError too: cases are read on every rank, never in a rank-local phase
    case other:
    default:
      throw CollectiveError<Error>(Error(named));
  }
}

bool injected_failure(const char* phase) {
  PetscInt rank = -1;
  PetscBool set = PETSC_FALSE;
  TC_PETSC(PetscOptionsGetInt(nullptr, nullptr, "-tc_fail_on_rank", &rank, &set));
  if (!set || rank != PetscSession::rank()) return false;
  char wanted[64] = "factorisation";
  TC_PETSC(PetscOptionsGetString(nullptr, nullptr, "-tc_fail_phase", wanted, sizeof wanted, &set));
  return std::strcmp(wanted, phase) == 0;
}

}  // namespace tc::core
