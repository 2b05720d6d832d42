#include "tc/physics/history.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "tc/core/error.hpp"

namespace tc::physics {

void History::add(std::string column, Value value) {
  columns_.push_back(std::move(column));
  values_.push_back(std::move(value));
}

void History::record() {
  row_.clear();
  row_.reserve(values_.size());
  for (const auto& value : values_) row_.push_back(value());
}

void History::restore(std::vector<double> row) {
  if (row.size() != columns_.size())
    throw Error(fmt::format("checkpoint: {} history columns, this problem {}", row.size(),
                            columns_.size()));
  row_ = std::move(row);
}

double History::operator[](const std::string& column) const {
  const auto it = std::find(columns_.begin(), columns_.end(), column);
  if (it == columns_.end()) throw Error("no history column named '" + column + "'");
  return row_[it - columns_.begin()];
}

}  // namespace tc::physics
