// bench/assembly: for 3D boxes of growing size, the time to assemble K_u and M_u, the time
// and memory to factorise 4/τ²M_u + K_u, and the time per solve; growth exponents by a
// least-squares fit of log(time) against log(dofs). Prints a Markdown table.
//
//   build/bin/bench_assembly [cells per axis ...] [-tc_factor_package mumps|cholmod]
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "../support/growth.hpp"
#include "tc/core/petsc.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/mesh/box.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Resident memory of this process [MiB] (VmRSS): counts what the factorisation packages
/// allocate outside PETSc's own accounting.
double rss_mib() {
  std::ifstream in("/proc/self/status");
  std::string key;
  while (in >> key) {
    if (key == "VmRSS:") {
      double kb = 0;
      in >> kb;
      return kb / 1024.0;
    }
    in.ignore(1 << 12, '\n');
  }
  return 0;
}

struct Row {
  double dofs, t_k, t_m, t_factor, mem_factor, t_solve;
};

double slope(const std::vector<Row>& rows, double Row::*field) {
  std::vector<double> dofs, cost;
  for (const auto& r : rows) {
    dofs.push_back(r.dofs);
    cost.push_back(r.*field);
  }
  return tc::bench::growth_exponent(dofs, cost);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  std::vector<char*> petsc_args{argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] == '-') {
      petsc_args.push_back(argv[i]);
      if (i + 1 < argc && argv[i + 1][0] != '-') petsc_args.push_back(argv[++i]);
    } else {
      sizes.push_back(std::stoi(argv[i]));
    }
  }
  if (sizes.empty()) sizes = {14, 31, 48};
  int pargc = static_cast<int>(petsc_args.size());
  char** pargv = petsc_args.data();
  tc::core::PetscSession session(&pargc, &pargv);

  tc::fem::Material steel;
  steel.density = 7850, steel.young_modulus = 2e11, steel.poisson_ratio = 0.3;
  steel.thermal_expansion = 1.2e-5, steel.specific_heat = 450, steel.thermal_conductivity = 50;
  const double tau = 1e-3;

  std::vector<Row> rows;
  std::string package;
  for (const int n : sizes) {
    const auto mesh = tc::mesh::make_box(3, {0, 0, 0}, {1, 1, 1}, {n, n, n});
    const auto graph = tc::fem::node_graph(mesh);
    Row r{};
    r.dofs = 3.0 * mesh.n_nodes();
    auto t0 = Clock::now();
    auto k = tc::fem::assemble(mesh, graph, 3, 3, [&](int, auto type, const auto& x) {
      return tc::fem::stiffness_u(type, x, steel.lame_lambda(), steel.lame_mu());
    });
    r.t_k = since(t0);
    t0 = Clock::now();
    auto m = tc::fem::assemble(mesh, graph, 3, 3, [&](int, auto type, const auto& x) {
      return tc::fem::mass_u(type, x, steel.density);
    });
    r.t_m = since(t0);
    auto a = k.copy();
    a.axpy(4.0 / (tau * tau), m);
    const double mem0 = rss_mib();
    t0 = Clock::now();
    tc::core::CholeskySolver chol(a);
    r.t_factor = since(t0);
    r.mem_factor = rss_mib() - mem0;
    package = chol.package();
    tc::core::Vector b(a.rows()), x(a.rows());
    b.fill(1.0);
    const int n_solves = 5;
    t0 = Clock::now();
    for (int s = 0; s < n_solves; ++s) chol.solve(b, x);
    r.t_solve = since(t0) / n_solves;
    rows.push_back(r);
    fmt::print(stderr, "n = {}: {:.0f} dofs done\n", n, r.dofs);
  }

  fmt::print("factorisation package: {}\n\n", package);
  fmt::print(
      "| cells | dofs | assemble K_u [s] | assemble M_u [s] | factorise [s] | factor memory [MiB] "
      "| solve [s] |\n|---|---|---|---|---|---|---|\n");
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    fmt::print("| {}³ | {:.0f} | {:.3f} | {:.3f} | {:.2f} | {:.0f} | {:.4f} |\n", sizes[i], r.dofs,
               r.t_k, r.t_m, r.t_factor, r.mem_factor, r.t_solve);
  }
  if (rows.size() >= 2)
    fmt::print("| growth exponent | | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} |\n",
               slope(rows, &Row::t_k), slope(rows, &Row::t_m), slope(rows, &Row::t_factor),
               slope(rows, &Row::mem_factor), slope(rows, &Row::t_solve));
  return 0;
}
