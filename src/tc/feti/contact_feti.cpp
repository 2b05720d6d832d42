#include "tc/feti/contact_feti.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "tc/core/error.hpp"
#include "tc/core/numeric/collective.hpp"
#include "tc/feti/subdomain.hpp"

namespace tc::feti {

struct ContactFeti::Part {
  int body_index;  // 0 slave, 1 master
  const Feti::Subdomain* sub;
  std::vector<Entry> b;        // its rows of B: the body's (shifted) and the contact ones
  Eigen::Index kernel_offset;  // first row of the combined G
  /// (local dof, body dof) of the dofs whose load this copy carries (the owner's copy): where
  /// f is scattered to and u gathered from.
  std::vector<std::pair<PetscInt, PetscInt>> carried;
  [[nodiscard]] bool owned() const { return sub->owned; }
  /// Entry i's row in the replicated dual vectors: its row of the combined B.
  [[nodiscard]] auto row() const {
    return [this](size_t i) { return b[i].row; };
  }
};

namespace {

/// The nonzeros of a sequential AIJ matrix, row by row.
template <class F>
void for_each_entry(const core::SparseMatrix& a, F&& f) {
  for (PetscInt i = 0; i < a.rows(); ++i) {
    PetscInt nc = 0;
    const PetscInt* cols = nullptr;
    const double* vals = nullptr;
    TC_PETSC(MatGetRow(a.get(), i, &nc, &cols, &vals));
    for (PetscInt k = 0; k < nc; ++k)
      if (vals[k] != 0) f(i, cols[k], vals[k]);
    TC_PETSC(MatRestoreRow(a.get(), i, &nc, &cols, &vals));
  }
}

}  // namespace

ContactFeti::ContactFeti(const Feti& slave, const Feti& master, const core::SparseMatrix& b_slave,
                         const core::SparseMatrix& b_master, int dim)
    : body_{&slave, &master}, dim_(dim), comm_(slave.comm()) {
  if (!slave.singular() || !master.singular())
    throw Error("ContactFeti: quasistatic only (both bodies' FETI with Singular::yes)");
  if (b_slave.rows() != b_master.rows() || b_slave.rows() % dim != 0)
    throw Error("ContactFeti: the contact rows of the two bodies disagree");
  const Eigen::Index mc = b_slave.rows();
  offset_[0] = 0;
  offset_[1] = slave.n_multipliers();
  offset_[2] = slave.n_multipliers() + master.n_multipliers();
  m_ = offset_[2] + mc;

  // One scale per contact node, 1/‖normal row‖: the gluing rows are orthonormal and the
  // Dirichlet rows unit, while mortar rows carry the nodal areas (∼h^(dim−1)); unit contact
  // rows keep F's diagonal of one size. One factor for all rows of a node keeps a disc a disc.
  const auto n_nodes = static_cast<size_t>(mc / dim);
  std::vector<double> sq(n_nodes, 0.0);
  for (const auto* b : {&b_slave, &b_master})
    for_each_entry(*b, [&](PetscInt i, PetscInt, double v) {
      if (i % dim == 0) sq[static_cast<size_t>(i / dim)] += v * v;
    });
  node_scale_.resize(n_nodes);
  for (size_t k = 0; k < n_nodes; ++k) node_scale_[k] = sq[k] > 0 ? 1 / std::sqrt(sq[k]) : 1.0;

  Eigen::Index kernel_base = 0;
  for (int bi = 0; bi < 2; ++bi) {
    const Feti& body = *body_[bi];
    const auto& owner = body.load_owners();
    const int block = body.block();
    const size_t first = parts_.size();
    for (int s = 0; s < body.n_subdomains(); ++s) {
      const auto& sub = body.subdomain(s);
      Part p{bi, &sub, sub.b, kernel_base + sub.kernel_offset, {}};
      for (auto& e : p.b) e.row += offset_[bi];
      for (PetscInt i = 0; i < sub.n(); ++i) {
        const PetscInt g = sub.global_dof[static_cast<size_t>(i)];
        if (owner[static_cast<size_t>(g / block)] == s) p.carried.emplace_back(i, g);
      }
      parts_.push_back(std::move(p));
    }
    kernel_base += body.coarse_dimension();
    // Each body dof of a contact row goes on the copy of its owner, the subdomain that also
    // carries its load: the local node of that copy for every body node.
    std::vector<PetscInt> owner_local(owner.size(), -1);
    for (int s = 0; s < body.n_subdomains(); ++s) {
      const auto& sub = body.subdomain(s);
      for (PetscInt a = 0; a < sub.n() / block; ++a) {
        const auto node =
            static_cast<size_t>(sub.global_dof[static_cast<size_t>(block * a)] / block);
        if (owner[node] == s) owner_local[node] = a;
      }
    }
    for_each_entry(bi == 0 ? b_slave : b_master, [&](PetscInt i, PetscInt j, double v) {
      const auto node = static_cast<size_t>(j / block);
      auto& part = parts_[first + static_cast<size_t>(owner[node])];
      part.b.push_back({offset_[2] + i, block * owner_local[node] + j % block,
                        v * node_scale_[static_cast<size_t>(i / dim)]});
    });
  }

  // G = RᵀBᵀ (6.4) over the subdomains of both bodies, contact columns included.
  std::vector<Eigen::Triplet<double>> t;
  for (const auto& p : parts_)
    for (const auto& e : p.b)
      for (Eigen::Index j = 0; j < p.sub->r.cols(); ++j)
        t.emplace_back(p.kernel_offset + j, e.row, e.value * p.sub->r(e.dof, j));
  g_.resize(kernel_base, m_);
  g_.setFromTriplets(t.begin(), t.end());
}

ContactFeti::~ContactFeti() = default;

void ContactFeti::sum_over_ranks(double* data, Eigen::Index n) const {
  core::sum_over_ranks(comm_, data, n, "ContactFeti");
}

void ContactFeti::sum_subdomain_products(DualIn x, DualOut y, const char* phase,
                                         Local local) const {
  // y = Σ_s B_s X_s B_sᵀ x over the subdomains this rank owns, of either body, summed over the
  // ranks (X_s = A_s⁺ for F, A_s for the lumped preconditioner).
  y.setZero();
  core::collective_check(comm_, phase, [&] {
    for (const auto& p : parts_)
      if (p.owned())
        p.sub->add_product(p.b, p.row(), x, y,
                           [local](const Feti::Subdomain& sub) { (sub.*local)(sub.w, sub.z); });
  });
  sum_over_ranks(y.data(), y.size());
}

void ContactFeti::precondition(DualIn x, DualOut y) const {
  sum_subdomain_products(x, y, "combined FETI preconditioner", &Feti::Subdomain::mult);
}

void ContactFeti::apply_f(DualIn x, DualOut y) const {
  sum_subdomain_products(x, y, "combined FETI subdomain solve", &Feti::Subdomain::pseudo_solve);
  ++stats_.applications;
}

qp::SmalbeResult ContactFeti::solve(const core::Vector& b_slave, const core::Vector& b_master,
                                    std::span<const double> c,
                                    std::span<const double> friction_bound, core::Vector& x_slave,
                                    core::Vector& x_master, core::Vector& lambda,
                                    const ContactFetiOptions& options,
                                    ContactFetiState* warm) const {
  const auto t0 = std::chrono::steady_clock::now();
  stats_.applications = 0;
  core::Vector* x[2] = {&x_slave, &x_master};
  const auto n_contact = static_cast<size_t>(m_ - offset_[2]);
  if (c.size() != n_contact || friction_bound.size() != node_scale_.size())
    throw Error("ContactFeti: targets or friction bounds of the wrong size");

  // The loads of every subdomain on the copies of the owners; d = Σ B_s A_s⁺ f_s − c and
  // e = Rᵀf (6.4).
  std::vector<Eigen::MatrixXd> fs(parts_.size());
  Eigen::VectorXd d = Eigen::VectorXd::Zero(m_), e = Eigen::VectorXd::Zero(g_.rows());
  {
    // The loads and the Dirichlet values read in place.
    const core::Vector::ReadView br[2] = {b_slave.read(), b_master.read()};
    const core::Vector::ReadView xr[2] = {x_slave.read(), x_master.read()};
    core::collective_check(comm_, "combined FETI right-hand side", [&] {
      for (size_t k = 0; k < parts_.size(); ++k) {
        const auto& p = parts_[k];
        if (!p.owned()) continue;
        auto& f = fs[k];
        f.setZero(p.sub->n(), 1);
        for (const auto& [i, g] : p.carried) f(i, 0) = br[p.body_index][g];
        if (p.sub->r.cols() > 0)
          e.segment(p.kernel_offset, p.sub->r.cols()) = p.sub->r.transpose() * f;
        Eigen::MatrixXd w = f;
        p.sub->pseudo_solve(w, p.sub->z);
        p.sub->gather(p.b, p.row(), p.sub->z, d);
      }
    });
    sum_over_ranks(d.data(), d.size());
    sum_over_ranks(e.data(), e.size());
    for (int bi = 0; bi < 2; ++bi) {
      const Feti& body = *body_[bi];
      const auto& row_dof = body.dirichlet_row_dofs();
      for (size_t i = 0; i < row_dof.size(); ++i)
        d[offset_[bi] + body.n_gluing() + static_cast<Eigen::Index>(i)] -= xr[bi][row_dof[i]];
    }
  }
  for (size_t i = 0; i < n_contact; ++i)
    d[offset_[2] + static_cast<Eigen::Index>(i)] -=
        node_scale_[i / static_cast<size_t>(dim_)] * c[i];

  // Ω: gluing and Dirichlet multipliers free; per contact node λ_n ≥ 0 and the Tresca bound
  // on the tangents, in the scaled multipliers λ̂ = λ/σ_k (bound 𝔉γ_k/σ_k).
  const auto dv = core::Vector::from(std::span<const double>(d.data(), static_cast<size_t>(m_)));
  qp::FeasibleSet set(dv);
  for (size_t k = 0; k < node_scale_.size(); ++k) {
    const auto row = static_cast<PetscInt>(offset_[2]) + dim_ * static_cast<PetscInt>(k);
    set.set_interval(row, {0.0, qp::infinity});
    const double r = std::max(friction_bound[k], 0.0) / node_scale_[k];
    if (dim_ == 2)
      set.set_interval(row + 1, {-r, r});
    else
      set.add_disc({row + 1, row + 2, {r}});
  }
  // F and the lumped preconditioner as qp operators on the replicated dual vectors, applied
  // to the vectors' arrays in place (in and out are never one vector in the QP).
  const auto dual_operator = [&](void (ContactFeti::*product)(DualIn, DualOut) const) {
    return qp::FunctionOperator(
        [this, product](const core::Vector& in, core::Vector& out) {
          const auto iv = in.read();
          auto ov = out.view();
          (this->*product)(Eigen::Map<const Eigen::VectorXd>(iv.span().data(), m_),
                           Eigen::Map<Eigen::VectorXd>(ov.span().data(), m_));
        },
        dv);
  };
  const qp::FunctionOperator f = dual_operator(&ContactFeti::apply_f);
  const qp::FunctionOperator lumped = dual_operator(&ContactFeti::precondition);
  qp::SmalbeOptions so = options.smalbe;
  if (options.lumped_preconditioner) so.inner.preconditioner = &lumped;
  if (so.max_eigenvalue <= 0) so.max_eigenvalue = lambda_max_;
  core::Vector lam = dv.duplicate();
  Eigen::VectorXd mu;
  if (warm) {
    // The contact part in the scaled multipliers λ̂ = λ/σ_k; SMALBE projects λ onto Ω.
    auto lw = lam.view();
    const auto in = lambda.read();
    if (static_cast<size_t>(lambda.size()) == n_contact)
      for (size_t i = 0; i < n_contact; ++i)
        lw[static_cast<PetscInt>(offset_[2] + static_cast<Eigen::Index>(i))] =
            in[static_cast<PetscInt>(i)] / node_scale_[i / static_cast<size_t>(dim_)];
    if (warm->body.size() == offset_[2])
      for (Eigen::Index i = 0; i < offset_[2]; ++i) lw[static_cast<PetscInt>(i)] = warm->body[i];
    if (warm->mu.size() == g_.rows()) {
      mu = warm->mu;
      so.initial_mu = true;
    }
  }
  const auto r = qp::Smalbe(f, set, g_, e, PETSC_COMM_SELF, so).solve(dv, lam, mu);
  lambda_max_ = r.max_eigenvalue;

  // u_s = A_s⁺(f_s − B_sᵀλ) + R_s α_s with α = −μ: the Lagrangian gradient Fλ − d + Gᵀμ is the
  // one of (6.4)'s Fλ − Gᵀα − d, so SMALBE's multiplier of Gλ = e is the amplitude of the
  // subdomains' rigid motions.
  const auto lam_read = lam.read();
  const auto lv = lam_read.span();
  if (warm) {
    warm->body = Eigen::Map<const Eigen::VectorXd>(lv.data(), offset_[2]);
    warm->mu = mu;
  }
  std::vector<Eigen::VectorXd> u(2);
  for (int bi = 0; bi < 2; ++bi) u[bi] = Eigen::VectorXd::Zero(x[bi]->size());
  core::collective_check(comm_, "combined FETI primal solution", [&] {
    for (size_t k = 0; k < parts_.size(); ++k) {
      const auto& p = parts_[k];
      if (!p.owned()) continue;
      Eigen::MatrixXd w = fs[k];
      for (const auto& en : p.b) w(en.dof, 0) -= en.value * lv[static_cast<size_t>(en.row)];
      p.sub->pseudo_solve(w, p.sub->z);
      if (p.sub->r.cols() > 0) p.sub->z -= p.sub->r * mu.segment(p.kernel_offset, p.sub->r.cols());
      for (const auto& [i, g] : p.carried) u[p.body_index][g] = p.sub->z(i, 0);
    }
  });
  for (int bi = 0; bi < 2; ++bi) {
    sum_over_ranks(u[bi].data(), u[bi].size());
    const auto& dir = body_[bi]->dirichlet_dofs();
    auto out = x[bi]->view();
    for (PetscInt i = 0; i < x[bi]->size(); ++i)
      if (!std::binary_search(dir.begin(), dir.end(), i)) out[i] = u[bi][i];
  }
  {
    auto out = lambda.view();
    for (size_t i = 0; i < n_contact; ++i)
      out[static_cast<PetscInt>(i)] =
          node_scale_[i / static_cast<size_t>(dim_)] * lv[static_cast<size_t>(offset_[2]) + i];
  }
  stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace tc::feti
