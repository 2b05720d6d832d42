#include "tc/record/history.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "tc/core/error.hpp"

namespace tc::physics {

namespace {

// The columns of docs/case-format.md ("What a run leaves in the output directory") in the
// file's order, which is part of the format; each with the component that registers it.
constexpr std::array<const char*, 25> kStandardColumns = {
    "step",                          // Simulation
    "time",                          // Simulation
    "coupling_iterations",           // Simulation
    "qp_iterations",                 // ContactStatistics
    "operator_applications",         // ContactStatistics
    "kinetic_energy",                // EnergyBalance
    "strain_energy",                 // EnergyBalance
    "thermal_energy",                // EnergyBalance
    "external_work",                 // EnergyBalance
    "contact_normal_force",          // ContactStatistics
    "contact_tangential_force",      // ContactStatistics
    "frictional_dissipation",        // ContactStatistics
    "heat_generated",                // ContactHeat
    "heat_to_slave",                 // ContactHeat
    "heat_to_master",                // ContactHeat
    "heat_conducted",                // ContactHeat
    "max_temperature",               // EnergyBalance
    "min_temperature",               // EnergyBalance
    "active_nodes",                  // ContactStatistics
    "slip_nodes",                    // ContactStatistics
    "wall_seconds",                  // Simulation
    "friction_iterations",           // ContactStatistics
    "contact_tangential_force_sum",  // ContactStatistics
    "heat_film",                     // BoundaryHeat
    "heat_radiation",                // BoundaryHeat
};

// (contact_force_z only in 3D: listed so that the case reader's check covers it.)
constexpr std::array<const char*, 13> kPairColumns = {"contact_normal_force",
                                                      "contact_tangential_force",
                                                      "frictional_dissipation",
                                                      "active_nodes",
                                                      "slip_nodes",
                                                      "contact_tangential_force_sum",
                                                      "heat_generated",
                                                      "heat_to_slave",
                                                      "heat_to_master",
                                                      "heat_conducted",
                                                      "contact_force_x",
                                                      "contact_force_y",
                                                      "contact_force_z"};

}  // namespace

std::span<const char* const> History::standard_columns() {
  return kStandardColumns;
}

std::span<const char* const> History::pair_columns() {
  return kPairColumns;
}

History::History()
    : columns_(kStandardColumns.begin(), kStandardColumns.end()), values_(columns_.size()) {}

void History::add(const std::string& column, Value value) {
  const auto standard = std::find(kStandardColumns.begin(), kStandardColumns.end(), column);
  if (standard == kStandardColumns.end()) {
    if (std::find(columns_.begin(), columns_.end(), column) != columns_.end())
      throw Error("history column '" + column + "' registered twice");
    columns_.push_back(column);
    values_.push_back(std::move(value));
    return;
  }
  auto& slot = values_[standard - kStandardColumns.begin()];
  if (slot) throw Error("history column '" + column + "' registered twice");
  slot = std::move(value);
}

void History::record() {
  row_.clear();
  row_.reserve(values_.size());
  for (size_t i = 0; i < values_.size(); ++i) {
    if (!values_[i]) throw Error("history column '" + columns_[i] + "' has no component");
    row_.push_back(values_[i]());
  }
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
