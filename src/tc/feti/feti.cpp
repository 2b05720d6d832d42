#include "tc/feti/feti.hpp"

#include <fmt/format.h>

#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "tc/core/error.hpp"
#include "tc/core/numeric/collective.hpp"
#include "tc/feti/subdomain.hpp"
#include "tc/linalg/cholesky_solver.hpp"

namespace tc::feti {

const char* name(Preconditioner p) {
  switch (p) {
    case Preconditioner::none:
      return "none";
    case Preconditioner::lumped:
      return "lumped";
    case Preconditioner::dirichlet:
      return "dirichlet";
  }
  return "?";
}

Feti::Feti(const std::vector<mesh::SubMesh>& subdomains, int n_nodes, int block,
           std::vector<PetscInt> dirichlet_dofs, Kernel kernel, Singular singular,
           const std::function<core::SparseMatrix(int s)>& local_matrix, FetiOptions options)
    : block_(block), options_(std::move(options)), singular_(singular == Singular::yes) {
  if (!singular_ && !options_.deflation) kernel = Kernel::none;
  const int n_sub = static_cast<int>(subdomains.size());
  int rank = 0, size = 1;
  if (MPI_Comm_rank(options_.comm, &rank) != MPI_SUCCESS ||
      MPI_Comm_size(options_.comm, &size) != MPI_SUCCESS)
    throw Error("FETI: MPI_Comm_rank/MPI_Comm_size failed");
  first_owned_ = first_subdomain(n_sub, rank, size);
  last_owned_ = first_subdomain(n_sub, rank + 1, size);
  for (int s = 0; s < n_sub; ++s) {
    auto sub = std::make_unique<Subdomain>();
    for (const int g : subdomains[static_cast<size_t>(s)].global_node)
      for (int k = 0; k < block_; ++k) sub->global_dof.push_back(block_ * g + k);
    sub->owned = s >= first_owned_ && s < last_owned_;
    subs_.push_back(std::move(sub));
  }
  std::sort(dirichlet_dofs.begin(), dirichlet_dofs.end());
  dirichlet_dofs_ = dirichlet_dofs;
  build_rows(n_nodes, dirichlet_dofs);
  build_distribution();
  build_kernels(subdomains, kernel);
  if (singular_) build_coarse();
  // Rank-local: a subdomain that fails to assemble or factorise on one rank stops every rank
  // (with the rank named) instead of leaving the others in the next MPI_Allreduce.
  core::collective_check(options_.comm, "FETI subdomain assembly and factorisation", [&] {
    for (int s = first_owned_; s < last_owned_; ++s) {
      auto& sub = *subs_[static_cast<size_t>(s)];
      sub.a = local_matrix(s);
      if (sub.a.rows() != sub.n())
        throw Error(fmt::format("FETI: subdomain {} matrix has {} rows, expected {}", s,
                                sub.a.rows(), sub.n()));
      if (s == first_owned_ && core::injected_failure("factorisation"))
        throw PetscError(PETSC_ERR_MAT_CH_ZRPVT,
                         fmt::format("FETI: the factorisation of subdomain {} failed (injected "
                                     "by -tc_fail_on_rank)",
                                     s));
      const double diag = core::mean_diagonal(sub.a);
      auto reduced = sub.a.copy();
      reduced.zero_rows_columns(sub.fixing, diag);
      sub.factor = linalg::CholeskySolver(reduced, options_.package);
      package_ = sub.factor.package();
      if (options_.preconditioner == Preconditioner::dirichlet) {
        for (const auto& e : sub.b) sub.boundary.push_back(e.dof);
        std::sort(sub.boundary.begin(), sub.boundary.end());
        sub.boundary.erase(std::unique(sub.boundary.begin(), sub.boundary.end()),
                           sub.boundary.end());
        auto inner = sub.a.copy();
        inner.zero_rows_columns(sub.boundary, diag);
        sub.interior = linalg::CholeskySolver(inner, options_.package);
      }
    }
  });
  if (core::injected_failure("solve")) {
    // After -tc_fail_after_solves solves of this operator (default 0): a failure in the run.
    PetscBool set = PETSC_FALSE;
    fail_after_ = 0;
    TC_PETSC(PetscOptionsGetInt(nullptr, nullptr, "-tc_fail_after_solves", &fail_after_, &set));
  }
  if (!singular_) build_deflation();
}

Feti::~Feti() = default;

void Feti::build_rows(int n_nodes, const std::vector<PetscInt>& dirichlet) {
  // Copies of every body node: (subdomain, local node), in subdomain order.
  std::vector<std::vector<std::pair<int, PetscInt>>> copies(static_cast<size_t>(n_nodes));
  for (int s = 0; s < n_subdomains(); ++s) {
    const auto& sub = *subs_[static_cast<size_t>(s)];
    for (PetscInt a = 0; a < sub.n() / block_; ++a)
      copies[static_cast<size_t>(sub.global_dof[static_cast<size_t>(block_ * a)] / block_)]
          .emplace_back(s, a);
  }
  owner_.assign(static_cast<size_t>(n_nodes), -1);
  Eigen::Index row = 0;
  auto add = [&](int s, PetscInt dof, double v) {
    subs_[static_cast<size_t>(s)]->b.push_back({row, dof, v});
  };
  // Gluing rows first ([gluing | Dirichlet], conventions), Dirichlet components excluded:
  // their copies are each pinned by a Dirichlet row, which already makes them agree.
  for (int node = 0; node < n_nodes; ++node) {
    const auto& c = copies[static_cast<size_t>(node)];
    if (c.empty()) throw Error(fmt::format("FETI: node {} belongs to no subdomain", node));
    owner_[static_cast<size_t>(node)] = c.front().first;
    const auto mult = static_cast<int>(c.size());
    for (int k = 0; k < block_; ++k) {
      if (std::binary_search(dirichlet.begin(), dirichlet.end(), block_ * node + k)) continue;
      for (int j = 1; j < mult; ++j, ++row) {
        if (options_.orthonormal_gluing) {
          // Helmert basis of {v : Σv = 0}: (1,…,1, −j, 0,…)/√(j(j+1)), orthonormal rows.
          const double h = 1.0 / std::sqrt(static_cast<double>(j) * (j + 1));
          for (int i = 0; i < j; ++i)
            add(c[static_cast<size_t>(i)].first, block_ * c[static_cast<size_t>(i)].second + k, h);
          add(c[static_cast<size_t>(j)].first, block_ * c[static_cast<size_t>(j)].second + k,
              -j * h);
        } else {
          add(c[static_cast<size_t>(j - 1)].first,
              block_ * c[static_cast<size_t>(j - 1)].second + k, 1.0);
          add(c[static_cast<size_t>(j)].first, block_ * c[static_cast<size_t>(j)].second + k, -1.0);
        }
      }
    }
  }
  m_gluing_ = row;
  for (const PetscInt dof : dirichlet) {
    for (const auto& [s, a] : copies[static_cast<size_t>(dof / block_)]) {
      add(s, block_ * a + dof % block_, 1.0);
      dirichlet_row_dof_.push_back(dof);
      ++row;
    }
  }
  m_ = row;
}

void Feti::build_kernels(const std::vector<mesh::SubMesh>& subdomains, Kernel kernel) {
  n_kernel_ = 0;
  for (int s = 0; s < n_subdomains(); ++s) {
    auto& sub = *subs_[static_cast<size_t>(s)];
    const auto& mesh = subdomains[static_cast<size_t>(s)].mesh;
    const PetscInt n = sub.n();
    const int dim = mesh.dim();
    if (kernel == Kernel::none) {
      sub.r.resize(n, 0);
    } else if (kernel == Kernel::constant) {
      sub.r = Eigen::MatrixXd::Constant(n, 1, 1.0 / std::sqrt(static_cast<double>(n)));
    } else {
      if (block_ != dim) throw Error("FETI: rigid kernel needs dim dofs per node");
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (int a = 0; a < mesh.n_nodes(); ++a) centre += Eigen::Vector3d(mesh.point(a).data());
      centre /= mesh.n_nodes();
      const int k = dim == 2 ? 3 : 6;
      Eigen::MatrixXd r = Eigen::MatrixXd::Zero(n, k);
      for (int a = 0; a < mesh.n_nodes(); ++a) {
        const Eigen::Vector3d x = Eigen::Vector3d(mesh.point(a).data()) - centre;
        for (int i = 0; i < dim; ++i) r(dim * a + i, i) = 1.0;  // translations
        if (dim == 2) {
          r(2 * a, 2) = -x[1];  // rotation about z
          r(2 * a + 1, 2) = x[0];
        } else {  // rotations about x, y, z: ω × x
          r(3 * a + 1, 3) = -x[2], r(3 * a + 2, 3) = x[1];
          r(3 * a, 4) = x[2], r(3 * a + 2, 4) = -x[0];
          r(3 * a, 5) = -x[1], r(3 * a + 1, 5) = x[0];
        }
      }
      Eigen::HouseholderQR<Eigen::MatrixXd> qr(r);
      sub.r = qr.householderQ() * Eigen::MatrixXd::Identity(n, k);  // orthonormal columns
    }
    sub.kernel_offset = n_kernel_;
    n_kernel_ += sub.r.cols();
    if (singular_ && sub.r.cols() > 0) {
      // Fixing dofs: the rows of R that a pivoted QR of Rᵀ picks first span the kernel best,
      // so A with them eliminated is non-singular and well conditioned.
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> piv(sub.r.transpose());
      for (Eigen::Index j = 0; j < sub.r.cols(); ++j)
        sub.fixing.push_back(static_cast<PetscInt>(piv.colsPermutation().indices()[j]));
      std::sort(sub.fixing.begin(), sub.fixing.end());
    }
  }
}

void Feti::build_distribution() {
  const int n_sub = n_subdomains();
  int size = 1;
  if (MPI_Comm_size(options_.comm, &size) != MPI_SUCCESS) throw Error("FETI: MPI_Comm_size failed");
  std::vector<int> sub_rank(static_cast<size_t>(n_sub));
  for (int p = 0; p < size; ++p)
    for (int s = first_subdomain(n_sub, p, size); s < first_subdomain(n_sub, p + 1, size); ++s)
      sub_rank[static_cast<size_t>(s)] = p;
  // A row is owned by the rank of the lowest-numbered subdomain it touches (for a gluing row
  // the node's first copy, which carries its load). A row inside one rank's block of
  // subdomains then never travels; a row on an interface between two ranks travels once each
  // way per product, whichever of its users owns it.
  std::vector<int> row_rank(static_cast<size_t>(m_), size);
  std::vector<char> touched(static_cast<size_t>(m_), 0);
  for (int s = 0; s < n_sub; ++s)
    for (const auto& e : subs_[static_cast<size_t>(s)]->b) {
      auto& r = row_rank[static_cast<size_t>(e.row)];
      r = std::min(r, sub_rank[static_cast<size_t>(s)]);
      if (subs_[static_cast<size_t>(s)]->owned) touched[static_cast<size_t>(e.row)] = 1;
    }
  std::vector<Eigen::Index> leaf_rows, leaf_of(static_cast<size_t>(m_), -1);
  for (Eigen::Index r = 0; r < m_; ++r)
    if (touched[static_cast<size_t>(r)]) {
      leaf_of[static_cast<size_t>(r)] = static_cast<Eigen::Index>(leaf_rows.size());
      leaf_rows.push_back(r);
    }
  for (const auto& sub : subs_) {
    if (!sub->owned) continue;
    sub->leaf.clear();
    for (const auto& e : sub->b) sub->leaf.push_back(leaf_of[static_cast<size_t>(e.row)]);
  }
  rows_ = DualDistribution(options_.comm, row_rank, leaf_rows);
  // One SF call per column by default: 2–5× faster than a datatype of k doubles on row-major
  // copies for k = 16 and 64 (bench/RESULTS.md); the option is kept for measuring.
  PetscBool row_major = PETSC_FALSE;
  TC_PETSC(PetscOptionsGetBool(nullptr, nullptr, "-tc_feti_sf_row_major", &row_major, nullptr));
  rows_.set_transfer(row_major ? DualDistribution::Transfer::row_major
                               : DualDistribution::Transfer::per_column);
}

Eigen::SparseMatrix<double> Feti::build_g() {
  // G = Rᵀ Bᵀ: row j of subdomain s is Σ over the entries of B_s of R_s(dof, j)·value. The
  // whole G (replicated, as B is) makes GGᵀ the same on every rank; g_ keeps the columns of
  // the owned rows.
  std::vector<Eigen::Index> local(static_cast<size_t>(m_), -1);
  const auto& owned = rows_.owned_rows();
  for (size_t i = 0; i < owned.size(); ++i)
    local[static_cast<size_t>(owned[i])] = static_cast<Eigen::Index>(i);
  std::vector<Eigen::Triplet<double>> all, mine;
  for (const auto& sub : subs_)
    for (const auto& e : sub->b)
      for (Eigen::Index j = 0; j < sub->r.cols(); ++j) {
        const double v = e.value * sub->r(e.dof, j);
        all.emplace_back(sub->kernel_offset + j, e.row, v);
        if (const Eigen::Index l = local[static_cast<size_t>(e.row)]; l >= 0)
          mine.emplace_back(sub->kernel_offset + j, l, v);
      }
  Eigen::SparseMatrix<double> g(n_kernel_, m_);
  g.setFromTriplets(all.begin(), all.end());
  g_.resize(n_kernel_, rows_.n_owned());
  g_.setFromTriplets(mine.begin(), mine.end());
  return g;
}

void Feti::build_coarse() {
  if (n_kernel_ == 0) return;
  const auto g = build_g();
  const Eigen::MatrixXd ggt = Eigen::MatrixXd(g * g.transpose());
  coarse_.compute(ggt);
  if (coarse_.info() != Eigen::Success)
    throw Error(
        "FETI: the coarse problem GGᵀ is singular: the body floats (no Dirichlet data and no "
        "inertia), or a subdomain is not connected");
}

void Feti::build_deflation() {
  if (n_kernel_ == 0) return;
  const auto g = build_g();
  // W spans the columns of Gᵀ = B R with the dependent ones dropped: a body without
  // Dirichlet data for the field (held by contact, or a slave's temperature) has a global
  // rigid motion or constant that B does not see. Orthonormal through the eigenvectors of GGᵀ.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(g * g.transpose()));
  const Eigen::VectorXd& ev = eig.eigenvalues();  // ascending
  Eigen::Index dropped = 0;
  while (dropped < ev.size() && ev[dropped] <= 1e-10 * ev[ev.size() - 1]) ++dropped;
  const Eigen::Index r = ev.size() - dropped;
  const Eigen::MatrixXd v =
      eig.eigenvectors().rightCols(r) * ev.tail(r).cwiseSqrt().cwiseInverse().asDiagonal();
  w_ = g_.transpose() * v;
  apply_f(w_, fw_);  // one product with F per coarse vector, once per operator
  Eigen::MatrixXd e = w_.transpose() * fw_;
  sum_over_ranks(e.data(), e.size());
  coarse_.compute(0.5 * (e + e.transpose()));
  if (coarse_.info() != Eigen::Success)
    throw Error("FETI: the deflation space is rank deficient (WᵀFW not positive definite)");
}

void Feti::deflate(Block& z) const {
  if (singular_ || w_.cols() == 0) return;
  Block c = fw_.transpose() * z;
  sum_over_ranks(c.data(), c.size());
  z -= w_ * coarse_.solve(c);
}

void Feti::sum_over_ranks(double* data, Eigen::Index n) const {
  core::sum_over_ranks(options_.comm, data, n, "FETI");
}

Eigen::ArrayXd Feti::column_dots(const Block& a, const Block& b) const {
  Eigen::ArrayXd d = a.cwiseProduct(b).colwise().sum().transpose().array();
  sum_over_ranks(d.data(), d.size());
  return d;
}

void Feti::sum_subdomain_products(const Block& x, Block& y, const char* phase,
                                  const std::function<void(const Subdomain&)>& local,
                                  const std::function<void()>& before) const {
  Block in, out = Block::Zero(rows_.n_leaves(), x.cols());
  rows_.bcast(x, in);
  core::collective_check(options_.comm, phase, [&] {
    if (before) before();
    for (int s = first_owned_; s < last_owned_; ++s) {
      const auto& sub = *subs_[static_cast<size_t>(s)];
      sub.add_product(sub.b, sub.leaf_row(), in, out, local);
    }
  });
  rows_.reduce(out, y);
}

void Feti::apply_f(const Block& x, Block& y) const {
  sum_subdomain_products(
      x, y, "FETI subdomain solve", [](const Subdomain& sub) { sub.pseudo_solve(sub.w, sub.z); },
      [&] {
        if (fail_after_ >= 0 && stats_.solves > fail_after_)  // fault injection
          throw NumericalError("FETI: a subdomain solve failed (injected by -tc_fail_on_rank)", -1,
                               0, std::nan(""));
      });
}

void Feti::precondition(const Block& x, Block& y) const {
  if (options_.preconditioner == Preconditioner::none) {
    y = x;
    return;
  }
  const bool lumped = options_.preconditioner == Preconditioner::lumped;
  sum_subdomain_products(x, y, "FETI preconditioner", [lumped](const Subdomain& sub) {
    if (lumped) {
      sub.mult(sub.w, sub.z);
      return;
    }
    // S v = (A (v̄ − A_red⁻¹ (A v̄)|_interior))|_boundary, v̄ = v on the boundary
    sub.mult(sub.w, sub.t);
    for (const PetscInt d : sub.boundary) sub.t.row(d).setZero();
    sub.interior_solve(sub.t, sub.z);
    sub.w -= sub.z;
    sub.mult(sub.w, sub.z);
  });
}

void Feti::project(Block& x) const {
  if (!singular_ || n_kernel_ == 0) return;
  Block gx = g_ * x;
  sum_over_ranks(gx.data(), gx.size());
  x -= g_.transpose() * coarse_.solve(gx);
}

Feti::Block Feti::solve_dual(const Block& f_global, const Block& c, std::vector<Block>& f) const {
  const Eigen::Index k = f_global.cols();
  ++stats_.solves;
  stats_.right_hand_sides += k;
  // Right-hand sides per subdomain: each body dof's load on the copy of its owner.
  f.assign(subs_.size(), Block{});
  Block d, d_leaves = Block::Zero(rows_.n_leaves(), k), e = Block::Zero(n_kernel_, k);
  core::collective_check(options_.comm, "FETI right-hand side", [&] {
    for (int s = first_owned_; s < last_owned_; ++s) {
      const auto& sub = *subs_[static_cast<size_t>(s)];
      auto& fs = f[static_cast<size_t>(s)];
      fs.setZero(sub.n(), k);
      for (PetscInt i = 0; i < sub.n(); ++i) {
        const PetscInt g = sub.global_dof[static_cast<size_t>(i)];
        if (owner_[static_cast<size_t>(g / block_)] == s) fs.row(i) = f_global.row(g);
      }
      if (singular_ && sub.r.cols() > 0)
        e.middleRows(sub.kernel_offset, sub.r.cols()) = sub.r.transpose() * fs;
      sub.w = fs;
      sub.pseudo_solve(sub.w, sub.z);
      sub.gather_leaves(sub.z, d_leaves);
    }
  });
  rows_.reduce(d_leaves, d);
  sum_over_ranks(e.data(), e.size());
  d -= c;

  // Projected preconditioned CG on λ₀ + Ker G, λ₀ = Gᵀ(GGᵀ)⁻¹e; or deflated CG from
  // λ₀ = W E⁻¹ Wᵀ d, which makes the gradient orthogonal to W from the start. The k
  // right-hand sides run their own recurrences; only the products are shared.
  const Eigen::Index m = rows_.n_owned();
  Block lambda = Block::Zero(m, k);
  if (n_kernel_ > 0 && singular_) {
    lambda = g_.transpose() * coarse_.solve(e);
  } else if (n_kernel_ > 0) {
    Block wd = w_.transpose() * d;
    sum_over_ranks(wd.data(), wd.size());
    lambda = w_ * coarse_.solve(wd);
  }
  Block g, w, z, p = Block::Zero(m, k), fp;
  apply_f(lambda, g);
  g -= d;
  w = g;
  project(w);
  Block pd = d;
  project(pd);
  // The scale of the criterion: ‖Pd‖, or ‖PFλ₀‖ = ‖P(g₀ + d)‖ when the load enters through
  // e = Rᵀf rather than d. A load on a fixing dof has A_s⁺f = 0 (d = 0, e ≠ 0): against ‖Pd‖
  // alone that column counted as solved by λ₀, which is only feasible (a unit load there came
  // back with a residual ‖Ku − f‖ of 3, the compliance built on it 40% off).
  const Block pf0 = w + pd;
  const Block f0 = g + d;
  // The five norms of the set-up in one reduction: ‖w‖, ‖d‖, ‖Fλ₀‖, ‖Pd‖, ‖PFλ₀‖.
  Eigen::MatrixXd sq(k, 5);
  sq.col(0) = w.colwise().squaredNorm().transpose();
  sq.col(1) = d.colwise().squaredNorm().transpose();
  sq.col(2) = f0.colwise().squaredNorm().transpose();
  sq.col(3) = pd.colwise().squaredNorm().transpose();
  sq.col(4) = pf0.colwise().squaredNorm().transpose();
  sum_over_ranks(sq.data(), sq.size());
  const Eigen::ArrayXXd norm = sq.array().sqrt();
  // The projected residual P(Fλ − d) cannot be computed below the round-off of d and Fλ,
  // whose rigid-body parts P removes: ‖w‖ ≤ 1e3 ε max(‖d‖, ‖Fλ₀‖) is converged whatever the
  // relative criterion says. It matters when ‖Pd‖ is itself near that level: Dirichlet data
  // that move a floating body rigidly (a slave block pressed down before contact: u = the
  // translation, λ = 0, ‖Pd‖ = 1e-15‖d‖) — solved by λ₀ at once — and the same with a load at
  // the round-off of the data on top (thermal expansion at θ ≈ θ_ref: ‖Pd‖ a little above
  // that level, and the relative criterion, 1e-10 of it, stalled CG at 3e-5 for 1000
  // iterations).
  const Eigen::ArrayXd floor =
      1e3 * std::numeric_limits<double>::epsilon() * norm.col(1).max(norm.col(2));
  const Eigen::ArrayXd scale =
      norm.col(3).max(norm.col(4)).max(floor / options_.tolerance).max(1e-300);
  Eigen::ArrayXd rz = Eigen::ArrayXd::Ones(k), w_norm = norm.col(0);
  int it = 0;
  double worst = 0;
  for (;; ++it) {
    const Eigen::ArrayXd res = w_norm / scale;
    worst = res.maxCoeff();
    if (worst <= options_.tolerance) break;
    if (!std::isfinite(worst))
      throw NumericalError("FETI: the dual residual is not finite", -1, it, worst);
    if (it >= options_.max_iterations)
      throw NumericalError(fmt::format("FETI: projected CG did not converge in {} iterations "
                                       "({} preconditioner)",
                                       it, name(options_.preconditioner)),
                           -1, it, worst);
    precondition(w, z);
    project(z);
    deflate(z);
    const Eigen::ArrayXd rz_new = column_dots(w, z);
    const Eigen::ArrayXd beta = it == 0 ? Eigen::ArrayXd::Zero(k) : Eigen::ArrayXd(rz_new / rz);
    p = z + p * beta.matrix().asDiagonal();
    rz = rz_new;
    apply_f(p, fp);
    // A converged column keeps α = 0: its λ stays where the criterion accepted it.
    const Eigen::ArrayXd pfp = column_dots(p, fp);
    const Eigen::ArrayXd alpha = (res > options_.tolerance).cast<double>() * rz / pfp.max(1e-300);
    lambda -= p * alpha.matrix().asDiagonal();
    g -= fp * alpha.matrix().asDiagonal();
    w = g;
    project(w);
    w_norm = column_dots(w, w).sqrt();
  }
  stats_.last_iterations = it;
  stats_.iterations += it;
  stats_.last_residual = worst;
  stats_.peak_residual = std::max(stats_.peak_residual, w_norm.maxCoeff());
  // α = (GGᵀ)⁻¹G(Fλ − d) of the floating subdomains, returned in the last rows.
  Block out(m + (singular_ ? n_kernel_ : 0), k);
  out.topRows(m) = lambda;
  if (singular_ && n_kernel_ > 0) {
    Block gg = g_ * g;
    sum_over_ranks(gg.data(), gg.size());
    out.bottomRows(n_kernel_) = coarse_.solve(gg);
  }
  return out;
}

Feti::Block Feti::primal(const Block& solution, const std::vector<Block>& f) const {
  // u_s = A_s⁺(f_s − B_sᵀλ) + R_s α_s; each body dof from the copy of its owner.
  const Eigen::Index k = solution.cols(), m = rows_.n_owned();
  Block lambda;
  rows_.bcast(solution.topRows(m), lambda);
  Block u = Block::Zero(static_cast<Eigen::Index>(owner_.size()) * block_, k);
  core::collective_check(options_.comm, "FETI primal solution", [&] {
    for (int s = first_owned_; s < last_owned_; ++s) {
      const auto& sub = *subs_[static_cast<size_t>(s)];
      sub.scatter_transpose_leaves(lambda, sub.w);
      sub.w = f[static_cast<size_t>(s)] - sub.w;
      sub.pseudo_solve(sub.w, sub.z);
      if (singular_ && sub.r.cols() > 0)
        sub.z += sub.r * solution.middleRows(m + sub.kernel_offset, sub.r.cols());
      for (PetscInt i = 0; i < sub.n(); ++i) {
        const PetscInt gdof = sub.global_dof[static_cast<size_t>(i)];
        if (owner_[static_cast<size_t>(gdof / block_)] == s) u.row(gdof) = sub.z.row(i);
      }
    }
  });
  sum_over_ranks(u.data(), u.size());
  return u;
}

void Feti::record_time(double seconds, Eigen::Index columns) const {
  stats_.seconds += seconds;
  if (columns != 1) return;
  ++stats_.single_solves;
  stats_.single_iterations += stats_.last_iterations;
  stats_.single_seconds += seconds;
}

void Feti::solve(const core::Vector& b, core::Vector& x) const {
  const auto t0 = std::chrono::steady_clock::now();
  const auto& owned = rows_.owned_rows();
  Block f(b.size(), 1), c = Block::Zero(rows_.n_owned(), 1);
  {
    const auto bv = b.read();
    for (PetscInt i = 0; i < b.size(); ++i) f(i, 0) = bv[i];
    const auto xv = x.read();
    for (size_t i = 0; i < owned.size(); ++i)
      if (owned[i] >= m_gluing_)
        c(static_cast<Eigen::Index>(i), 0) =
            xv[dirichlet_row_dof_[static_cast<size_t>(owned[i] - m_gluing_)]];
  }
  std::vector<Block> fs;
  const Block u = primal(solve_dual(f, c, fs), fs);
  auto xv = x.view();
  for (PetscInt i = 0; i < x.size(); ++i)
    if (!std::binary_search(dirichlet_dofs_.begin(), dirichlet_dofs_.end(), i)) xv[i] = u(i, 0);
  record_time(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1);
}

void Feti::solve_homogeneous_many(::Mat b, ::Mat x) const {
  const auto t0 = std::chrono::steady_clock::now();
  PetscInt n = 0, k = 0;
  TC_PETSC(MatGetSize(b, &n, &k));
  Block f(n, k);
  {
    const double* bv = nullptr;
    TC_PETSC(MatDenseGetArrayRead(b, &bv));
    f = Eigen::Map<const Block>(bv, n, k);
    TC_PETSC(MatDenseRestoreArrayRead(b, &bv));
  }
  std::vector<Block> fs;
  Block u = primal(solve_dual(f, Block::Zero(rows_.n_owned(), k), fs), fs);
  for (const PetscInt d : dirichlet_dofs_) u.row(d).setZero();
  double* xv = nullptr;
  TC_PETSC(MatDenseGetArrayWrite(x, &xv));
  Eigen::Map<Block>(xv, n, k) = u;
  TC_PETSC(MatDenseRestoreArrayWrite(x, &xv));
  record_time(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), k);
}

}  // namespace tc::feti
