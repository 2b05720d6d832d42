#include "tc/io/vtk/vtu.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>

#include "tc/core/error.hpp"
#include "tc/io/files/files.hpp"
#include "tc/io/vtk/vtk_grid.hpp"

namespace tc::io {

namespace {

// ---- ASCII ---------------------------------------------------------------------------------

/// `values`, `per_line` to a line, each in the shortest form that reads back to the same
/// double ({} of fmt), so that an ASCII file holds the values a binary one does, bit for bit.
template <class Out, class T>
void ascii_values(Out& out, const std::vector<T>& values, size_t per_line) {
  for (size_t i = 0; i < values.size(); ++i)
    out.print("{}{}", values[i], (i + 1) % per_line == 0 || i + 1 == values.size() ? "\n" : " ");
}

/// The grid's arrays as text into `out`, a StreamedFile: never the whole text in memory.
void write_ascii(StreamedFile& out, const VtkGrid& g) {
  out.print(R"(        <DataArray type="Float64" NumberOfComponents="3" format="ascii">)"
            "\n");
  ascii_values(out, g.points, 3);
  out.print("        </DataArray>\n      </Points>\n      <Cells>\n");
  out.print(R"(        <DataArray type="Int64" Name="connectivity" format="ascii">)"
            "\n");
  for (size_t c = 0; c < g.offsets.size(); ++c) {  // one cell a line
    for (auto i = c ? g.offsets[c - 1] : 0; i < g.offsets[c]; ++i)
      out.print("{} ", g.connectivity[static_cast<size_t>(i)]);
    out.print("\n");
  }
  out.print("        </DataArray>\n");
  out.print(R"(        <DataArray type="Int64" Name="offsets" format="ascii">)"
            "\n");
  ascii_values(out, g.offsets, 1);
  out.print("        </DataArray>\n");
  out.print(R"(        <DataArray type="UInt8" Name="types" format="ascii">)"
            "\n");
  for (const auto t : g.types) out.print("{}\n", static_cast<int>(t));
  out.print("        </DataArray>\n      </Cells>\n");
  const auto fields = [&](const std::vector<const Field*>& list) {
    for (const auto* f : list) {
      out.print(
          R"(        <DataArray type="Float64" Name="{}" NumberOfComponents="{}" format="ascii">)"
          "\n",
          f->name, f->components);
      ascii_values(out, f->values, static_cast<size_t>(f->components));
      out.print("        </DataArray>\n");
    }
  };
  out.print("      <PointData>\n");
  fields(g.point_data);
  out.print("      </PointData>\n      <CellData>\n");
  fields(g.cell_data);
  out.print("      </CellData>\n");
}

// ---- Appended binary -----------------------------------------------------------------------

/// VTK's block size for compressed data (vtkXMLWriter's default): each block is compressed on
/// its own, so a reader can seek to one.
constexpr size_t kBlock = 32768;

/// The bytes of one array as VTK reads them with header_type="UInt64": its byte count, then
/// the bytes (raw); or the compression header [number of blocks, block size, size of the
/// last block when partial (0 when whole), compressed size of each block], then the
/// compressed blocks (zlib).
void append_array(std::string& data, const void* bytes, size_t n, VtuEncoding encoding) {
  const auto put = [&](std::uint64_t v) {
    data.append(reinterpret_cast<const char*>(&v), sizeof v);
  };
  const auto* in = static_cast<const unsigned char*>(bytes);
  if (encoding == VtuEncoding::binary) {
    put(n);
    data.append(reinterpret_cast<const char*>(in), n);
    return;
  }
  const size_t blocks = (n + kBlock - 1) / kBlock;
  const size_t header = data.size();
  put(blocks);
  put(kBlock);
  put(n % kBlock);
  for (size_t b = 0; b < blocks; ++b) put(0);  // the sizes, filled in below
  std::vector<unsigned char> out(compressBound(kBlock));
  for (size_t b = 0; b < blocks; ++b) {
    const size_t size = std::min(kBlock, n - b * kBlock);
    auto length = static_cast<uLongf>(out.size());
    // Level 1: most of the size saved at a fraction of the default level's time (measured
    // in bench/RESULTS.md, "Field output").
    const int rc = compress2(out.data(), &length, in + b * kBlock, static_cast<uLong>(size), 1);
    if (rc != Z_OK) throw OutputError(fmt::format("zlib compress2 failed ({})", rc));
    const std::uint64_t compressed = length;
    std::memcpy(data.data() + header + (3 + b) * sizeof compressed, &compressed, sizeof compressed);
    data.append(reinterpret_cast<const char*>(out.data()), length);
  }
}

void write_appended(TextBuffer& out, std::string& data, const VtkGrid& g, VtuEncoding encoding) {
  const auto array = [&](const char* type, const std::string& attributes, const auto& values) {
    out.print(R"(        <DataArray type="{}" {}format="appended" offset="{}"/>)"
              "\n",
              type, attributes, data.size());
    append_array(data, values.data(), values.size() * sizeof(values[0]), encoding);
  };
  array("Float64", R"(NumberOfComponents="3" )", g.points);
  out.print("      </Points>\n      <Cells>\n");
  array("Int64", R"(Name="connectivity" )", g.connectivity);
  array("Int64", R"(Name="offsets" )", g.offsets);
  array("UInt8", R"(Name="types" )", g.types);
  out.print("      </Cells>\n");
  const auto fields = [&](const std::vector<const Field*>& list) {
    for (const auto* f : list)
      array("Float64", fmt::format(R"(Name="{}" NumberOfComponents="{}" )", f->name, f->components),
            f->values);
  };
  out.print("      <PointData>\n");
  fields(g.point_data);
  out.print("      </PointData>\n      <CellData>\n");
  fields(g.cell_data);
  out.print("      </CellData>\n");
}

/// The grid `g` as a .vtu in `encoding`.
void write_grid(const std::filesystem::path& file, const VtkGrid& g, VtuEncoding encoding) {
  const auto head = [&](auto& out) {
    out.print(R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="{}" header_type="UInt64"{}>
  <UnstructuredGrid>
    <Piece NumberOfPoints="{}" NumberOfCells="{}">
      <Points>
)",
              std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian",
              encoding == VtuEncoding::zlib ? R"( compressor="vtkZLibDataCompressor")" : "",
              g.points.size() / 3, g.types.size());
  };
  if (encoding == VtuEncoding::ascii) {
    StreamedFile out(file);
    head(out);
    write_ascii(out, g);
    out.print("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    out.finish();
    return;
  }
  TextBuffer out;
  head(out);
  std::string data;
  if (encoding == VtuEncoding::binary) {  // its exact size: no growth by doubling, no copy
    size_t bytes = 8 * 4 + sizeof(double) * g.points.size() +
                   sizeof(std::int64_t) * (g.connectivity.size() + g.offsets.size()) +
                   g.types.size();
    for (const auto* list : {&g.point_data, &g.cell_data})
      for (const auto* f : *list) bytes += 8 + sizeof(double) * f->values.size();
    data.reserve(bytes);
  }
  write_appended(out, data, g, encoding);
  // The appended section as VTK writes it: '_' then the arrays' bytes, offsets counted from
  // the byte after it; the XML, the bytes and the end written one after the other (no copy
  // of the whole file).
  out.print("    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _");
  write_file(file, {out.view(), std::string_view(data), "\n  </AppendedData>\n</VTKFile>\n"});
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
               const std::vector<Field>& point_data, const std::vector<Field>& cell_data,
               VtuEncoding encoding) {
  write_grid(file, whole_grid(m, point_data, cell_data), encoding);
}

void write_vtu_piece(const std::filesystem::path& file, const mesh::Mesh& m,
                     const std::vector<int>& cells, const std::vector<Field>& point_data,
                     const std::vector<Field>& cell_data, VtuEncoding encoding) {
  write_grid(file, piece_grid(m, cells, point_data, cell_data), encoding);
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
