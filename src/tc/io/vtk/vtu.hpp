#pragma once
// VTK XML unstructured grids (.vtu), their parallel form (.pvtu listing one .vtu piece per
// rank) and ParaView collections (.pvd). A .vtu's arrays are ASCII text, or raw binary in the
// file's appended section, optionally zlib-compressed, laid out as VTK's own writer does.
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

/// How a .vtu holds its arrays (`[output]` format and compression): ASCII numbers printed to
/// round trip (shortest form that reads back to the same double); or every array appended
/// after the XML as raw little- or big-endian bytes (the host's order, named in byte_order),
/// each preceded by its UInt64 byte count; or those bytes cut into 32 KiB blocks, each
/// compressed by zlib, after VTK's compression header (vtkZLibDataCompressor).
enum class VtuEncoding { ascii, binary, zlib };

/// Writes one mesh with point and cell data. Points are written in 3D (z = 0 in 2D).
void write_vtu(const std::filesystem::path& file, const mesh::Mesh& m,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_data,
               VtuEncoding encoding = VtuEncoding::ascii);

/// Writes the cells `cells` of m as one piece of a parallel data set: the points they use
/// (renumbered in ascending order) and the fields restricted to those points and cells; the
/// fields are given on the whole mesh.
void write_vtu_piece(const std::filesystem::path& file, const mesh::Mesh& m,
                     const std::vector<int>& cells, const std::vector<Field>& point_data,
                     const std::vector<Field>& cell_data,
                     VtuEncoding encoding = VtuEncoding::ascii);

/// Writes a .pvtu listing `pieces` (file names relative to it) with the fields' names and
/// components.
void write_pvtu(const std::filesystem::path& file, const std::vector<Field>& point_data,
                const std::vector<Field>& cell_data, const std::vector<std::string>& pieces);

/// A .pvd collection, rewritten whole (through a temporary file and a rename) after every
/// added entry, so it is valid whenever the run stops.
class PvdCollection {
 public:
  explicit PvdCollection(std::filesystem::path file) : file_(std::move(file)) {}
  void add(double time, int part, const std::string& relative_file);
  /// Reads the entries of an existing collection file (a restart) and keeps those with
  /// time ≤ `until`, rewriting the file with them. False, with nothing read or written, when
  /// there is no such file or it is not a whole collection as write() leaves it (deleted,
  /// cut short, garbled): the caller rebuilds it (add_existing) or refuses.
  [[nodiscard]] bool load(double until);
  /// Lists an existing data set without rewriting the file (a rebuild; write_all() after).
  void add_existing(double time, int part, const std::string& relative_file) {
    entries_.push_back({time, part, relative_file});
  }
  [[nodiscard]] size_t size() const { return entries_.size(); }
  void write_all() const { write(); }

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
