// The field output's encodings on a real frame (issue 43): reads an ASCII .vtu that a run wrote
// (its points, cells and arrays), then writes it again as ASCII, raw binary and zlib-compressed
// binary, in alternating rounds, and prints per encoding the file size and the median CPU and
// wall seconds of a write (bench/RESULTS.md, "Field output").
//   build/bin/bench_output FRAME.vtu [ROUNDS] [DIR]
#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "tc/io/output/vtu.hpp"

namespace {

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

std::vector<double> numbers(const std::string& text) {
  std::vector<double> out;
  const char* p = text.c_str();
  for (char* end = nullptr;; p = end) {
    const double v = std::strtod(p, &end);
    if (end == p) break;
    out.push_back(v);
  }
  return out;
}

tc::mesh::CellType cell_type(int vtk) {
  switch (vtk) {
    case 5:
      return tc::mesh::CellType::Tri3;
    case 9:
      return tc::mesh::CellType::Quad4;
    case 10:
      return tc::mesh::CellType::Tet4;
    default:
      return tc::mesh::CellType::Hex8;
  }
}

struct Frame {
  tc::mesh::Mesh mesh;
  std::vector<tc::io::Field> point, cell;
};

Frame read_ascii(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  const std::string xml = s.str();
  const auto array = [&](size_t tag) {
    const auto start = xml.find('>', tag) + 1;
    return numbers(xml.substr(start, xml.find("</DataArray>", start) - start));
  };
  const auto named = [&](const std::string& name) {
    return array(xml.rfind("<DataArray", xml.find("Name=\"" + name + "\"")));
  };
  const auto points = array(xml.find("<DataArray", xml.find("<Points>")));
  const auto conn = named("connectivity"), offsets = named("offsets"), types = named("types");
  int dim = 2;
  for (const auto t : types)
    if (t >= 10) dim = 3;
  Frame f{tc::mesh::Mesh(dim), {}, {}};
  for (size_t a = 0; a + 2 < points.size(); a += 3)
    f.mesh.add_point({points[a], points[a + 1], points[a + 2]});
  size_t begin = 0;
  for (size_t c = 0; c < offsets.size(); ++c) {
    const auto end = static_cast<size_t>(offsets[c]);
    std::vector<int> nodes;
    for (size_t i = begin; i < end; ++i) nodes.push_back(static_cast<int>(conn[i]));
    f.mesh.add_cell(cell_type(static_cast<int>(types[c])), nodes);
    begin = end;
  }
  const std::regex tag(
      R"re(<DataArray type="Float64" Name="([^"]+)" NumberOfComponents="(\d+)")re");
  const auto cells_at = xml.find("<CellData>");
  for (std::sregex_iterator it(xml.begin(), xml.end(), tag), e; it != e; ++it) {
    tc::io::Field field{(*it)[1], std::stoi((*it)[2]), array(static_cast<size_t>(it->position()))};
    (static_cast<size_t>(it->position()) > cells_at ? f.cell : f.point).push_back(std::move(field));
  }
  return f;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    fmt::print(stderr, "usage: {} FRAME.vtu [ROUNDS] [DIR]\n", argv[0]);
    return 2;
  }
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 5;
  const std::filesystem::path dir = argc > 3 ? argv[3] : std::filesystem::temp_directory_path();
  const auto frame = read_ascii(argv[1]);
  fmt::print("{}: {} points, {} cells, {} point and {} cell arrays\n", argv[1],
             frame.mesh.n_nodes(), frame.mesh.n_cells(), frame.point.size(), frame.cell.size());
  using E = tc::io::VtuEncoding;
  const std::pair<E, const char*> encodings[] = {
      {E::ascii, "ascii"}, {E::binary, "binary"}, {E::zlib, "zlib"}};
  std::vector<double> cpu[3], wall[3];
  std::uintmax_t size[3] = {};
  for (int r = 0; r < rounds; ++r)
    for (int e = 0; e < 3; ++e) {  // alternating: the machine's load falls on all alike
      const auto file = dir / fmt::format("bench_output_{}.vtu", encodings[e].second);
      const double c0 = cpu_seconds();
      const auto w0 = std::chrono::steady_clock::now();
      tc::io::write_vtu(file, frame.mesh, frame.point, frame.cell, encodings[e].first);
      wall[e].push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
      cpu[e].push_back(cpu_seconds() - c0);
      size[e] = std::filesystem::file_size(file);
      std::filesystem::remove(file);
    }
  for (int e = 0; e < 3; ++e)
    fmt::print(
        "{:7} {:10.3f} MB  cpu {:.3f} s  wall {:.3f} s  (size {:.3f}x, cpu {:.3f}x of ascii)\n",
        encodings[e].second, static_cast<double>(size[e]) / 1e6, median(cpu[e]), median(wall[e]),
        static_cast<double>(size[e]) / static_cast<double>(size[0]),
        median(cpu[e]) / median(cpu[0]));
  return 0;
}
