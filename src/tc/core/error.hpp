#pragma once
// Typed exceptions of thermocontact (docs/architecture.md, "Errors").
// Input errors carry the place in the user's file; numerical failures carry the
// step, iteration and residual so the time loop and the user can act on them.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace tc {

/// Base of every error the solver reports to its user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One problem found in a case file: `FILE:LINE: KEY: what was found, what was expected`.
struct InputIssue {
  std::string file;
  int line = 0;  // 0 when the key is absent (then the line of its table is used if known);
                 // < 0 for an issue of a command-line --set (file: "--set KEY=VALUE")
  std::string key;
  std::string message;
  [[nodiscard]] std::string str() const;
};

/// All problems of one case file, reported together (exit code 2).
class InputError : public Error {
 public:
  explicit InputError(std::vector<InputIssue> issues);
  [[nodiscard]] const std::vector<InputIssue>& issues() const { return issues_; }

 private:
  std::vector<InputIssue> issues_;
};

/// A mesh that cannot be used: unsupported element, inverted cell, missing group.
class MeshError : public Error {
 public:
  using Error::Error;
};

/// A PETSc call that failed; the message names the call and PETSc's own text.
class PetscError : public Error {
 public:
  PetscError(int code, const std::string& what) : Error(what), code_(code) {}
  [[nodiscard]] int code() const { return code_; }

 private:
  int code_;
};

/// A numerical failure of the run (no convergence, NaN): exit code 1.
class NumericalError : public Error {
 public:
  NumericalError(const std::string& what, int step, int iteration, double residual);
  /// The same error with `what` already formatted (a copy received from another rank).
  [[nodiscard]] static NumericalError preformatted(const std::string& what, int step, int iteration,
                                                   double residual);
  [[nodiscard]] int step() const { return step_; }
  [[nodiscard]] int iteration() const { return iteration_; }
  [[nodiscard]] double residual() const { return residual_; }
  /// The same error with the step it happened in, for a thrower that cannot know it (FETI, a
  /// QP: step < 0, shown as "step ?"): `step` ≥ 1 names a time step, 0 the set-up before step
  /// 1. An error that knows its step is returned unchanged.
  [[nodiscard]] NumericalError at_step(int step) const;

 private:
  struct Preformatted {};
  NumericalError(Preformatted, const std::string& what, int step, int iteration, double residual)
      : Error(what), step_(step), iteration_(iteration), residual_(residual) {}
  int step_, iteration_;
  double residual_;
};

/// The process was asked to stop (a stop signal, core/stop.hpp) during work that cannot finish
/// a step first, such as reading a mesh: exit code 1, like a run stopped by a signal.
class Interrupted : public Error {
 public:
  using Error::Error;
};

/// A file of the run's output that could not be written (a full disk, a file-size limit, an
/// I/O error): the run stops as after a numerical failure, exit code 1, and the steps already
/// written stay readable.
class OutputError : public Error {
 public:
  using Error::Error;
};

/// Marks an error that every rank threw together (core/numeric/collective.hpp): reported once, on
/// rank 0, where an error of one rank alone is reported by that rank.
class Collective {
 public:
  virtual ~Collective() = default;
};

/// An error of type E thrown by every rank (the type keeps the exit code).
template <class E>
class CollectiveError : public E, public Collective {
 public:
  explicit CollectiveError(E e) : E(std::move(e)) {}
};

/// Throws e.at_step(step), a CollectiveError if e was one (so that it is still reported once).
[[noreturn]] void rethrow_at_step(const NumericalError& e, int step);

/// Whether this rank reports `e` to the user: rank 0 for a collective error, else every rank
/// that has it.
[[nodiscard]] bool reported_here(const std::exception& e, int rank);

}  // namespace tc
