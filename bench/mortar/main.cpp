// bench/mortar: MortarPair::update() on 3D non-matching interfaces of growing size, the time
// per slave face, the growth exponent of the total time (least-squares slope of log(time)
// against log(slave faces)) and the share of the stages (search, geometry + clipping,
// integration, assembly). Prints a Markdown table.
//
//   build/bin/bench_mortar [slave faces per axis ...] [--standard] [--element T]
//
// The slave is the bottom of [0, 1]² × [0, 0.05] with n × n faces, the master the top of
// [−0.013, 1.011]² × [−0.05, 0] with about 0.77 n × 0.77 n faces; the interface nodes of both
// are jittered in-plane by 20 % of their spacing (general quadrilaterals, no alignment), and
// the slave is lowered by 0.1 % of a face into the master (a closed contact, every face active).
// --element Hex20 | Hex27 | Tet10 | Tet4: both boxes of T cells on the jittered corners (issue
// 37: mortar time per contact node of order 2 against order 1).
// --curved R: every node of both boxes (second-order ones included) mapped onto the sphere of
// radius R, (x, y, z) ↦ radius R + z, longitude (x − ½)/R, latitude (y − ½)/R, so the
// second-order faces' edges are curved (clipped on sub-facets unless --divisions 1).
// --divisions N: MortarOptions::curved_face_divisions.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../support/growth.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/mesh/box.hpp"
#include "tc/mesh/reference_cell.hpp"
#include "tc/mesh/second_order.hpp"

namespace {

using tc::contact::MortarPair;

/// The box with the nodes of `boundary` (not on its rim) moved in-plane by up to `amplitude`.
tc::mesh::Mesh jittered(const tc::mesh::Mesh& m, const std::string& boundary, double amplitude,
                        unsigned seed) {
  std::vector<char> on(m.n_nodes(), 0);
  for (const int j : m.boundary_nodes(boundary)) on[j] = 1;
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const auto& p : m.points())
    for (int i = 0; i < 2; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
  std::mt19937 rng(seed);
  tc::mesh::Mesh out(3);
  for (int j = 0; j < m.n_nodes(); ++j) {
    auto p = m.point(j);
    for (int i = 0; i < 2; ++i) {
      const double shift = amplitude * (2.0 * rng() / 4294967295.0 - 1.0);
      if (on[j] && p[i] > lo[i] + 1e-12 && p[i] < hi[i] - 1e-12) p[i] += shift;
    }
    out.add_point(p);
  }
  for (int c = 0; c < m.n_cells(); ++c) out.add_cell(m.cell_type(c), m.cell(c));
  for (const auto& name : m.boundary_names())
    for (const auto& f : m.boundary(name)) out.add_facet(name, f);
  return out;
}

/// The first-order box as cells of `element` on its corners.
tc::mesh::Mesh as_element(const tc::mesh::Mesh& box, tc::mesh::CellType element) {
  using tc::mesh::CellType;
  if (element == CellType::Hex8) return box;
  const CellType corners = tc::mesh::corner_type(element);
  tc::mesh::Mesh m = corners == CellType::Tet4 ? tc::mesh::split_into_simplices(box) : box;
  return tc::mesh::order(element) == 2 ? tc::mesh::to_second_order(m, element) : m;
}

/// The mesh with every node mapped onto the sphere of radius r (see --curved above).
tc::mesh::Mesh on_sphere(const tc::mesh::Mesh& m, double r) {
  tc::mesh::Mesh out(3);
  for (const auto& p : m.points()) {
    const double rho = r + p[2], lon = (p[0] - 0.5) / r, lat = (p[1] - 0.5) / r;
    out.add_point({rho * std::cos(lat) * std::cos(lon), rho * std::cos(lat) * std::sin(lon),
                   rho * std::sin(lat)});
  }
  for (int c = 0; c < m.n_cells(); ++c) out.add_cell(m.cell_type(c), m.cell(c));
  for (const auto& name : m.boundary_names())
    for (const auto& f : m.boundary(name)) out.add_facet(name, f);
  return out;
}

struct Row {
  int faces = 0, contact_nodes = 0, segments = 0, repeats = 0;
  double time = 0;  // per update
  tc::contact::MortarTimings t;
};

double slope(const std::vector<Row>& rows) {
  std::vector<double> faces, time;
  for (const auto& r : rows) {
    faces.push_back(static_cast<double>(r.faces));
    time.push_back(r.time);
  }
  return tc::bench::growth_exponent(faces, time);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  tc::contact::MortarOptions options;
  std::vector<char*> petsc_args{argv[0]};
  auto element = tc::mesh::CellType::Hex8;
  double curved = 0;  // sphere radius, 0 = flat
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--standard") == 0)
      options.basis = tc::contact::MultiplierBasis::standard;
    else if (std::strcmp(argv[i], "--curved") == 0 && i + 1 < argc)
      curved = std::stod(argv[++i]);
    else if (std::strcmp(argv[i], "--divisions") == 0 && i + 1 < argc)
      options.curved_face_divisions = std::stoi(argv[++i]);
    else if (std::strcmp(argv[i], "--element") == 0 && i + 1 < argc) {
      const std::string name = argv[++i];
      for (const auto t :
           {tc::mesh::CellType::Hex8, tc::mesh::CellType::Hex20, tc::mesh::CellType::Hex27,
            tc::mesh::CellType::Tet4, tc::mesh::CellType::Tet10})
        if (name == tc::mesh::name(t)) element = t;
    } else if (argv[i][0] == '-')
      petsc_args.push_back(argv[i]);
    else
      sizes.push_back(std::stoi(argv[i]));
  }
  if (sizes.empty()) sizes = {10, 32, 100, 316};
  int pargc = static_cast<int>(petsc_args.size());
  petsc_args.push_back(nullptr);  // argv[argc] = NULL, as MPI_Init expects
  char** pargv = petsc_args.data();
  tc::core::PetscSession session(&pargc, &pargv);

  std::vector<Row> rows;
  for (const int n : sizes) {
    const int nm = std::max(2, static_cast<int>(std::lround(0.77 * n)));
    const double h = 1.0 / n, hm = 1.024 / nm;
    auto slave =
        as_element(jittered(tc::mesh::make_box(3, {0, 0, -1e-3 * h}, {1, 1, 0.05}, {n, n, 1}),
                            "zmin", 0.2 * h, 1),
                   element);
    auto master = as_element(
        jittered(tc::mesh::make_box(3, {-0.013, -0.013, -0.05}, {1.011, 1.011, 0}, {nm, nm, 1}),
                 "zmax", 0.2 * hm, 2),
        element);
    if (curved > 0) {
      slave = on_sphere(slave, curved);
      master = on_sphere(master, curved);
    }
    MortarPair pair(slave, "zmin", master, "zmax", options);
    const std::vector<double> us(3 * slave.n_nodes(), 0.0), um(3 * master.n_nodes(), 0.0);
    Row r;
    r.faces = n * n;
    r.repeats = std::max(3, 20000 / r.faces);  // ≥ 0.5 s of work per size
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < r.repeats; ++k) {
      pair.update(us, um);
      const auto& t = pair.timings();
      r.t.search += t.search, r.t.geometry += t.geometry;
      r.t.integration += t.integration, r.t.assembly += t.assembly;
    }
    r.time =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / r.repeats;
    r.contact_nodes = static_cast<int>(pair.contact_nodes().size());
    r.segments = static_cast<int>(pair.segments().size());
    rows.push_back(r);
    fmt::print(stderr, "{} slave faces: {:.3e} s per update\n", r.faces, r.time);
  }

  fmt::print("basis: {}, element: {}, {}\n\n", tc::contact::name(options.basis),
             tc::mesh::name(element),
             curved > 0 ? fmt::format("on a sphere of radius {}, {} division(s) per curved edge",
                                      curved, options.curved_face_divisions)
                        : std::string("flat"));
  fmt::print(
      "| slave faces | master faces | segments | contact nodes | update [s] | per slave face [µs] "
      "| per contact node [µs] | search | geometry + clipping | integration | assembly |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const int nm = std::max(2, static_cast<int>(std::lround(0.77 * sizes[i])));
    const double all = r.t.search + r.t.geometry + r.t.integration + r.t.assembly;
    fmt::print(
        "| {} | {} | {} | {} | {:.4f} | {:.2f} | {:.2f} | {:.0f} % | {:.0f} % | {:.0f} % | {:.0f} "
        "% "
        "|\n",
        r.faces, nm * nm, r.segments, r.contact_nodes, r.time, 1e6 * r.time / r.faces,
        1e6 * r.time / r.contact_nodes, 100 * r.t.search / all, 100 * r.t.geometry / all,
        100 * r.t.integration / all, 100 * r.t.assembly / all);
  }
  if (rows.size() >= 2) fmt::print("\ngrowth exponent of update(): {:.3f}\n", slope(rows));
  return 0;
}
