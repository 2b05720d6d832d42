#include "tc/feti/feti.hpp"

#include <fmt/format.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "tc/core/error.hpp"

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

namespace {

struct Entry {  // one nonzero of B_s: row of B, local dof, value
  Eigen::Index row;
  PetscInt dof;
  double value;
};

double mean_diagonal(const core::SparseMatrix& a) {
  core::Vector d(a.rows());
  TC_PETSC(MatGetDiagonal(a.get(), d.get()));
  const double mean = d.sum() / static_cast<double>(a.rows());
  return mean > 0 ? mean : 1.0;
}

}  // namespace

struct Feti::Subdomain {
  std::vector<PetscInt> global_dof;  // local dof → body dof
  std::vector<Entry> b;              // B_s, sorted by row
  Eigen::MatrixXd r;                 // kernel basis, orthonormal columns (local dofs × k)
  Eigen::Index kernel_offset = 0;    // first row of G belonging to this subdomain
  bool owned = false;
  // Owned subdomains only:
  core::SparseMatrix a;
  std::vector<PetscInt> fixing;    // dofs set to zero in A⁺ (the fixing-node generalised inverse)
  core::CholeskySolver factor;     // of A with the fixing dofs eliminated
  std::vector<PetscInt> boundary;  // local dofs with a row of B (Dirichlet preconditioner)
  core::CholeskySolver interior;   // of A with the boundary dofs eliminated
  mutable core::Vector w, z, t;

  [[nodiscard]] PetscInt n() const { return static_cast<PetscInt>(global_dof.size()); }

  void scatter_transpose(const Dual& x, core::Vector& out) const {  // out = B_sᵀ x
    out.zero();
    auto v = out.view();
    for (const auto& e : b) v[e.dof] += e.value * x[e.row];
  }
  void gather(const core::Vector& in, Dual& y) const {  // y += B_s in
    const auto v = in.read();
    for (const auto& e : b) y[e.row] += e.value * v[e.dof];
  }
  /// out = A_s⁺ in (in is overwritten at the fixing dofs).
  void pseudo_solve(core::Vector& in, core::Vector& out) const {
    if (!fixing.empty()) {
      auto v = in.view();
      for (const PetscInt d : fixing) v[d] = 0.0;
    }
    factor.solve(in, out);
  }
};

Feti::Feti(const std::vector<mesh::SubMesh>& subdomains, int n_nodes, int block,
           std::vector<PetscInt> dirichlet_dofs, Kernel kernel, Singular singular,
           const std::function<core::SparseMatrix(int s)>& local_matrix, FetiOptions options)
    : block_(block), options_(std::move(options)), singular_(singular == Singular::yes) {
  if (!singular_ && !options_.deflation) kernel = Kernel::none;
  const int n_sub = static_cast<int>(subdomains.size());
  int rank = 0, size = 1;
  MPI_Comm_rank(options_.comm, &rank);
  MPI_Comm_size(options_.comm, &size);
  first_owned_ = static_cast<int>(static_cast<long>(n_sub) * rank / size);
  last_owned_ = static_cast<int>(static_cast<long>(n_sub) * (rank + 1) / size);
  for (int s = 0; s < n_sub; ++s) {
    auto sub = std::make_unique<Subdomain>();
    for (const int g : subdomains[static_cast<size_t>(s)].global_node)
      for (int k = 0; k < block_; ++k) sub->global_dof.push_back(block_ * g + k);
    sub->owned = s >= first_owned_ && s < last_owned_;
    subs_.push_back(std::move(sub));
  }
  std::sort(dirichlet_dofs.begin(), dirichlet_dofs.end());
  build_rows(n_nodes, dirichlet_dofs);
  build_kernels(subdomains, kernel);
  if (singular_) build_coarse();
  for (int s = first_owned_; s < last_owned_; ++s) {
    auto& sub = *subs_[static_cast<size_t>(s)];
    sub.a = local_matrix(s);
    if (sub.a.rows() != sub.n())
      throw Error(fmt::format("FETI: subdomain {} matrix has {} rows, expected {}", s, sub.a.rows(),
                              sub.n()));
    const double diag = mean_diagonal(sub.a);
    auto reduced = sub.a.copy();
    reduced.zero_rows_columns(sub.fixing, diag);
    sub.factor = core::CholeskySolver(reduced, options_.package);
    package_ = sub.factor.package();
    if (options_.preconditioner == Preconditioner::dirichlet) {
      for (const auto& e : sub.b) sub.boundary.push_back(e.dof);
      std::sort(sub.boundary.begin(), sub.boundary.end());
      sub.boundary.erase(std::unique(sub.boundary.begin(), sub.boundary.end()), sub.boundary.end());
      auto inner = sub.a.copy();
      inner.zero_rows_columns(sub.boundary, diag);
      sub.interior = core::CholeskySolver(inner, options_.package);
    }
    sub.w = core::Vector(sub.n());
    sub.z = core::Vector(sub.n());
    sub.t = core::Vector(sub.n());
  }
  if (!singular_) build_deflation();
}

Feti::~Feti() = default;

int Feti::owner_rank(int s) const {
  int size = 1;
  MPI_Comm_size(options_.comm, &size);
  const int n = n_subdomains();
  for (int r = 0; r < size; ++r)
    if (s < static_cast<int>(static_cast<long>(n) * (r + 1) / size)) return r;
  return size - 1;
}

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

void Feti::build_g() {
  // G = Rᵀ Bᵀ: row j of subdomain s is Σ over the entries of B_s of R_s(dof, j)·value.
  std::vector<Eigen::Triplet<double>> t;
  for (const auto& sub : subs_)
    for (const auto& e : sub->b)
      for (Eigen::Index j = 0; j < sub->r.cols(); ++j)
        t.emplace_back(sub->kernel_offset + j, e.row, e.value * sub->r(e.dof, j));
  g_.resize(n_kernel_, m_);
  g_.setFromTriplets(t.begin(), t.end());
}

void Feti::build_coarse() {
  if (n_kernel_ == 0) return;
  build_g();
  const Eigen::MatrixXd ggt = Eigen::MatrixXd(g_ * g_.transpose());
  coarse_.compute(ggt);
  if (coarse_.info() != Eigen::Success)
    throw Error(
        "FETI: the coarse problem GGᵀ is singular: the body floats (no Dirichlet data and no "
        "inertia), or a subdomain is not connected");
}

void Feti::build_deflation() {
  if (n_kernel_ == 0) return;
  build_g();
  // W = Gᵀ: one product with F per coarse vector, once per operator.
  fw_.resize(m_, n_kernel_);
  Dual col(m_), y(m_);
  for (Eigen::Index j = 0; j < n_kernel_; ++j) {
    col = g_.row(j).transpose();
    apply_f(col, y);
    fw_.col(j) = y;
  }
  const Eigen::MatrixXd e = g_ * fw_;
  coarse_.compute(0.5 * (e + e.transpose()));
  if (coarse_.info() != Eigen::Success)
    throw Error("FETI: the deflation space is rank deficient (WᵀFW not positive definite)");
}

void Feti::deflate(Dual& z) const {
  if (singular_ || n_kernel_ == 0) return;
  const Eigen::VectorXd c = fw_.transpose() * z;
  z -= g_.transpose() * coarse_.solve(c);
}

void Feti::sum_over_ranks(double* data, Eigen::Index n) const {
  int size = 1;
  MPI_Comm_size(options_.comm, &size);
  if (size == 1) return;
  const int rc =
      MPI_Allreduce(MPI_IN_PLACE, data, static_cast<int>(n), MPI_DOUBLE, MPI_SUM, options_.comm);
  if (rc != MPI_SUCCESS) throw Error("FETI: MPI_Allreduce failed");
}

void Feti::apply_f(const Dual& x, Dual& y) const {
  y.setZero(m_);
  for (int s = first_owned_; s < last_owned_; ++s) {
    const auto& sub = *subs_[static_cast<size_t>(s)];
    sub.scatter_transpose(x, sub.w);
    sub.pseudo_solve(sub.w, sub.z);
    sub.gather(sub.z, y);
  }
  sum_over_ranks(y.data(), m_);
}

void Feti::precondition(const Dual& x, Dual& y) const {
  if (options_.preconditioner == Preconditioner::none) {
    y = x;
    return;
  }
  y.setZero(m_);
  for (int s = first_owned_; s < last_owned_; ++s) {
    const auto& sub = *subs_[static_cast<size_t>(s)];
    sub.scatter_transpose(x, sub.w);
    if (options_.preconditioner == Preconditioner::lumped) {
      sub.a.mult(sub.w, sub.z);
    } else {  // S v = (A (v̄ − A_red⁻¹ (A v̄)|_interior))|_boundary, v̄ = v on the boundary
      sub.a.mult(sub.w, sub.t);
      {
        auto tv = sub.t.view();
        for (const PetscInt d : sub.boundary) tv[d] = 0.0;
      }
      sub.interior.solve(sub.t, sub.z);
      sub.w.axpy(-1.0, sub.z);
      sub.a.mult(sub.w, sub.z);
    }
    sub.gather(sub.z, y);
  }
  sum_over_ranks(y.data(), m_);
}

void Feti::project(Dual& x) const {
  if (!singular_ || n_kernel_ == 0) return;
  const Eigen::VectorXd gx = g_ * x;
  x -= g_.transpose() * coarse_.solve(gx);
}

void Feti::solve(const core::Vector& b, core::Vector& x) const {
  ++stats_.solves;
  // Right-hand sides per subdomain: each body dof's load on the copy of its owner.
  std::vector<core::Vector> f(subs_.size());
  Dual d = Dual::Zero(m_), e = Dual::Zero(n_kernel_);
  {
    const auto bv = b.read();
    for (int s = first_owned_; s < last_owned_; ++s) {
      const auto& sub = *subs_[static_cast<size_t>(s)];
      f[static_cast<size_t>(s)] = core::Vector(sub.n());
      auto fv = f[static_cast<size_t>(s)].view();
      for (PetscInt i = 0; i < sub.n(); ++i) {
        const PetscInt g = sub.global_dof[static_cast<size_t>(i)];
        if (owner_[static_cast<size_t>(g / block_)] == s) fv[i] = bv[g];
      }
    }
  }
  for (int s = first_owned_; s < last_owned_; ++s) {
    const auto& sub = *subs_[static_cast<size_t>(s)];
    auto& fs = f[static_cast<size_t>(s)];
    if (sub.r.cols() > 0) {
      const auto fv = fs.read();
      const Eigen::Map<const Eigen::VectorXd> fe(fv.span().data(), sub.n());
      e.segment(sub.kernel_offset, sub.r.cols()) = sub.r.transpose() * fe;
    }
    sub.w.copy_from(fs);
    sub.pseudo_solve(sub.w, sub.z);
    sub.gather(sub.z, d);
  }
  sum_over_ranks(d.data(), m_);
  sum_over_ranks(e.data(), n_kernel_);
  {
    const auto xv = x.read();
    for (size_t i = 0; i < dirichlet_row_dof_.size(); ++i)
      d[m_gluing_ + static_cast<Eigen::Index>(i)] -= xv[dirichlet_row_dof_[i]];
  }

  // Projected preconditioned CG on λ₀ + Ker G, λ₀ = Gᵀ(GGᵀ)⁻¹e; or deflated CG from
  // λ₀ = W E⁻¹ Wᵀ d, which makes the gradient orthogonal to W from the start.
  Dual lambda = Dual::Zero(m_);
  if (n_kernel_ > 0) {
    if (singular_)
      lambda = g_.transpose() * coarse_.solve(e);
    else
      lambda = g_.transpose() * coarse_.solve(Eigen::VectorXd(g_ * d));
  }
  Dual fl(m_), g(m_), w(m_), z(m_), p(m_), fp(m_);
  apply_f(lambda, fl);
  g = fl - d;
  w = g;
  project(w);
  Dual pd = d;
  project(pd);
  const double scale = std::max(pd.norm(), 1e-300);
  int it = 0;
  double rz = 0;
  for (;; ++it) {
    const double res = w.norm() / scale;
    stats_.last_residual = res;
    if (res <= options_.tolerance || pd.norm() == 0.0) break;
    if (!std::isfinite(res))
      throw NumericalError("FETI: the dual residual is not finite", -1, it, res);
    if (it >= options_.max_iterations)
      throw NumericalError(fmt::format("FETI: projected CG did not converge in {} iterations "
                                       "({} preconditioner)",
                                       it, name(options_.preconditioner)),
                           -1, it, res);
    precondition(w, z);
    project(z);
    deflate(z);
    const double rz_new = w.dot(z);
    p = it == 0 ? z : Dual(z + (rz_new / rz) * p);
    rz = rz_new;
    apply_f(p, fp);
    const double alpha = rz / p.dot(fp);
    lambda -= alpha * p;
    g -= alpha * fp;
    w = g;
    project(w);
  }
  stats_.last_iterations = it;
  stats_.iterations += it;

  // u_s = A_s⁺(f_s − B_sᵀλ) + R_s α_s, α = (GGᵀ)⁻¹G(Fλ − d); each body dof from its owner.
  Dual alpha = Dual::Zero(n_kernel_);
  if (singular_ && n_kernel_ > 0) alpha = coarse_.solve(g_ * g);
  std::vector<double> u(static_cast<size_t>(x.size()), 0.0);
  for (int s = first_owned_; s < last_owned_; ++s) {
    const auto& sub = *subs_[static_cast<size_t>(s)];
    sub.scatter_transpose(lambda, sub.w);
    sub.w.scale(-1.0);
    sub.w.axpy(1.0, f[static_cast<size_t>(s)]);
    sub.pseudo_solve(sub.w, sub.z);
    const auto zv = sub.z.read();
    Eigen::VectorXd kernel_part;
    const bool floating = singular_ && sub.r.cols() > 0;
    if (floating) kernel_part = sub.r * alpha.segment(sub.kernel_offset, sub.r.cols());
    for (PetscInt i = 0; i < sub.n(); ++i) {
      const PetscInt gdof = sub.global_dof[static_cast<size_t>(i)];
      if (owner_[static_cast<size_t>(gdof / block_)] != s) continue;
      u[static_cast<size_t>(gdof)] = zv[i] + (floating ? kernel_part[i] : 0.0);
    }
  }
  sum_over_ranks(u.data(), static_cast<Eigen::Index>(u.size()));
  std::vector<double> prescribed;
  {
    const auto xv = x.read();
    for (const PetscInt dof : dirichlet_row_dof_) prescribed.push_back(xv[dof]);
  }
  auto xv = x.view();
  for (size_t i = 0; i < u.size(); ++i) xv[static_cast<PetscInt>(i)] = u[i];
  for (size_t i = 0; i < prescribed.size(); ++i) xv[dirichlet_row_dof_[i]] = prescribed[i];
}

void Feti::solve_homogeneous_many(::Mat b, ::Mat x) const {
  PetscInt n = 0, k = 0;
  TC_PETSC(MatGetSize(b, &n, &k));
  const double* bv = nullptr;
  double* xv = nullptr;
  TC_PETSC(MatDenseGetArrayRead(b, &bv));
  TC_PETSC(MatDenseGetArrayWrite(x, &xv));
  core::Vector rhs(n), sol(n);
  for (PetscInt j = 0; j < k; ++j) {
    {
      auto r = rhs.view();
      for (PetscInt i = 0; i < n; ++i) r[i] = bv[j * n + i];
    }
    sol.zero();
    solve(rhs, sol);
    const auto s = sol.read();
    for (PetscInt i = 0; i < n; ++i) xv[j * n + i] = s[i];
  }
  TC_PETSC(MatDenseRestoreArrayWrite(x, &xv));
  TC_PETSC(MatDenseRestoreArrayRead(b, &bv));
}

}  // namespace tc::feti
