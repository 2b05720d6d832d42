#pragma once
// Random QPs min ½xᵀFx − xᵀd over the sets of the dual contact problem, with a known
// solution x* built first: F is SPD, x* and the gradient g* = Fx* − d satisfy the KKT
// conditions of the set by construction, then d = Fx* − g*. Everything is generated from
// the global index with a fixed seed, so 1 and N ranks build the same problem.
#include <mpi.h>

#include <cmath>
#include <random>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/qp/sets.hpp"

namespace tc::test {

/// The set of every block of components: free; λ ≥ 0; an interval [−r, r] (2D friction);
/// a disc of radius r (3D friction); or the 3D contact node [free, λ_n ≥ 0, disc].
enum class QpKind { free, lower, box, disc, contact3d };

inline int block_size(QpKind k) {
  switch (k) {
    case QpKind::disc:
      return 2;
    case QpKind::contact3d:
      return 4;
    default:
      return 1;
  }
}

struct QpProblem {
  core::Handle<::Mat, MatDestroy> f;
  core::Vector d, x_star, g_star;
  qp::FeasibleSet set;
  double kappa_bound = 0;      // λ_max/λ_min bound from Gershgorin and the shift
  std::vector<double> radius;  // per block of this rank: the interval's or disc's radius
};

/// n_blocks blocks of `kind`; F = graph Laplacian (random weights, links at fixed strides) +
/// shift, with λ_max ≤ 2·max weighted degree + shift and λ_min ≥ shift, so κ ≤ `kappa`.
/// `degenerate` is the fraction of active components whose multiplier is exactly zero.
inline QpProblem random_qp(MPI_Comm comm, PetscInt n_blocks, QpKind kind, double kappa,
                           double active_fraction, double degenerate, std::uint64_t seed) {
  const int bs = block_size(kind);
  const PetscInt n = n_blocks * bs;
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const PetscInt blocks_begin = n_blocks * rank / size, blocks_end = n_blocks * (rank + 1) / size;
  const PetscInt begin = blocks_begin * bs, end = blocks_end * bs;

  // The solution and the gradient at it, per block, from one global random stream.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<double> x(n), g(n), radius(n_blocks, 0.0);
  auto active = [&] { return u01(rng) < active_fraction; };
  auto multiplier = [&] { return u01(rng) < degenerate ? 0.0 : 0.1 + u01(rng); };
  auto disc = [&](PetscInt i, double r) {  // x[i], x[i+1] in the disc of radius r
    const double phi = 2 * M_PI * u01(rng);
    if (r == 0) {
      x[i] = x[i + 1] = 0;  // the centre: any gradient is a KKT gradient
      g[i] = u01(rng) - 0.5;
      g[i + 1] = u01(rng) - 0.5;
    } else if (active()) {  // on the circle, −g along the outward normal
      const double mu = multiplier();
      x[i] = r * std::cos(phi), x[i + 1] = r * std::sin(phi);
      g[i] = -mu * std::cos(phi), g[i + 1] = -mu * std::sin(phi);
    } else {
      const double rho = 0.9 * r * u01(rng);
      x[i] = rho * std::cos(phi), x[i + 1] = rho * std::sin(phi);
      g[i] = g[i + 1] = 0;
    }
  };
  for (PetscInt b = 0; b < n_blocks; ++b) {
    const PetscInt i = b * bs;
    switch (kind) {
      case QpKind::free:
        x[i] = 2 * u01(rng) - 1, g[i] = 0;
        break;
      case QpKind::lower:
        if (active())
          x[i] = 0, g[i] = multiplier();
        else
          x[i] = 0.1 + u01(rng), g[i] = 0;
        break;
      case QpKind::box: {
        const double r = radius[b] = 0.5 + u01(rng);
        if (active()) {
          const bool up = u01(rng) < 0.5;
          x[i] = up ? r : -r;
          g[i] = (up ? -1 : 1) * multiplier();
        } else {
          x[i] = (2 * u01(rng) - 1) * 0.9 * r, g[i] = 0;
        }
        break;
      }
      case QpKind::disc:
        radius[b] = u01(rng) < 0.05 ? 0.0 : 0.5 + u01(rng);
        disc(i, radius[b]);
        break;
      case QpKind::contact3d:
        x[i] = 2 * u01(rng) - 1, g[i] = 0;  // a Dirichlet (free) multiplier
        if (active())
          x[i + 1] = 0, g[i + 1] = multiplier();
        else
          x[i + 1] = 0.1 + u01(rng), g[i + 1] = 0;
        radius[b] = x[i + 1] == 0 ? 0.0 : 0.9 * x[i + 1];  // Tresca bound 𝔉γ with 𝔉 = 0.9
        disc(i + 2, radius[b]);
        break;
    }
  }

  // F: links of node i to i + s for a few strides s, random weights in (0.1, 1.1).
  const std::vector<PetscInt> strides{1, 2, 7, 31};
  std::mt19937_64 wrng(seed ^ 0x5bd1e995ULL);
  std::vector<std::vector<std::pair<PetscInt, double>>> rows(n);
  std::vector<double> degree(n, 0.0);
  for (PetscInt i = 0; i < n; ++i)
    for (const PetscInt s : strides) {
      if (i + s >= n) continue;
      const double w = 0.1 + std::uniform_real_distribution<double>(0, 1)(wrng);
      rows[i].push_back({i + s, -w});
      rows[i + s].push_back({i, -w});
      degree[i] += w, degree[i + s] += w;
    }
  double max_degree = 0;
  for (const double dg : degree) max_degree = std::max(max_degree, dg);
  const double shift = 2 * max_degree / (kappa - 1);

  QpProblem p{{}, {}, {}, {}, qp::FeasibleSet(core::Vector(0)), 0, {}};
  p.radius.assign(radius.begin() + blocks_begin, radius.begin() + blocks_end);
  TC_PETSC(MatCreateAIJ(comm, end - begin, end - begin, n, n, 1 + 2 * strides.size(), nullptr,
                        2 * strides.size(), nullptr, p.f.out()));
  for (PetscInt i = begin; i < end; ++i) {
    const double diag = degree[i] + shift;
    TC_PETSC(MatSetValue(p.f.get(), i, i, diag, INSERT_VALUES));
    for (const auto& [j, v] : rows[i]) TC_PETSC(MatSetValue(p.f.get(), i, j, v, INSERT_VALUES));
  }
  TC_PETSC(MatAssemblyBegin(p.f.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(p.f.get(), MAT_FINAL_ASSEMBLY));
  p.kappa_bound = (2 * max_degree + shift) / shift;

  p.x_star = core::Vector::distributed(comm, end - begin);
  p.g_star = p.x_star.duplicate();
  {
    auto xv = p.x_star.view();
    auto gv = p.g_star.view();
    for (PetscInt i = begin; i < end; ++i) xv[i - begin] = x[i], gv[i - begin] = g[i];
  }
  p.d = p.x_star.duplicate();
  TC_PETSC(MatMult(p.f.get(), p.x_star.get(), p.d.get()));
  p.d.axpy(-1.0, p.g_star);

  p.set = qp::FeasibleSet(p.x_star);
  for (PetscInt b = blocks_begin; b < blocks_end; ++b) {
    const PetscInt l = (b - blocks_begin) * bs;
    switch (kind) {
      case QpKind::free:
        break;
      case QpKind::lower:
        p.set.set_interval(l, {0.0, qp::infinity});
        break;
      case QpKind::box:
        p.set.set_interval(l, {-radius[b], radius[b]});
        break;
      case QpKind::disc:
        p.set.add_disc({l, l + 1, {radius[b]}});
        break;
      case QpKind::contact3d:
        p.set.set_interval(l + 1, {0.0, qp::infinity});
        p.set.add_disc({l + 2, l + 3, {radius[b]}});
        break;
    }
  }
  return p;
}

/// The 3D contact instance of random_qp, made ill-conditioned for bench/qp and the MPGP
/// disc tests (per node: a free multiplier, λ_n ≥ 0 and a friction
/// disc of radius 0.9 λ_n*) with κ(F₀) ≤ 10, scaled like scaled_qp but with one factor per
/// node, so that a disc stays a disc (of radius r/D_b) and the bound at 0 stays at 0.
inline QpProblem scaled_disc_qp(long nodes, double kappa, double active, std::uint64_t seed) {
  auto p = random_qp(PETSC_COMM_SELF, nodes, QpKind::contact3d, 10.0, active, 0.0, seed);
  core::Vector scale = p.d.duplicate();
  std::vector<double> node_scale(static_cast<size_t>(nodes));
  {
    std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
    std::uniform_real_distribution<double> u(0.0, 0.5 * std::log10(kappa / 10.0));
    auto v = scale.view();
    for (long b = 0; b < nodes; ++b) {
      node_scale[b] = std::pow(10.0, u(rng));
      for (int k = 0; k < 4; ++k) v[4 * b + k] = node_scale[b];
    }
  }
  TC_PETSC(MatDiagonalScale(p.f.get(), scale.get(), scale.get()));
  TC_PETSC(VecPointwiseDivide(p.x_star.get(), p.x_star.get(), scale.get()));
  TC_PETSC(VecPointwiseMult(p.g_star.get(), p.g_star.get(), scale.get()));
  TC_PETSC(MatMult(p.f.get(), p.x_star.get(), p.d.get()));
  p.d.axpy(-1.0, p.g_star);
  p.set = qp::FeasibleSet(p.d);
  for (long b = 0; b < nodes; ++b) {
    p.set.set_interval(static_cast<PetscInt>(4 * b + 1), {0.0, qp::infinity});
    const auto i = static_cast<PetscInt>(4 * b);
    p.set.add_disc({i + 2, i + 3, {p.radius[b] / node_scale[b]}});
  }
  p.kappa_bound *= kappa / 10.0;
  return p;
}

}  // namespace tc::test
