// The field output's encodings on a real frame (issue 43): reads an ASCII .vtu that a run wrote
// (its points, cells and arrays), then writes it again as ASCII, raw binary, zlib-compressed
// binary and VTKHDF (when the build has parallel HDF5), in alternating rounds, and prints per
// encoding the file size and the median CPU and wall seconds of a write (bench/RESULTS.md,
// "Field output"). Under `mpirun -n N` each rank writes a contiguous block of the cells, as a
// run's ranks do: a .vtu piece each, or its piece of the one VTKHDF file, collectively; the
// size is then the pieces' sum, the times the slowest rank's (after a barrier).
//   build/bin/bench_output FRAME.vtu [ROUNDS] [DIR]
#include <fmt/format.h>
#include <mpi.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "tc/io/vtk/vtkhdf.hpp"
#include "tc/io/vtk/vtu.hpp"

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

/// Rank `rank`'s contiguous block of the frame's cells.
std::vector<int> block(const Frame& f, int rank, int size) {
  std::vector<int> cells;
  const int n = f.mesh.n_cells();
  for (int c = n * rank / size; c < n * (rank + 1) / size; ++c) cells.push_back(c);
  return cells;
}

double largest(double v) {
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (argc < 2) {
    if (rank == 0) fmt::print(stderr, "usage: {} FRAME.vtu [ROUNDS] [DIR]\n", argv[0]);
    MPI_Finalize();
    return 2;
  }
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 5;
  const std::filesystem::path dir = argc > 3 ? argv[3] : std::filesystem::temp_directory_path();
  std::error_code made;  // the writers take an existing folder
  if (rank == 0) std::filesystem::create_directories(dir, made);
  MPI_Barrier(MPI_COMM_WORLD);
  const auto frame = read_ascii(argv[1]);
  const auto mine = block(frame, rank, size);
  if (rank == 0)
    fmt::print("{}: {} points, {} cells, {} point and {} cell arrays, {} rank(s)\n", argv[1],
               frame.mesh.n_nodes(), frame.mesh.n_cells(), frame.point.size(), frame.cell.size(),
               size);
  using E = tc::io::VtuEncoding;
  struct Encoding {
    E vtu;
    const char* name;
    bool vtkhdf;
  };
  std::vector<Encoding> encodings{
      {E::ascii, "ascii", false}, {E::binary, "binary", false}, {E::zlib, "zlib", false}};
  if (tc::io::vtkhdf_available()) encodings.push_back({E::ascii, "vtkhdf", true});
  const size_t n = encodings.size();
  std::vector<std::vector<double>> cpu(n), wall(n);
  std::vector<double> size_mb(n);
  for (int r = 0; r < rounds; ++r)
    for (size_t e = 0; e < n; ++e) {  // alternating: the machine's load falls on all alike
      const auto& enc = encodings[e];
      const auto file = enc.vtkhdf ? dir / "bench_output.vtkhdf"
                                   : dir / fmt::format("bench_output_{}_{}.vtu", enc.name, rank);
      MPI_Barrier(MPI_COMM_WORLD);
      const double c0 = cpu_seconds();
      const auto w0 = std::chrono::steady_clock::now();
      if (enc.vtkhdf)
        tc::io::write_vtkhdf(file, frame.mesh, mine, frame.point, frame.cell, MPI_COMM_WORLD);
      else if (size == 1)
        tc::io::write_vtu(file, frame.mesh, frame.point, frame.cell, enc.vtu);
      else
        tc::io::write_vtu_piece(file, frame.mesh, mine, frame.point, frame.cell, enc.vtu);
      wall[e].push_back(
          largest(std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count()));
      cpu[e].push_back(largest(cpu_seconds() - c0));
      MPI_Barrier(MPI_COMM_WORLD);
      double bytes =
          enc.vtkhdf && rank != 0 ? 0.0 : static_cast<double>(std::filesystem::file_size(file));
      MPI_Allreduce(MPI_IN_PLACE, &bytes, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
      size_mb[e] = bytes / 1e6;
      MPI_Barrier(MPI_COMM_WORLD);
      if (!enc.vtkhdf || rank == 0) std::filesystem::remove(file);
    }
  if (rank == 0)
    for (size_t e = 0; e < n; ++e)
      fmt::print(
          "{:7} {:10.3f} MB  cpu {:.3f} s  wall {:.3f} s  (size {:.3f}x, cpu {:.3f}x, wall "
          "{:.3f}x of ascii)\n",
          encodings[e].name, size_mb[e], median(cpu[e]), median(wall[e]), size_mb[e] / size_mb[0],
          median(cpu[e]) / median(cpu[0]), median(wall[e]) / median(wall[0]));
  MPI_Finalize();
  return 0;
}
