#include "tc/io/vtu.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include "tc/core/error.hpp"
#include "tc/io/files.hpp"

namespace tc::io {

namespace {

int vtk_type(mesh::CellType t) {
  switch (t) {
    case mesh::CellType::Tri3:
      return 5;
    case mesh::CellType::Quad4:
      return 9;
    case mesh::CellType::Tet4:
      return 10;
    case mesh::CellType::Hex8:
      return 12;
  }
  return 0;
}

void write_field(TextBuffer& out, const Field& f) {
  out.print(
      R"(        <DataArray type="Float64" Name="{}" NumberOfComponents="{}" format="ascii">)",
      f.name, f.components);
  out.print("\n");
  for (size_t i = 0; i < f.values.size(); ++i)
    out.print("{:.12g}{}", f.values[i], (i + 1) % f.components == 0 ? "\n" : " ");
  out.print("        </DataArray>\n");
}

/// The grid of `cells` of m with the points `points` (ascending; local[global] their new
/// numbers, or identity when empty) and the fields restricted to them.
void write_grid(const std::filesystem::path& file, const mesh::Mesh& m,
                const std::vector<int>& points, const std::vector<int>& cells,
                const std::vector<int>& local, const std::vector<Field>& point_data,
                const std::vector<Field>& cell_data) {
  TextBuffer out;
  out.print(R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <UnstructuredGrid>
    <Piece NumberOfPoints="{}" NumberOfCells="{}">
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">
)",
            points.size(), cells.size());
  for (const int a : points) {
    const auto& p = m.point(a);
    out.print("{:.15g} {:.15g} {:.15g}\n", p[0], p[1], p[2]);
  }
  out.print("        </DataArray>\n      </Points>\n      <Cells>\n");
  out.print(R"(        <DataArray type="Int64" Name="connectivity" format="ascii">)");
  out.print("\n");
  long offset = 0;
  std::string offsets, types;
  for (const int c : cells) {
    for (const int n : m.cell(c))
      out.print("{} ", local.empty() ? n : local[static_cast<size_t>(n)]);
    out.print("\n");
    offset += static_cast<long>(m.cell(c).size());
    offsets += fmt::format("{}\n", offset);
    types += fmt::format("{}\n", vtk_type(m.cell_type(c)));
  }
  out.print("        </DataArray>\n");
  out.print(R"(        <DataArray type="Int64" Name="offsets" format="ascii">)");
  out.print("\n{}        </DataArray>\n", offsets);
  out.print(R"(        <DataArray type="UInt8" Name="types" format="ascii">)");
  out.print("\n{}        </DataArray>\n      </Cells>\n", types);
  auto restricted = [](const Field& f, const std::vector<int>& rows, size_t all) {
    if (rows.size() == all) return f;
    Field r{f.name, f.components, {}};
    r.values.reserve(rows.size() * static_cast<size_t>(f.components));
    for (const int i : rows)
      for (int k = 0; k < f.components; ++k)
        r.values.push_back(f.values[static_cast<size_t>(f.components * i + k)]);
    return r;
  };
  out.print("      <PointData>\n");
  for (const auto& f : point_data)
    write_field(out, restricted(f, points, static_cast<size_t>(m.n_nodes())));
  out.print("      </PointData>\n      <CellData>\n");
  for (const auto& f : cell_data)
    write_field(out, restricted(f, cells, static_cast<size_t>(m.n_cells())));
  out.print("      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
  write_file(file, out.view());
}

std::vector<int> iota(int n) {
  std::vector<int> v(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<size_t>(i)] = i;
  return v;
}

void write_data_arrays(TextBuffer& out, const char* tag, const std::vector<Field>& fields) {
  out.print("    <{}>\n", tag);
  for (const auto& f : fields)
    out.print(R"(      <PDataArray type="Float64" Name="{}" NumberOfComponents="{}"/>)"
              "\n",
              f.name, f.components);
  out.print("    </{}>\n", tag);
}

}  // namespace

void write_vtu(const std::filesystem::path& file, const mesh::Mesh& m,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  write_grid(file, m, iota(m.n_nodes()), iota(m.n_cells()), {}, point_data, cell_data);
}

void write_vtu_piece(const std::filesystem::path& file, const mesh::Mesh& m,
                     const std::vector<int>& cells, const std::vector<Field>& point_data,
                     const std::vector<Field>& cell_data) {
  std::vector<int> local(static_cast<size_t>(m.n_nodes()), -1), points;
  for (const int c : cells)
    for (const int n : m.cell(c)) local[static_cast<size_t>(n)] = 0;
  for (int a = 0; a < m.n_nodes(); ++a)
    if (local[static_cast<size_t>(a)] == 0) {
      local[static_cast<size_t>(a)] = static_cast<int>(points.size());
      points.push_back(a);
    }
  write_grid(file, m, points, cells, local, point_data, cell_data);
}

void write_pvtu(const std::filesystem::path& file, const std::vector<Field>& point_data,
                const std::vector<Field>& cell_data, const std::vector<std::string>& pieces) {
  TextBuffer out;
  out.print(R"(<?xml version="1.0"?>
<VTKFile type="PUnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <PUnstructuredGrid GhostLevel="0">
)");
  write_data_arrays(out, "PPointData", point_data);
  write_data_arrays(out, "PCellData", cell_data);
  out.print(R"(    <PPoints>
      <PDataArray type="Float64" NumberOfComponents="3"/>
    </PPoints>
)");
  for (const auto& p : pieces) out.print("    <Piece Source=\"{}\"/>\n", p);
  out.print("  </PUnstructuredGrid>\n</VTKFile>\n");
  write_file(file, out.view());
}

void PvdCollection::add(double time, int part, const std::string& relative_file) {
  entries_.push_back({time, part, relative_file});
  try {
    write();
  } catch (...) {  // not on disk: not listed, should a later write succeed
    entries_.pop_back();
    throw;
  }
}

bool PvdCollection::load(double until) {
  entries_.clear();
  std::ifstream in(file_);
  if (!in) return false;
  std::stringstream text;
  text << in.rdbuf();
  // Whole as write() leaves it: its head, one data set a line, its tail (a file cut short by a
  // full disk or edited by hand is not taken for the list of what was written).
  const std::string head =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n  <Collection>\n";
  const std::string tail = "  </Collection>\n</VTKFile>\n";
  const auto all = text.str();
  if (all.size() < head.size() + tail.size() || all.compare(0, head.size(), head) != 0 ||
      all.compare(all.size() - tail.size(), tail.size(), tail) != 0)
    return false;
  std::istringstream lines(all.substr(head.size(), all.size() - head.size() - tail.size()));
  std::string line;
  const std::regex data_set(
      R"re(    <DataSet timestep="([^"]*)" part="([0-9]+)" file="([^"<>&/]+)"/>)re");
  std::smatch m;
  std::vector<Entry> kept;
  while (std::getline(lines, line)) {
    if (!std::regex_match(line, m, data_set)) return false;
    char* end = nullptr;
    const double time = std::strtod(m[1].str().c_str(), &end);
    if (end == m[1].str().c_str() || *end != '\0') return false;
    if (time <= until) kept.push_back({time, std::atoi(m[2].str().c_str()), m[3].str()});
  }
  entries_ = std::move(kept);
  write();
  return true;
}

void PvdCollection::write() const {
  TextBuffer out;
  out.print(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n"
      "  <Collection>\n");
  for (const auto& e : entries_)
    out.print("    <DataSet timestep=\"{:.12g}\" part=\"{}\" file=\"{}\"/>\n", e.time, e.part,
              e.file);
  out.print("  </Collection>\n</VTKFile>\n");
  replace_file(file_, out.view());
}

}  // namespace tc::io
