#pragma once
// history.csv: one row per step, one column per quantity. Each component registers the columns
// it owns (register_history: Simulation, EnergyBalance, ContactCoupling with its statistics and
// heat, BoundaryHeat), each with the name it has in the file and the function that reads its
// value, so a column's name and value are written in one place and never matched by position.
// The order of the columns is the file's contract (docs/case-format.md) and is kept here, apart
// from who registers them: the standard columns in their order, then the others (the support
// reactions) in the order they were added.
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace tc::physics {

class History {
 public:
  using Value = std::function<double()>;

  /// The columns every history.csv opens with, in their order (docs/case-format.md).
  [[nodiscard]] static std::span<const char* const> standard_columns();
  /// The columns each contact pair has with two or more pairs, as <column>_<pair name>
  /// (ContactStatistics::register_pair_history, ContactHeat::register_history,
  /// ContactCoupling::register_history); the case
  /// reader refuses pair names that make two of them one.
  [[nodiscard]] static std::span<const char* const> pair_columns();

  History();

  /// The column value of a counter or a number kept by a component that outlives the history.
  [[nodiscard]] static Value value_of(const int& n) {
    return [&n] { return static_cast<double>(n); };
  }
  [[nodiscard]] static Value value_of(const double& x) {
    return [&x] { return x; };
  }

  /// Registers a column: a standard one takes its place in the order, any other follows them;
  /// Error when a column of that name was registered before (a reader by name would read the
  /// wrong series: the case reader refuses the names that lead here).
  void add(const std::string& column, Value value);
  /// The row of the current state: every column's value, in the order of columns(). Throws
  /// Error when a standard column has not been registered.
  void record();
  /// Replaces the row (restart: the row of the checkpoint's step); throws Error when its
  /// length is not the number of columns.
  void restore(std::vector<double> row);

  [[nodiscard]] const std::vector<std::string>& columns() const { return columns_; }
  [[nodiscard]] const std::vector<double>& row() const { return row_; }
  /// The value of `column` in the row; throws Error for an unknown name.
  [[nodiscard]] double operator[](const std::string& column) const;

 private:
  std::vector<std::string> columns_;
  std::vector<Value> values_;  // empty while a standard column waits for its component
  std::vector<double> row_;
};

}  // namespace tc::physics
