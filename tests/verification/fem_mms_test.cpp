// Manufactured solutions, steady elasticity and heat, 2D and 3D (verification.md): with the
// load computed from a smooth exact solution and Dirichlet data on the whole boundary, the
// observed orders on three refinements must be ≥ 1.9 in L2 and ≥ 0.95 in the H1 seminorm for
// the first-order elements, ≥ 2.9 and ≥ 1.9 for the second-order ones (issue 37).
#include <gtest/gtest.h>

#include <cmath>

#include "support/fe_solve.hpp"
#include "support/problems.hpp"

using namespace tc;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Orders {
  double l2 = 0, h1 = 0;
};

/// θ = Π_k sin(π x_k) + x: the source is r = −κΔθ = κ d π² Π sin.
double theta_exact(const mesh::Point& p, int dim) {
  double s = 1;
  for (int k = 0; k < dim; ++k) s *= std::sin(kPi * p[k]);
  return s + p[0];
}

Eigen::Vector3d theta_grad(const mesh::Point& p, int dim) {
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (int k = 0; k < dim; ++k) {
    double s = kPi * std::cos(kPi * p[k]);
    for (int j = 0; j < dim; ++j)
      if (j != k) s *= std::sin(kPi * p[j]);
    g[k] = s;
  }
  g[0] += 1;
  return g;
}

/// u_i = sin(π x)·sin(π y)·(sin(π z)) · (i + 1) + cos(π x_i)/2 (a smooth vector field).
double u_exact(const mesh::Point& p, int i, int dim) {
  double s = 1;
  for (int k = 0; k < dim; ++k) s *= std::sin(kPi * p[k]);
  return (i + 1) * s + 0.5 * std::cos(kPi * p[i]);
}

Eigen::Vector3d u_grad(const mesh::Point& p, int i, int dim) {
  Eigen::Vector3d g = (i + 1) * (theta_grad(p, dim) - Eigen::Vector3d::UnitX());
  g[i] -= 0.5 * kPi * std::sin(kPi * p[i]);
  return g;
}

/// Body force f = −div σ(u), with the divergence of the analytic stress by central
/// differences (step 1e-5: error ~1e-10, far below the FE errors measured, ≥ 1e-5).
double body_force(const mesh::Point& p, int i, int dim, double lambda, double mu) {
  auto sigma_row = [&](const mesh::Point& x) {
    Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
    for (int r = 0; r < dim; ++r) g.row(r) = u_grad(x, r, dim).transpose();
    const Eigen::Matrix3d eps = 0.5 * (g + g.transpose());
    const Eigen::Matrix3d s = lambda * eps.trace() * Eigen::Matrix3d::Identity() + 2 * mu * eps;
    return Eigen::Vector3d(s.row(i).transpose());
  };
  const double h = 1e-5;
  double div = 0;
  for (int j = 0; j < dim; ++j) {
    mesh::Point a = p, b = p;
    a[j] += h;
    b[j] -= h;
    div += (sigma_row(a)[j] - sigma_row(b)[j]) / (2 * h);
  }
  return -div;
}

fem::ErrorNorms heat_errors(const mesh::Mesh& m) {
  const int dim = m.dim();
  const double kappa = 2.0;
  const auto g = fem::node_graph(m);
  const auto k = fem::assemble(
      m, g, 1, 1, [&](int, auto t, const auto& x) { return fem::stiffness_theta(t, x, kappa); });
  const auto r = fem::volume_integrals(m, [&](const mesh::Point& p) {
    double s = 1;
    for (int j = 0; j < dim; ++j) s *= std::sin(kPi * p[j]);
    return kappa * dim * kPi * kPi * s;
  });
  const auto th = test::solve_dirichlet(k, core::Vector::from(r), test::all_boundary_nodes(m), 1,
                                        [&](int a, int) { return theta_exact(m.point(a), dim); });
  return fem::error_norms(
      m, th, 1, [&](const mesh::Point& p, int) { return theta_exact(p, dim); },
      [&](const mesh::Point& p, int) { return theta_grad(p, dim); });
}

fem::ErrorNorms elasticity_errors(const mesh::Mesh& m) {
  const int dim = m.dim();
  const double lambda = 1.5, mu = 1.0;
  const auto g = fem::node_graph(m);
  const auto k = fem::assemble(m, g, dim, dim, [&](int, auto t, const auto& x) {
    return fem::stiffness_u(t, x, lambda, mu);
  });
  std::vector<double> f(static_cast<size_t>(dim) * m.n_nodes());
  for (int i = 0; i < dim; ++i) {
    const auto fi = fem::volume_integrals(
        m, [&](const mesh::Point& p) { return body_force(p, i, dim, lambda, mu); });
    for (int a = 0; a < m.n_nodes(); ++a) f[dim * a + i] = fi[a];
  }
  const auto u = test::solve_dirichlet(k, core::Vector::from(f), test::all_boundary_nodes(m), dim,
                                       [&](int a, int i) { return u_exact(m.point(a), i, dim); });
  return fem::error_norms(
      m, u, dim, [&](const mesh::Point& p, int i) { return u_exact(p, i, dim); },
      [&](const mesh::Point& p, int i) { return u_grad(p, i, dim); });
}

Orders observed(const std::function<fem::ErrorNorms(int)>& errors, std::vector<int> levels) {
  std::vector<fem::ErrorNorms> e;
  for (const int n : levels) e.push_back(errors(n));
  const double ratio = std::log(static_cast<double>(levels[2]) / levels[1]);
  for (size_t i = 0; i + 1 < e.size(); ++i)  // errors must decrease at every refinement
    EXPECT_LT(e[i + 1].l2, e[i].l2);
  return {std::log(e[1].l2 / e[2].l2) / ratio, std::log(e[1].h1 / e[2].h1) / ratio};
}

struct MmsCase {
  int dim;
  bool simplices;
  bool elasticity;
  const char* name;
};

// Readable test names in ctest (gtest would print the struct's bytes).
void PrintTo(const MmsCase& c, std::ostream* os) {
  *os << c.name;
}

class Mms : public ::testing::TestWithParam<MmsCase> {};

TEST_P(Mms, ObservedOrders) {
  const auto c = GetParam();
  const std::vector<int> levels =
      c.dim == 2 ? std::vector<int>{8, 16, 32} : std::vector<int>{4, 8, 16};
  const auto o = observed(
      [&](int n) {
        auto m = mesh::make_box(c.dim, {0, 0, 0}, {1, 1, 1}, {n, n, n});
        if (c.simplices) m = test::split_to_simplices(m);
        return c.elasticity ? elasticity_errors(m) : heat_errors(m);
      },
      levels);
  RecordProperty("l2_order", std::to_string(o.l2));
  RecordProperty("h1_order", std::to_string(o.h1));
  std::printf("%s: L2 order %.3f, H1 order %.3f\n", c.name, o.l2, o.h1);
  // Linear elements: 2 in L2 and 1 in H1 asymptotically; the bounds leave 5 % for the
  // pre-asymptotic range of the last refinement.
  EXPECT_GE(o.l2, 1.9);
  EXPECT_GE(o.h1, 0.95);
}

INSTANTIATE_TEST_SUITE_P(Fields, Mms,
                         ::testing::Values(MmsCase{2, false, false, "heat_Quad4"},
                                           MmsCase{2, true, false, "heat_Tri3"},
                                           MmsCase{3, false, false, "heat_Hex8"},
                                           MmsCase{3, true, false, "heat_Tet4"},
                                           MmsCase{2, false, true, "elasticity_Quad4"},
                                           MmsCase{2, true, true, "elasticity_Tri3"},
                                           MmsCase{3, false, true, "elasticity_Hex8"},
                                           MmsCase{3, true, true, "elasticity_Tet4"}),
                         [](const auto& info) { return std::string(info.param.name); });

// ---- Second order ----------------------------------------------------------------------------

struct MmsCase2 {
  mesh::CellType type;
  bool elasticity;
  const char* name;
};
void PrintTo(const MmsCase2& c, std::ostream* os) {
  *os << c.name;
}

class Mms2 : public ::testing::TestWithParam<MmsCase2> {};

TEST_P(Mms2, ObservedOrders) {
  const auto c = GetParam();
  const int dim = mesh::dimension(c.type);
  const std::vector<int> levels = dim == 2 ? std::vector<int>{4, 8, 16} : std::vector<int>{2, 4, 8};
  const auto o = observed(
      [&](int n) {
        const auto m = mesh::make_box(dim, {0, 0, 0}, {1, 1, 1}, {n, n, n}, c.type);
        return c.elasticity ? elasticity_errors(m) : heat_errors(m);
      },
      levels);
  RecordProperty("l2_order", std::to_string(o.l2));
  RecordProperty("h1_order", std::to_string(o.h1));
  std::printf("%s: L2 order %.3f, H1 order %.3f\n", c.name, o.l2, o.h1);
  // Quadratic elements: 3 in L2 and 2 in H1 asymptotically (issue 37's bounds).
  EXPECT_GE(o.l2, 2.9);
  EXPECT_GE(o.h1, 1.9);
}

INSTANTIATE_TEST_SUITE_P(
    SecondOrder, Mms2,
    ::testing::Values(MmsCase2{mesh::CellType::Tri6, false, "heat_Tri6"},
                      MmsCase2{mesh::CellType::Quad8, false, "heat_Quad8"},
                      MmsCase2{mesh::CellType::Quad9, false, "heat_Quad9"},
                      MmsCase2{mesh::CellType::Tet10, false, "heat_Tet10"},
                      MmsCase2{mesh::CellType::Hex20, false, "heat_Hex20"},
                      MmsCase2{mesh::CellType::Hex27, false, "heat_Hex27"},
                      MmsCase2{mesh::CellType::Tri6, true, "elasticity_Tri6"},
                      MmsCase2{mesh::CellType::Quad8, true, "elasticity_Quad8"},
                      MmsCase2{mesh::CellType::Quad9, true, "elasticity_Quad9"},
                      MmsCase2{mesh::CellType::Tet10, true, "elasticity_Tet10"},
                      MmsCase2{mesh::CellType::Hex20, true, "elasticity_Hex20"},
                      MmsCase2{mesh::CellType::Hex27, true, "elasticity_Hex27"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
