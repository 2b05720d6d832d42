#include "tc/io/vtu.hpp"

#include <fmt/format.h>
#include <fmt/os.h>

#include <cstdlib>
#include <fstream>
#include <regex>

#include "tc/core/error.hpp"

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

void write_field(fmt::ostream& out, const Field& f) {
  out.print(
      R"(        <DataArray type="Float64" Name="{}" NumberOfComponents="{}" format="ascii">)",
      f.name, f.components);
  out.print("\n");
  for (size_t i = 0; i < f.values.size(); ++i)
    out.print("{:.12g}{}", f.values[i], (i + 1) % f.components == 0 ? "\n" : " ");
  out.print("        </DataArray>\n");
}

}  // namespace

void write_vtu(const std::filesystem::path& file, const mesh::Mesh& m,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  auto out = fmt::output_file(file.string());
  out.print(R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <UnstructuredGrid>
    <Piece NumberOfPoints="{}" NumberOfCells="{}">
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">
)",
            m.n_nodes(), m.n_cells());
  for (const auto& p : m.points()) out.print("{:.15g} {:.15g} {:.15g}\n", p[0], p[1], p[2]);
  out.print("        </DataArray>\n      </Points>\n      <Cells>\n");
  out.print(R"(        <DataArray type="Int64" Name="connectivity" format="ascii">)");
  out.print("\n");
  long offset = 0;
  std::string offsets, types;
  for (int c = 0; c < m.n_cells(); ++c) {
    for (const int n : m.cell(c)) out.print("{} ", n);
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
  out.print("      <PointData>\n");
  for (const auto& f : point_data) write_field(out, f);
  out.print("      </PointData>\n      <CellData>\n");
  for (const auto& f : cell_data) write_field(out, f);
  out.print("      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
}

void PvdCollection::add(double time, int part, const std::string& relative_file) {
  entries_.push_back({time, part, relative_file});
  write();
}

void PvdCollection::load(double until) {
  entries_.clear();
  std::ifstream in(file_);
  std::string line;
  const std::regex data_set(R"re(<DataSet timestep="([^"]*)" part="([^"]*)" file="([^"]*)"/>)re");
  std::smatch m;
  while (std::getline(in, line)) {
    if (!std::regex_search(line, m, data_set)) continue;
    const double time = std::strtod(m[1].str().c_str(), nullptr);
    if (time <= until) entries_.push_back({time, std::atoi(m[2].str().c_str()), m[3].str()});
  }
  write();
}

void PvdCollection::write() const {
  const auto tmp = std::filesystem::path(file_.string() + ".tmp");
  {
    auto out = fmt::output_file(tmp.string());
    out.print(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n"
        "  <Collection>\n");
    for (const auto& e : entries_)
      out.print("    <DataSet timestep=\"{:.12g}\" part=\"{}\" file=\"{}\"/>\n", e.time, e.part,
                e.file);
    out.print("  </Collection>\n</VTKFile>\n");
  }
  std::filesystem::rename(tmp, file_);
}

}  // namespace tc::io
