#pragma once
// VTK XML unstructured grids (.vtu, ASCII) and ParaView collections (.pvd).
#include <filesystem>
#include <string>
#include <vector>

#include "tc/mesh/mesh.hpp"

namespace tc::io {

/// A named field with `components` values per point or per cell.
struct Field {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

/// Writes one mesh with point and cell data. Points are written in 3D (z = 0 in 2D).
void write_vtu(const std::filesystem::path& file, const mesh::Mesh& m,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_data);

/// A .pvd collection, rewritten whole (through a temporary file and a rename) after every
/// added entry, so it is valid whenever the run stops.
class PvdCollection {
 public:
  explicit PvdCollection(std::filesystem::path file) : file_(std::move(file)) {}
  void add(double time, int part, const std::string& relative_file);
  /// Reads the entries of an existing collection file (a restart) and keeps those with
  /// time ≤ `until`, rewriting the file with them (none if there is no file yet).
  void load(double until);

 private:
  void write() const;
  struct Entry {
    double time;
    int part;
    std::string file;
  };
  std::filesystem::path file_;
  std::vector<Entry> entries_;
};

}  // namespace tc::io
