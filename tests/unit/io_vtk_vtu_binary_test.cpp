// The binary .vtu encodings (io/vtk/vtu.hpp): appended raw data and zlib-compressed blocks hold
// the same bytes as the ASCII file's numbers, bit for bit, read back by a reader written here from
// VTK's description of the format (offsets from the byte after '_', a UInt64 byte count before
// each raw array; [blocks, block size, last partial size, compressed sizes] before compressed
// ones), and by meshio when python3-meshio is installed.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <regex>

#include "support/cli.hpp"
#include "tc/io/vtk/vtu.hpp"

using namespace tc;

namespace {

/// One DataArray as bytes in the host's order (what a binary file holds, what the ASCII
/// numbers parse to).
struct Array {
  std::string type;
  int components = 1;
  std::vector<unsigned char> bytes;
};

std::uint64_t get_u64(const std::string& s, size_t at) {
  std::uint64_t v = 0;
  EXPECT_LE(at + 8, s.size());
  if (at + 8 <= s.size()) std::memcpy(&v, s.data() + at, 8);
  return v;
}

template <class T>
void append(std::vector<unsigned char>& out, T v) {
  const auto* p = reinterpret_cast<const unsigned char*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

std::vector<unsigned char> parse_ascii(const std::string& type, const std::string& text) {
  std::vector<unsigned char> out;
  const char* p = text.c_str();
  for (;;) {
    char* end = nullptr;
    if (type == "Float64") {
      const double v = std::strtod(p, &end);
      if (end == p) break;
      append(out, v);
    } else {
      const long long v = std::strtoll(p, &end, 10);
      if (end == p) break;
      if (type == "Int64")
        append(out, static_cast<std::int64_t>(v));
      else
        append(out, static_cast<std::uint8_t>(v));
    }
    p = end;
  }
  return out;
}

/// The bytes of the appended array at `at` (the position of its header in the file).
std::vector<unsigned char> appended(const std::string& file, size_t at, bool zlib) {
  if (!zlib) {
    const auto n = get_u64(file, at);
    EXPECT_LE(at + 8 + n, file.size());
    return {file.begin() + static_cast<long>(at + 8), file.begin() + static_cast<long>(at + 8 + n)};
  }
  const auto blocks = get_u64(file, at), block = get_u64(file, at + 8),
             last = get_u64(file, at + 16);
  EXPECT_EQ(block, 32768u);
  std::vector<unsigned char> out;
  size_t data = at + 24 + 8 * blocks;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const auto compressed = get_u64(file, at + 24 + 8 * b);
    const auto size = b + 1 == blocks && last != 0 ? last : block;
    std::vector<unsigned char> plain(size);
    uLongf length = static_cast<uLongf>(size);
    EXPECT_EQ(uncompress(plain.data(), &length, reinterpret_cast<const Bytef*>(file.data() + data),
                         static_cast<uLong>(compressed)),
              Z_OK);
    EXPECT_EQ(length, size);
    out.insert(out.end(), plain.begin(), plain.end());
    data += compressed;
  }
  return out;
}

/// Every DataArray of a .vtu, keyed by section ("Points", "Cells", "PointData", "CellData")
/// and name.
std::map<std::string, Array> read_vtu(const std::filesystem::path& path) {
  const auto file = test::read_file(path);
  const bool zlib = file.find(R"(compressor="vtkZLibDataCompressor")") != std::string::npos;
  EXPECT_NE(file.find(R"(header_type="UInt64")"), std::string::npos);
  EXPECT_NE(file.find(R"(byte_order="LittleEndian")"), std::string::npos);  // x86-64, ARM64
  const auto marker = file.find("<AppendedData encoding=\"raw\">");
  const std::string xml = file.substr(0, marker);
  size_t base = std::string::npos;  // the byte after '_'
  if (marker != std::string::npos) {
    base = file.find('_', marker) + 1;
    const std::string tail = "\n  </AppendedData>\n</VTKFile>\n";
    EXPECT_EQ(file.substr(file.size() - tail.size()), tail);
  }
  std::map<std::string, Array> arrays;
  const std::regex tag(R"(<DataArray([^>]*?)(/?)>)");
  const std::regex attribute(R"re((\w+)="([^"]*)")re");
  for (std::sregex_iterator it(xml.begin(), xml.end(), tag), e; it != e; ++it) {
    std::map<std::string, std::string> a;
    const std::string attributes = (*it)[1];
    for (std::sregex_iterator at(attributes.begin(), attributes.end(), attribute), ae; at != ae;
         ++at)
      a[(*at)[1]] = (*at)[2];
    const auto where = static_cast<size_t>(it->position());
    std::string section = "Points";
    for (const char* s : {"<Cells>", "<PointData>", "<CellData>"})
      if (xml.rfind(s, where) != std::string::npos) section = std::string(s + 1, s + strlen(s) - 1);
    Array array{
        a["type"], a.count("NumberOfComponents") ? std::stoi(a["NumberOfComponents"]) : 1, {}};
    if (a["format"] == "ascii") {
      const auto start = where + static_cast<size_t>(it->length());
      array.bytes =
          parse_ascii(array.type, xml.substr(start, xml.find("</DataArray>", start) - start));
    } else {
      EXPECT_EQ(a["format"], "appended");
      EXPECT_EQ((*it)[2], "/");
      EXPECT_NE(base, std::string::npos);
      array.bytes = appended(file, base + std::stoull(a["offset"]), zlib);
    }
    arrays[section + "/" + a["Name"]] = std::move(array);
  }
  return arrays;
}

/// A 2D mesh of both cell types: 2 × 40 quads and a row of triangles on top.
mesh::Mesh mixed_mesh() {
  mesh::Mesh m(2);
  const int nx = 40;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= nx; ++i) m.add_point({i / 3.0, j * 0.1 + 1e-17 * i, 0.0});
  const auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::array<int, 4> q{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      m.add_cell(mesh::CellType::Quad4, q);
    }
  for (int i = 0; i < nx; ++i) {
    const std::array<int, 3> t{id(i, 2), id(i + 1, 2), id(i + 1, 3)};
    m.add_cell(mesh::CellType::Tri3, t);
  }
  return m;
}

/// Values that a 12-digit ASCII file did not hold exactly: thirds, extremes, subnormals, −0.
double awkward(size_t i) {
  switch (i % 7) {
    case 0:
      return 1.0 / 3.0 + static_cast<double>(i);
    case 1:
      return -0.0;
    case 2:
      return std::numeric_limits<double>::denorm_min() * static_cast<double>(i);
    case 3:
      return std::numeric_limits<double>::max() / static_cast<double>(i + 1);
    case 4:
      return -std::exp(-static_cast<double>(i));
    case 5:
      return 1e-300 * std::sqrt(static_cast<double>(i));
    default:
      return std::nextafter(1.0, 2.0) * static_cast<double>(i);
  }
}

io::Field field(const std::string& name, int components, size_t rows) {
  io::Field f{name, components, {}};
  for (size_t i = 0; i < rows * static_cast<size_t>(components); ++i)
    f.values.push_back(awkward(i + name.size()));
  return f;
}

std::vector<unsigned char> bytes_of(const std::vector<double>& v) {
  const auto* p = reinterpret_cast<const unsigned char*>(v.data());
  return {p, p + v.size() * sizeof(double)};
}

void expect_same(const std::map<std::string, Array>& a, const std::map<std::string, Array>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [key, array] : a) {
    ASSERT_EQ(b.count(key), 1u) << key;
    EXPECT_EQ(array.type, b.at(key).type) << key;
    EXPECT_EQ(array.components, b.at(key).components) << key;
    EXPECT_TRUE(array.bytes == b.at(key).bytes) << key;  // to the bit
  }
}

TEST(VtuBinary, AppendedRawAndZlibHoldTheAsciiValuesToTheBit) {
  const auto m = mixed_mesh();
  const auto nodes = static_cast<size_t>(m.n_nodes()), cells = static_cast<size_t>(m.n_cells());
  // 4096 values: exactly one 32 KiB block (its partial size is 0); 4100: one block and a bit.
  const std::vector<io::Field> point{field("t", 1, nodes), field("u", 3, nodes)};
  io::Field whole{"whole_block", 4096 / static_cast<int>(cells) + 1, {}};
  whole.values.resize(cells * static_cast<size_t>(whole.components));
  for (size_t i = 0; i < whole.values.size(); ++i) whole.values[i] = awkward(3 * i);
  const std::vector<io::Field> cell{field("s", 1, cells), field("q", 9, cells), whole};
  const auto dir = test::fresh_dir("vtu-binary");
  io::write_vtu(dir / "a.vtu", m, point, cell, io::VtuEncoding::ascii);
  io::write_vtu(dir / "b.vtu", m, point, cell, io::VtuEncoding::binary);
  io::write_vtu(dir / "z.vtu", m, point, cell, io::VtuEncoding::zlib);
  const auto a = read_vtu(dir / "a.vtu"), b = read_vtu(dir / "b.vtu"), z = read_vtu(dir / "z.vtu");
  expect_same(a, b);
  expect_same(a, z);
  // And the values are the ones given, not only the same in the three files.
  EXPECT_TRUE(b.at("PointData/u").bytes == bytes_of(point[1].values));
  EXPECT_TRUE(b.at("CellData/whole_block").bytes == bytes_of(whole.values));
  std::vector<double> xyz;
  for (const auto& p : m.points()) xyz.insert(xyz.end(), p.begin(), p.end());
  EXPECT_TRUE(a.at("Points/").bytes == bytes_of(xyz));
  EXPECT_EQ(b.at("Cells/types").bytes.size(), cells);
  EXPECT_EQ(b.at("Cells/connectivity").bytes.size(), 8 * (4 * 80 + 3 * 40u));
  // The compressed file is smaller than the raw one (the mesh's integers compress well).
  EXPECT_LT(std::filesystem::file_size(dir / "z.vtu"), std::filesystem::file_size(dir / "b.vtu"));
}

TEST(VtuBinary, BlockBoundaries) {
  // A cell field of exactly 32768 bytes (one whole block: the header's partial size is 0) and
  // a point field of 32768 + 8 (a whole block and a partial one of 8 bytes).
  mesh::Mesh m(3);
  for (int i = 0; i < 4096; ++i) m.add_point({static_cast<double>(i), 0.5, -1.0 / (i + 1)});
  m.add_point({0, 1, 0});
  const std::array<int, 4> tet{0, 1, 4096, 2};
  m.add_cell(mesh::CellType::Tet4, tet);
  const auto point = field("p", 1, static_cast<size_t>(m.n_nodes()));
  const auto block = field("block", 4096, 1);
  const auto dir = test::fresh_dir("vtu-binary-blocks");
  for (const auto encoding :
       {io::VtuEncoding::ascii, io::VtuEncoding::binary, io::VtuEncoding::zlib}) {
    const auto file = dir / fmt::format("f{}.vtu", static_cast<int>(encoding));
    io::write_vtu(file, m, {point}, {block}, encoding);
    const auto arrays = read_vtu(file);
    EXPECT_TRUE(arrays.at("CellData/block").bytes == bytes_of(block.values));
    EXPECT_TRUE(arrays.at("PointData/p").bytes == bytes_of(point.values));
  }
  const auto z = test::read_file(dir / "f2.vtu");
  const auto base = z.find('_', z.find("<AppendedData")) + 1;
  const auto header = [&](const std::string& name) {
    const std::regex offset("Name=\"" + name +
                            R"re(" NumberOfComponents="\d+" format="appended" offset="(\d+)")re");
    std::smatch s;
    EXPECT_TRUE(std::regex_search(z, s, offset)) << name;
    const size_t at = base + std::stoull(s[1]);
    return std::array<std::uint64_t, 3>{get_u64(z, at), get_u64(z, at + 8), get_u64(z, at + 16)};
  };
  EXPECT_EQ(header("block"), (std::array<std::uint64_t, 3>{1, 32768, 0}));
  EXPECT_EQ(header("p"), (std::array<std::uint64_t, 3>{2, 32768, 8}));
}

TEST(VtuBinary, PiecesInEveryEncodingHoldTheSameValues) {
  const auto m = mixed_mesh();
  const std::vector<int> cells{3, 7, 80, 119};
  const std::vector<io::Field> point{field("t", 1, static_cast<size_t>(m.n_nodes()))};
  const std::vector<io::Field> cell{field("s", 3, static_cast<size_t>(m.n_cells()))};
  const auto dir = test::fresh_dir("vtu-binary-pieces");
  io::write_vtu_piece(dir / "a.vtu", m, cells, point, cell, io::VtuEncoding::ascii);
  io::write_vtu_piece(dir / "b.vtu", m, cells, point, cell, io::VtuEncoding::binary);
  io::write_vtu_piece(dir / "z.vtu", m, cells, point, cell, io::VtuEncoding::zlib);
  const auto a = read_vtu(dir / "a.vtu");
  expect_same(a, read_vtu(dir / "b.vtu"));
  expect_same(a, read_vtu(dir / "z.vtu"));
  EXPECT_EQ(a.at("CellData/s").bytes.size(), 3 * 8 * cells.size());
}

TEST(VtuBinary, MeshioReadsTheBinaryFilesAsTheAsciiOne) {
  // An independent reader (python3-meshio, Debian's package; skipped when not installed).
  if (std::system("/usr/bin/python3 -c 'import meshio' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3-meshio is not installed";
  const auto m = mixed_mesh();
  const auto nodes = static_cast<size_t>(m.n_nodes()), cells = static_cast<size_t>(m.n_cells());
  const std::vector<io::Field> point{field("t", 1, nodes), field("u", 3, nodes)};
  const std::vector<io::Field> cell{field("s", 1, cells), field("q", 9, cells)};
  const auto dir = test::fresh_dir("vtu-binary-meshio");
  io::write_vtu(dir / "a.vtu", m, point, cell, io::VtuEncoding::ascii);
  io::write_vtu(dir / "b.vtu", m, point, cell, io::VtuEncoding::binary);
  io::write_vtu(dir / "z.vtu", m, point, cell, io::VtuEncoding::zlib);
  // Bitwise: the arrays compared as the integers of their bytes (NaN-free, −0 distinct).
  const auto script = dir / "compare.py";
  {
    std::ofstream py(script);
    py << R"(import sys, meshio, numpy as np
def same(x, y):
    x, y = np.ascontiguousarray(x), np.ascontiguousarray(y)
    return x.shape == y.shape and x.dtype == y.dtype and x.tobytes() == y.tobytes()
a = meshio.read(sys.argv[1])
for f in sys.argv[2:]:
    b = meshio.read(f)
    assert same(a.points, b.points), f + ": points"
    assert len(a.cells) == len(b.cells) == 2, f + ": cell blocks"
    for ca, cb in zip(a.cells, b.cells):
        assert ca.type == cb.type and same(ca.data, cb.data), f + ": cells"
    for k in a.point_data:
        assert same(a.point_data[k], b.point_data[k]), f + ": " + k
    for k in a.cell_data:
        for x, y in zip(a.cell_data[k], b.cell_data[k]):
            assert same(x, y), f + ": " + k
assert a.point_data["t"].dtype == np.float64
print("same")
)";
  }
  const auto r =
      test::run_command("/usr/bin/python3 " + script.string() + " " + (dir / "a.vtu").string() +
                        " " + (dir / "b.vtu").string() + " " + (dir / "z.vtu").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("same"), std::string::npos) << r.output;
}

}  // namespace
