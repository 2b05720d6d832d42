#include "tc/physics/thermal_contact.hpp"

#include <fmt/format.h>

#include "tc/core/error.hpp"

namespace tc::physics {

InterfaceHeatSolver::InterfaceHeatSolver(const ConstrainedSolver& slave, PetscInt n_slave,
                                         const std::vector<int>& slave_nodes,
                                         const ConstrainedSolver& master, PetscInt n_master,
                                         const std::vector<int>& master_nodes)
    : solver_{&slave, &master}, n_{n_slave, n_master}, nodes_{slave_nodes, master_nodes} {
  for (int i = 0; i < 2; ++i) {
    index_[i].assign(static_cast<size_t>(n_[i]), -1);
    for (size_t a = 0; a < nodes_[i].size(); ++a) {
      const int node = nodes_[i][a];
      if (node < 0 || node >= n_[i])
        throw Error("InterfaceHeatSolver: interface node out of range");
      index_[i][node] = n_gamma_ + static_cast<int>(a);
    }
    n_gamma_ += static_cast<int>(nodes_[i].size());
    rhs_[i] = core::Vector(n_[i]);
  }
  columns_.resize(static_cast<size_t>(n_gamma_));
}

const std::vector<double>& InterfaceHeatSolver::column(int g) {
  auto& col = columns_[g];
  if (!col.empty()) return col;
  const int body = g < static_cast<int>(nodes_[0].size()) ? 0 : 1;
  const int offset = body == 0 ? 0 : static_cast<int>(nodes_[0].size());
  core::Vector e(n_[body]), x(n_[body]);  // x = 0 on the constrained dofs: homogeneous data
  {
    auto ev = e.view();
    ev[nodes_[body][g - offset]] = 1.0;
  }
  solver_[body]->solve(e, x);
  ++setup_solves_;
  const auto xs = x.to_std();
  col.resize(nodes_[body].size());
  for (size_t a = 0; a < nodes_[body].size(); ++a) col[a] = xs[nodes_[body][a]];
  return col;
}

void InterfaceHeatSolver::set_conductance(const contact::ThermalContact& l) {
  // L_Γ entries (global interface indices) from the four blocks, rows of Γ only. The blocks
  // cover disjoint (row, column) pairs and a row lists a column once: no entry repeats.
  struct Entry {
    int row, col;
    double value;
  };
  std::vector<Entry> entries;
  const core::SparseMatrix* blocks[2][2] = {{&l.ss, &l.sm}, {&l.ms, &l.mm}};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      const auto& m = *blocks[i][j];
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
  // The active set J: interface nodes with a row or a column of L.
  std::vector<int> position(static_cast<size_t>(n_gamma_), -1);
  for (const auto& e : entries) position[e.row] = position[e.col] = 0;
  active_.clear();
  for (int g = 0; g < n_gamma_; ++g)
    if (position[g] == 0) {
      position[g] = static_cast<int>(active_.size());
      active_.push_back(g);
    }
  const auto na = static_cast<Eigen::Index>(active_.size());
  // L_JJ has a few entries per row (the facets around a node): sparse
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(entries.size());
  for (const auto& e : entries) triplets.emplace_back(position[e.row], position[e.col], e.value);
  l_active_.resize(na, na);
  l_active_.setFromTriplets(triplets.begin(), triplets.end());
  if (na == 0) return;
  // I + S_JJ L_JJ, S block diagonal (the bodies do not see each other through A).
  const int n_s = static_cast<int>(nodes_[0].size());
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(na, na);
  for (Eigen::Index b = 0; b < na; ++b) {
    const int gb = active_[b];
    const auto& col = column(gb);
    const bool slave_b = gb < n_s;
    for (Eigen::Index a = 0; a < na; ++a) {
      const int ga = active_[a];
      if ((ga < n_s) == slave_b) s(a, b) = col[slave_b ? ga : ga - n_s];
    }
  }
  Eigen::MatrixXd k = s * l_active_;
  k.diagonal().array() += 1.0;
  lu_.compute(k);
}

void InterfaceHeatSolver::solve(const core::Vector& b_slave, const core::Vector& b_master,
                                core::Vector& x_slave, core::Vector& x_master) const {
  const core::Vector* b[2] = {&b_slave, &b_master};
  core::Vector* x[2] = {&x_slave, &x_master};
  for (int i = 0; i < 2; ++i) solver_[i]->solve(*b[i], *x[i]);  // x = G(b): P x = y₀
  if (active_.empty()) return;
  const int n_s = static_cast<int>(nodes_[0].size());
  const auto na = static_cast<Eigen::Index>(active_.size());
  Eigen::VectorXd y0(na);
  {
    const auto xs = x_slave.read();
    const auto xm = x_master.read();
    for (Eigen::Index a = 0; a < na; ++a) {
      const int g = active_[a];
      y0(a) = g < n_s ? xs[nodes_[0][g]] : xm[nodes_[1][g - n_s]];
    }
  }
  const Eigen::VectorXd c = l_active_ * lu_.solve(y0);  // L_Γ y
  bool touched[2] = {false, false};
  for (int i = 0; i < 2; ++i) rhs_[i].copy_from(*b[i]);
  {
    auto rs = rhs_[0].view();
    auto rm = rhs_[1].view();
    for (Eigen::Index a = 0; a < na; ++a) {
      const int g = active_[a];
      if (c(a) == 0.0) continue;
      if (g < n_s) {
        rs[nodes_[0][g]] -= c(a);
        touched[0] = true;
      } else {
        rm[nodes_[1][g - n_s]] -= c(a);
        touched[1] = true;
      }
    }
  }
  for (int i = 0; i < 2; ++i)
    if (touched[i]) solver_[i]->solve(rhs_[i], *x[i]);  // θ = G(b − Pᵀ L_Γ y)
}

}  // namespace tc::physics
