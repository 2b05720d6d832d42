#pragma once
// history.csv: one row per step, one column per quantity. Each column is registered with the
// name it has in the file and the function that reads its value from the component owning it
// (docs/case-format.md lists them), so a column's name and value are written in one place
// and never matched by position.
#include <functional>
#include <string>
#include <vector>

namespace tc::physics {

class History {
 public:
  using Value = std::function<double()>;

  /// Appends a column; its value is read by `value` at every record().
  void add(std::string column, Value value);
  /// The row of the current state: every column's value, in the order they were added.
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
  std::vector<Value> values_;
  std::vector<double> row_;
};

}  // namespace tc::physics
