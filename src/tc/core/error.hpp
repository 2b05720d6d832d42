#pragma once
// Typed exceptions of thermocontact (docs/architecture.md, "Errors").
// Input errors carry the place in the user's file; numerical failures carry the
// step, iteration and residual so the time loop and the user can act on them.
#include <stdexcept>
#include <string>
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
  int line = 0;  // 0 when the key is absent (then the line of its table is used if known)
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
  [[nodiscard]] int step() const { return step_; }
  [[nodiscard]] int iteration() const { return iteration_; }
  [[nodiscard]] double residual() const { return residual_; }

 private:
  int step_, iteration_;
  double residual_;
};

}  // namespace tc
