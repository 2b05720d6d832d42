#include "tc/io/output/probes.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "tc/core/verify.hpp"
#include "tc/fem/element.hpp"
#include "tc/mesh/reference_cell.hpp"
#include "tc/run/simulation.hpp"

namespace tc::io {

namespace {

/// Whether ξ lies in the reference cell of t (to `tol`): the unit simplex for Tri3/Tet4,
/// [−1, 1]^d for Quad4/Hex8.
bool inside(mesh::CellType t, const Eigen::Vector3d& xi, int dim, double tol) {
  const auto corners = mesh::corner_type(t);
  if (corners == mesh::CellType::Tri3 || corners == mesh::CellType::Tet4) {
    double sum = 0;
    for (int k = 0; k < dim; ++k) {
      if (xi[k] < -tol) return false;
      sum += xi[k];
    }
    return sum <= 1 + tol;
  }
  for (int k = 0; k < dim; ++k)
    if (std::abs(xi[k]) > 1 + tol) return false;
  return true;
}

}  // namespace

std::optional<ProbeStencil> locate_point(const mesh::Mesh& m, const std::array<double, 3>& x) {
  const int dim = m.dim();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  for (int k = 0; k < dim; ++k) target[k] = x[k];
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto nodes = m.cell(c);
    // A cheap rejection by the cell's bounding box (widened by 1e-9 of its size).
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (const int a : nodes)
      for (int k = 0; k < dim; ++k) {
        lo[k] = std::min(lo[k], m.point(a)[k]);
        hi[k] = std::max(hi[k], m.point(a)[k]);
      }
    bool near = true;
    for (int k = 0; k < dim; ++k) {
      const double pad = 1e-9 * (hi[k] - lo[k]);
      near = near && target[k] >= lo[k] - pad && target[k] <= hi[k] + pad;
    }
    if (!near) continue;
    const auto type = m.cell_type(c);
    const auto xe = fem::cell_coords(m, c);
    Eigen::Vector3d xi = Eigen::Vector3d::Zero();
    Eigen::VectorXd n;
    Eigen::MatrixXd dn;
    for (int it = 0; it < 20; ++it) {  // Newton on x(ξ) = target; bilinear maps converge fast
      fem::shape(type, {xi[0], xi[1], xi[2]}, n, dn);
      const Eigen::VectorXd r = target.head(dim) - xe.transpose() * n;
      const Eigen::MatrixXd j = xe.transpose() * dn.leftCols(dim);  // ∂x/∂ξ
      const Eigen::VectorXd step = j.partialPivLu().solve(r);
      xi.head(dim) += step;
      if (step.norm() < 1e-14) break;
    }
    if (!inside(type, xi, dim, 1e-10)) continue;
    fem::shape(type, {xi[0], xi[1], xi[2]}, n, dn);
    ProbeStencil s;
    s.nodes.assign(nodes.begin(), nodes.end());
    s.weights.assign(n.data(), n.data() + n.size());
    return s;
  }
  return std::nullopt;
}

std::vector<ProbeStencil> probe_stencils(const physics::Problem& p) {
  std::vector<ProbeStencil> out;
  for (const auto& probe : p.output.probes) {
    const auto& m = p.bodies[static_cast<size_t>(probe.body)].mesh;
    ProbeStencil s;
    if (!probe.where.empty()) {
      s.nodes = m.boundary_nodes(probe.where);
      s.weights.assign(s.nodes.size(), 1.0 / static_cast<double>(s.nodes.size()));
    } else {
      auto located = locate_point(m, probe.point);
      TC_VERIFY(located.has_value(), "a probe's point lies in its body (checked on reading)");
      s = std::move(*located);
    }
    s.body = probe.body;
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<std::string> probe_columns(const physics::Problem& p) {
  std::vector<std::string> columns{"step", "time"};
  const char* axes[] = {"x", "y", "z"};
  for (const auto& probe : p.output.probes) {
    columns.push_back(probe.name + "_temperature");
    for (const char* field : {"displacement", "velocity"})
      for (int k = 0; k < p.dimension; ++k)
        columns.push_back(probe.name + "_" + field + "_" + axes[k]);
  }
  return columns;
}

std::vector<double> probe_row(const physics::Simulation& sim,
                              const std::vector<ProbeStencil>& stencils) {
  std::vector<double> row{static_cast<double>(sim.step()), sim.time()};
  const int dim = sim.problem().dimension;
  // Each body's state copied once a step, however many probes read it.
  struct Values {
    std::vector<double> theta, u, v;
  };
  std::vector<std::optional<Values>> bodies(static_cast<size_t>(sim.n_bodies()));
  for (const auto& s : stencils) {
    auto& b = bodies[static_cast<size_t>(s.body)];
    if (!b) {
      const auto& st = sim.state(s.body);
      b = Values{st.theta.to_std(), st.u.to_std(), st.v.to_std()};
    }
    double t = 0;
    for (size_t i = 0; i < s.nodes.size(); ++i)
      t += s.weights[i] * b->theta[static_cast<size_t>(s.nodes[i])];
    row.push_back(t);
    for (const auto* field : {&b->u, &b->v})
      for (int k = 0; k < dim; ++k) {
        double value = 0;
        for (size_t i = 0; i < s.nodes.size(); ++i)
          value += s.weights[i] * (*field)[static_cast<size_t>(dim * s.nodes[i] + k)];
        row.push_back(value);
      }
  }
  return row;
}

}  // namespace tc::io
