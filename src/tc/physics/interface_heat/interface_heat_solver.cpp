#include "tc/physics/interface_heat/interface_heat_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "tc/core/error.hpp"
#include "tc/core/numeric/blas.hpp"
#include "tc/core/verify.hpp"

namespace tc::physics {

InterfaceHeatSolver::InterfaceHeatSolver(std::vector<const ConstrainedSolver*> solvers,
                                         std::vector<PetscInt> n,
                                         std::vector<std::vector<int>> nodes)
    : solver_(std::move(solvers)), n_(std::move(n)), nodes_(std::move(nodes)) {
  offset_.push_back(0);
  for (int i = 0; i < n_bodies(); ++i) {
    index_.emplace_back(static_cast<size_t>(n_[i]), -1);
    for (size_t a = 0; a < nodes_[i].size(); ++a) {
      const int node = nodes_[i][a];
      if (node < 0 || node >= n_[i])
        throw Error("InterfaceHeatSolver: interface node out of range");
      index_[i][node] = offset_.back() + static_cast<int>(a);
    }
    offset_.push_back(offset_.back() + static_cast<int>(nodes_[i].size()));
    rhs_.emplace_back(n_[i]);
    compliance_.push_back(solver_[i]->compliance(n_[i]));
  }
  corrected_.resize(static_cast<size_t>(n_bodies()));
}

void InterfaceHeatSolver::save_compliance(std::vector<std::vector<int>>& record) const {
  linalg::save_compliances(compliance_, record);
}

void InterfaceHeatSolver::replay_compliance(std::span<const std::vector<int>> record) {
  linalg::replay_compliances(compliance_, record, "interface heat");
  // J, L_JJ and the LU are set afresh by the first heat step of the next time step
  // (set_conductance without refinement): nothing else passes between steps.
  active_.clear();
  lu_current_ = false;
}

int InterfaceHeatSolver::body_of(int g) const {
  return static_cast<int>(std::upper_bound(offset_.begin(), offset_.end(), g) - offset_.begin()) -
         1;
}

void InterfaceHeatSolver::set_conductance(std::span<const PairConductance> pairs, bool refine) {
  // L_Γ entries (global interface indices) from the four blocks of each pair, rows of Γ only.
  // Within a pair the blocks cover disjoint (row, column) pairs and a row lists a column once;
  // two pairs on one body may add to the same entry (setFromTriplets sums them).
  struct Entry {
    int row, col;
    double value;
  };
  std::vector<Entry> entries;
  for (const auto& pair : pairs) {
    const auto& l = *pair.l;
    const core::SparseMatrix* blocks[2][2] = {{&l.ss, &l.sm}, {&l.ms, &l.mm}};
    const int body[2] = {pair.slave, pair.master};
    for (int bi = 0; bi < 2; ++bi)
      for (int bj = 0; bj < 2; ++bj) {
        const int i = body[bi], j = body[bj];
        const auto& m = *blocks[bi][bj];
        if (m.rows() != n_[i] || m.cols() != n_[j])
          throw Error("InterfaceHeatSolver: L_θγ block sizes do not match the bodies");
        for (const int r : nodes_[i]) {
          PetscInt n = 0;
          const PetscInt* cols = nullptr;
          const PetscScalar* vals = nullptr;
          TC_PETSC(MatGetRow(m.get(), r, &n, &cols, &vals));
          for (PetscInt k = 0; k < n; ++k) {
            if (vals[k] == 0.0) continue;
            const int gc = index_[j][cols[k]];
            if (gc < 0) {
              TC_PETSC(MatRestoreRow(m.get(), r, &n, &cols, &vals));
              throw Error(fmt::format(
                  "InterfaceHeatSolver: L_θγ couples interface node {} to node {} off the "
                  "contact surface",
                  r, cols[k]));
            }
            entries.push_back({index_[i][r], gc, vals[k]});
          }
          TC_PETSC(MatRestoreRow(m.get(), r, &n, &cols, &vals));
        }
      }
  }
  // L's support: interface nodes with a row or a column of L. It becomes the working set J
  // unless J already holds it (then the LU of J is kept for refinement).
  std::vector<char> in_l(static_cast<size_t>(offset_.back()), 0);
  for (const auto& e : entries) in_l[e.row] = in_l[e.col] = 1;
  std::vector<int> position(static_cast<size_t>(offset_.back()), -1);
  for (size_t a = 0; a < active_.size(); ++a) position[active_[a]] = static_cast<int>(a);
  bool grows = !refine || active_.empty();
  for (int g = 0; g < offset_.back() && !grows; ++g) grows = in_l[g] && position[g] < 0;
  if (grows) {
    active_.clear();
    std::fill(position.begin(), position.end(), -1);
    for (int g = 0; g < offset_.back(); ++g)
      if (in_l[g]) {
        position[g] = static_cast<int>(active_.size());
        active_.push_back(g);
      }
  }
  const auto na = static_cast<Eigen::Index>(active_.size());
  // L_JJ has a few entries per row (the facets around a node): sparse
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(entries.size());
  for (const auto& e : entries) triplets.emplace_back(position[e.row], position[e.col], e.value);
  l_active_.resize(na, na);
  l_active_.setFromTriplets(triplets.begin(), triplets.end());
  lu_current_ = false;
  if (!grows || na == 0) return;
  // S_JJ, block diagonal (the bodies do not see each other through A); the columns of the nodes
  // new to J first, body by body.
  std::vector<std::vector<PetscInt>> nodes(static_cast<size_t>(n_bodies()));
  std::vector<PetscInt> node(static_cast<size_t>(na));
  std::vector<int> body(static_cast<size_t>(na));
  for (Eigen::Index a = 0; a < na; ++a) {
    body[a] = body_of(active_[a]);
    node[a] = nodes_[body[a]][active_[a] - offset_[body[a]]];
    nodes[body[a]].push_back(node[a]);
  }
  for (int i = 0; i < n_bodies(); ++i) setup_solves_ += compliance_[i]->cover(nodes[i]);
  s_.setZero(na, na);
  for (Eigen::Index b = 0; b < na; ++b) {
    const auto& comp = *compliance_[body[b]];
    const PetscInt cb = comp.index(node[b]);
    for (Eigen::Index a = 0; a < na; ++a)
      if (body[a] == body[b]) s_(a, b) = comp.matrix()(comp.index(node[a]), cb);
  }
  factorize();
}

void InterfaceHeatSolver::factorize() const {
  lu_ = s_ * l_active_;
  lu_.diagonal().array() += 1.0;
  const int n = static_cast<int>(lu_.rows());
  pivots_.resize(static_cast<size_t>(n));
  int info = 0;
  dgetrf_(&n, &n, lu_.data(), &n, pivots_.data(), &info);
  // I + S L_Γ is similar to I + S^½ L_Γ S^½ (eigenvalues ≥ 1): a zero pivot is a broken L or S.
  if (info != 0)
    throw Error(fmt::format("InterfaceHeatSolver: LU of I + S L_JJ failed (LAPACK info {})", info));
  lu_current_ = true;
  ++factorizations_;
}

void InterfaceHeatSolver::lu_solve(Eigen::VectorXd& y) const {
  const int n = static_cast<int>(y.size()), one = 1;
  int info = 0;
  dgetrs_("N", &n, &one, lu_.data(), &n, pivots_.data(), y.data(), &n, &info);
  TC_VERIFY(info == 0, "dgetrs is called with valid arguments");
}

void InterfaceHeatSolver::interface_solve(Eigen::VectorXd& y) const {
  if (lu_current_) return lu_solve(y);
  // Refinement y ← y + LU⁻¹(y₀ − (I + S L) y) contracts by ‖I − LU⁻¹(I + S L)‖, of the order of
  // the relative change of L since the LU (~1e-3 between iterations of (6.3)). It stops when a
  // correction is below 1e-14‖y‖: at that contraction the error is of the size of the last
  // correction, i.e. round-off, as with the LU itself. A correction that does not shrink by 1/3
  // means L moved too far (or round-off was reached above 1e-14): a new LU.
  constexpr int kMaxSteps = 10;
  constexpr double kTolerance = 1e-14, kContraction = 1.0 / 3.0;
  const Eigen::VectorXd y0 = y;
  const int n = static_cast<int>(y.size()), one = 1;
  const double plus = 1.0, minus = -1.0;
  lu_solve(y);
  Eigen::VectorXd r(y.size());
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 0; k < kMaxSteps; ++k) {
    const Eigen::VectorXd ly = l_active_ * y;
    r = y0 - y;
    dsymv_("U", &n, &minus, s_.data(), &n, ly.data(), &one, &plus, r.data(), &one);  // − S L y
    lu_solve(r);
    y += r;
    ++refinement_steps_;
    const double correction = r.norm();
    if (correction <= kTolerance * y.norm()) return;
    if (correction > kContraction * previous) break;
    previous = correction;
  }
  factorize();
  y = y0;
  lu_solve(y);
}

void InterfaceHeatSolver::solve(std::span<const core::Vector* const> b,
                                std::span<core::Vector* const> x) const {
  // x = G(b), P x = y₀, then θ = G(b − Pᵀ L_Γ y): one corrected solve of body i's compliance
  // where it has one (x on T ⊇ J first, linalg::Compliance::begin_corrected), else two solves.
  std::vector<char> shared(static_cast<size_t>(n_bodies()), 0);
  for (int i = 0; i < n_bodies(); ++i) {
    const auto k = static_cast<size_t>(i);
    corrected_[k].cancel();
    shared[k] = !active_.empty() && compliance_[k]->begin_corrected(*b[i], *x[i], corrected_[k]);
    if (!shared[k]) solver_[i]->solve(*b[i], *x[i]);
  }
  if (active_.empty()) return;
  const auto na = static_cast<Eigen::Index>(active_.size());
  Eigen::VectorXd y0(na);
  for (int i = 0; i < n_bodies(); ++i) {  // the interface entries only, body by body
    const auto xv = x[i]->read();
    for (Eigen::Index a = 0; a < na; ++a) {
      const int g = active_[a];
      if (g >= offset_[i] && g < offset_[i + 1]) y0(a) = xv[nodes_[i][g - offset_[i]]];
    }
  }
  interface_solve(y0);
  const Eigen::VectorXd c = l_active_ * y0;  // L_Γ y
  std::vector<char> touched(static_cast<size_t>(n_bodies()), 0);
  for (int i = 0; i < n_bodies(); ++i) {
    // b − Pᵀ L_Γ y, or Pᵀ L_Γ y alone for the corrected solve, which subtracts it from b
    const double sign = shared[static_cast<size_t>(i)] ? 1.0 : -1.0;
    if (shared[static_cast<size_t>(i)])
      rhs_[i].zero();
    else
      rhs_[i].copy_from(*b[i]);
    auto rv = rhs_[i].view();
    for (Eigen::Index a = 0; a < na; ++a) {
      const int g = active_[a];
      if (c(a) == 0.0 || g < offset_[i] || g >= offset_[i + 1]) continue;
      rv[nodes_[i][g - offset_[i]]] += sign * c(a);
      touched[i] = 1;
    }
  }
  for (int i = 0; i < n_bodies(); ++i) {
    const auto k = static_cast<size_t>(i);
    if (shared[k]) {
      TC_VERIFY(compliance_[k]->finish_corrected(corrected_[k], rhs_[i], *x[i]),
                "a begun corrected heat solve finishes");
    } else if (touched[i]) {
      solver_[i]->solve(rhs_[i], *x[i]);  // θ = G(b − Pᵀ L_Γ y)
    }
  }
}

}  // namespace tc::physics
