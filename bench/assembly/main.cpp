// bench/assembly: for 3D boxes of growing size, the time to assemble K_u and M_u, the time
// and memory to factorise 4/τ²M_u + K_u, and the time per solve; growth exponents by a
// least-squares fit of log(time) against log(dofs). Prints a Markdown table. With --iterative
// also conjugate gradients preconditioned by PETSc's smoothed-aggregation multigrid (GAMG,
// the rigid-body modes as its near null space) on the same operator and right-hand side: the
// preconditioner's set-up, the iterations to 1e-8 of ‖b‖ from zero, a solve (the second,
// after what the first sets up), their memory (RSS: run with --no-direct for it) —
// what an iterative body solver would cost against the factorisation (issue 22's choice of
// the path at 10⁶ dofs). --no-direct skips the factorisation (sizes it cannot fit).
//
// --element T boxes of T cells (Hex8 by default; Hex20, Hex27, Tet4, Tet10: issue 37's
// assembly time per dof of order 2 against order 1).
//
//   build/bin/bench_assembly [cells per axis ...] [--iterative] [--no-direct] [--element T]
//                            [-tc_factor_package mumps|cholmod]
#include <fmt/format.h>
#include <petscksp.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "../support/growth.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/linalg/cholesky_solver.hpp"
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
  double t_gamg_setup = 0, mem_gamg = 0, t_cg = 0;
  int cg_iterations = 0;
};

/// A copy of a with block size 3 (GAMG aggregates nodes, not dofs), same entries.
tc::core::Handle<::Mat, MatDestroy> with_blocks(const tc::core::SparseMatrix& a) {
  const PetscInt n = a.rows();
  std::vector<PetscInt> nnz(static_cast<size_t>(n));
  for (PetscInt r = 0; r < n; ++r) {
    PetscInt nz = 0;
    TC_PETSC(MatGetRow(a.get(), r, &nz, nullptr, nullptr));
    nnz[static_cast<size_t>(r)] = nz;
    TC_PETSC(MatRestoreRow(a.get(), r, &nz, nullptr, nullptr));
  }
  tc::core::Handle<::Mat, MatDestroy> b;
  TC_PETSC(MatCreate(PETSC_COMM_SELF, b.out()));
  TC_PETSC(MatSetSizes(b.get(), n, n, n, n));
  TC_PETSC(MatSetBlockSize(b.get(), 3));
  TC_PETSC(MatSetType(b.get(), MATSEQAIJ));
  TC_PETSC(MatSeqAIJSetPreallocation(b.get(), 0, nnz.data()));
  for (PetscInt r = 0; r < n; ++r) {
    PetscInt nz = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    TC_PETSC(MatGetRow(a.get(), r, &nz, &cols, &vals));
    TC_PETSC(MatSetValues(b.get(), 1, &r, nz, cols, vals, INSERT_VALUES));
    TC_PETSC(MatRestoreRow(a.get(), r, &nz, &cols, &vals));
  }
  TC_PETSC(MatAssemblyBegin(b.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(b.get(), MAT_FINAL_ASSEMBLY));
  return b;
}

/// CG + GAMG on a (block size 3, rigid-body modes of the mesh's points as the near null
/// space) from x = 0 to ‖r‖ ≤ 1e-8‖b‖ (unpreconditioned norm, as a direct solve's accuracy
/// is judged): set-up time and memory, solve time, iterations into r.
void gamg_solve(const tc::core::SparseMatrix& a0, const tc::mesh::Mesh& mesh,
                const tc::core::Vector& b, Row& r) {
  const auto a = with_blocks(a0);
  tc::core::Handle<::Vec, VecDestroy> coords;
  TC_PETSC(VecCreateSeq(PETSC_COMM_SELF, 3 * mesh.n_nodes(), coords.out()));
  TC_PETSC(VecSetBlockSize(coords.get(), 3));
  PetscScalar* c = nullptr;
  TC_PETSC(VecGetArray(coords.get(), &c));
  for (int i = 0; i < mesh.n_nodes(); ++i)
    for (int d = 0; d < 3; ++d) c[3 * i + d] = mesh.point(i)[d];
  TC_PETSC(VecRestoreArray(coords.get(), &c));
  tc::core::Handle<::MatNullSpace, MatNullSpaceDestroy> rigid;
  TC_PETSC(MatNullSpaceCreateRigidBody(coords.get(), rigid.out()));
  TC_PETSC(MatSetNearNullSpace(a.get(), rigid.get()));
  tc::core::Handle<::KSP, KSPDestroy> ksp;
  TC_PETSC(KSPCreate(PETSC_COMM_SELF, ksp.out()));
  TC_PETSC(KSPSetOperators(ksp.get(), a.get(), a.get()));
  TC_PETSC(KSPSetType(ksp.get(), KSPCG));
  TC_PETSC(KSPSetNormType(ksp.get(), KSP_NORM_UNPRECONDITIONED));
  TC_PETSC(KSPSetTolerances(ksp.get(), 1e-8, PETSC_DEFAULT, PETSC_DEFAULT, 10000));
  ::PC pc = nullptr;
  TC_PETSC(KSPGetPC(ksp.get(), &pc));
  TC_PETSC(PCSetType(pc, PCGAMG));
  TC_PETSC(KSPSetFromOptions(ksp.get()));  // -pc_gamg_… and -mg_levels_… to vary it
  const double mem0 = rss_mib();
  auto t0 = Clock::now();
  TC_PETSC(KSPSetUp(ksp.get()));
  TC_PETSC(PCSetUp(pc));
  r.t_gamg_setup = since(t0);
  r.mem_gamg = rss_mib() - mem0;
  tc::core::Vector x(a0.rows());
  TC_PETSC(KSPSolve(ksp.get(), b.get(), x.get()));  // the smoothers' first application sets
  x.zero();                                         // up what PCSetUp left (eigenvalue
  t0 = Clock::now();                                // estimates): time the second solve
  TC_PETSC(KSPSolve(ksp.get(), b.get(), x.get()));
  r.t_cg = since(t0);
  PetscInt its = 0;
  TC_PETSC(KSPGetIterationNumber(ksp.get(), &its));
  KSPConvergedReason reason;
  TC_PETSC(KSPGetConvergedReason(ksp.get(), &reason));
  if (reason < 0)
    fmt::print(stderr, "CG + GAMG did not converge: {}\n", KSPConvergedReasons[reason]);
  r.cg_iterations = static_cast<int>(its);
}

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
  bool iterative = false, direct = true;
  auto element = tc::mesh::CellType::Hex8;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--element" && i + 1 < argc) {
      const std::string name = argv[++i];
      for (const auto t :
           {tc::mesh::CellType::Hex8, tc::mesh::CellType::Hex20, tc::mesh::CellType::Hex27,
            tc::mesh::CellType::Tet4, tc::mesh::CellType::Tet10})
        if (name == tc::mesh::name(t)) element = t;
    } else if (std::string(argv[i]) == "--iterative") {
      iterative = true;
    } else if (std::string(argv[i]) == "--no-direct") {
      direct = false;
    } else if (argv[i][0] == '-') {
      petsc_args.push_back(argv[i]);
      if (i + 1 < argc && argv[i + 1][0] != '-') petsc_args.push_back(argv[++i]);
    } else {
      sizes.push_back(std::stoi(argv[i]));
    }
  }
  if (sizes.empty()) sizes = {14, 31, 48};
  int pargc = static_cast<int>(petsc_args.size());
  petsc_args.push_back(nullptr);  // argv[argc] = NULL, as MPI_Init expects
  char** pargv = petsc_args.data();
  tc::core::PetscSession session(&pargc, &pargv);

  tc::fem::Material steel;
  steel.density = 7850, steel.young_modulus = 2e11, steel.poisson_ratio = 0.3;
  steel.thermal_expansion = 1.2e-5, steel.specific_heat = 450, steel.thermal_conductivity = 50;
  const double tau = 1e-3;

  std::vector<Row> rows;
  std::string package;
  for (const int n : sizes) {
    const auto mesh = tc::mesh::make_box(3, {0, 0, 0}, {1, 1, 1}, {n, n, n}, element);
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
    tc::core::Vector b(a.rows()), x(a.rows());
    b.fill(1.0);
    if (direct) {
      const double mem0 = rss_mib();
      t0 = Clock::now();
      tc::linalg::CholeskySolver chol(a);
      r.t_factor = since(t0);
      r.mem_factor = rss_mib() - mem0;
      package = chol.package();
      const int n_solves = 5;
      t0 = Clock::now();
      for (int s = 0; s < n_solves; ++s) chol.solve(b, x);
      r.t_solve = since(t0) / n_solves;
    }
    if (iterative) gamg_solve(a, mesh, b, r);
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
  if (rows.size() >= 2 && direct)
    fmt::print("| growth exponent | | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} |\n",
               slope(rows, &Row::t_k), slope(rows, &Row::t_m), slope(rows, &Row::t_factor),
               slope(rows, &Row::mem_factor), slope(rows, &Row::t_solve));
  if (!iterative) return 0;
  fmt::print(
      "\nCG + GAMG (rigid-body near null space), ‖r‖ ≤ 1e-8‖b‖ from 0:\n\n| cells | dofs | "
      "GAMG set-up [s] | its memory [MiB] | CG iterations | solve [s] | solve / direct solve "
      "|\n|---|---|---|---|---|---|---|\n");
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    fmt::print("| {}³ | {:.0f} | {:.2f} | {:.0f} | {} | {:.3f} | {} |\n", sizes[i], r.dofs,
               r.t_gamg_setup, r.mem_gamg, r.cg_iterations, r.t_cg,
               direct ? fmt::format("{:.1f}", r.t_cg / r.t_solve) : std::string("–"));
  }
  if (rows.size() >= 2)
    fmt::print("| growth exponent | | {:.2f} | {:.2f} | | {:.2f} | |\n",
               slope(rows, &Row::t_gamg_setup), slope(rows, &Row::mem_gamg),
               slope(rows, &Row::t_cg));
  return 0;
}
