// Reference elements, quadrature rules and the element kernels of thesis ch. 3–4 (the
// bilinear forms (3.2), (3.3) on one cell, assembled as in (4.3), (4.4)).
//
// Performance: kernels are called once per cell and per matrix, ~10⁶ times in the assembly
// benchmark. Reference shape values and gradients at the quadrature points are tabulated once
// per element type; per-point work uses fixed-capacity Eigen types (no heap); the only
// allocations of a kernel are its result.
#include "tc/fem/element.hpp"

#include <cmath>
#include <utility>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/core/verify.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::fem {

namespace {

constexpr int kMaxNodes = mesh::kMaxCellNodes;  // Hex27
// Fixed capacity, dynamic size: lives on the stack.
using NodeVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxNodes, 1>;
using NodeGrad = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxNodes, 3>;
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;

// ---- Quadrature rules ---------------------------------------------------------------------

constexpr double kG = 0.57735026918962576451;  // 1/√3: 2-point Gauss, exact to degree 3

const QuadraturePoint kLine2[] = {{{-kG, 0, 0}, 1.0}, {{kG, 0, 0}, 1.0}};
const QuadraturePoint kQuad2x2[] = {
    {{-kG, -kG, 0}, 1.0}, {{kG, -kG, 0}, 1.0}, {{kG, kG, 0}, 1.0}, {{-kG, kG, 0}, 1.0}};
const QuadraturePoint kHex2x2x2[] = {
    {{-kG, -kG, -kG}, 1.0}, {{kG, -kG, -kG}, 1.0}, {{kG, kG, -kG}, 1.0}, {{-kG, kG, -kG}, 1.0},
    {{-kG, -kG, kG}, 1.0},  {{kG, -kG, kG}, 1.0},  {{kG, kG, kG}, 1.0},  {{-kG, kG, kG}, 1.0}};
// Degree-2 rules on the reference simplices (exact for products of two linear functions);
// weights sum to the reference measure 1/2 (triangle) and 1/6 (tetrahedron).
const QuadraturePoint kTri3[] = {{{1.0 / 6, 1.0 / 6, 0}, 1.0 / 6},
                                 {{2.0 / 3, 1.0 / 6, 0}, 1.0 / 6},
                                 {{1.0 / 6, 2.0 / 3, 0}, 1.0 / 6}};
constexpr double kTa = 0.58541019662496845446, kTb = 0.13819660112501051518;  // (5 ± 3√5)/20
const QuadraturePoint kTet4[] = {{{kTb, kTb, kTb}, 1.0 / 24},
                                 {{kTa, kTb, kTb}, 1.0 / 24},
                                 {{kTb, kTa, kTb}, 1.0 / 24},
                                 {{kTb, kTb, kTa}, 1.0 / 24}};

// ---- Second-order rules: exact for products of two quadratic shape functions (degree 4 on
// the simplices, degree 2 + 2 per direction on the tensor cells), the mass matrices' integrand
// on cells with straight edges; stiffness and coupling need less (degrees 2 and 3).

constexpr double kG3 = 0.77459666924148337704;  // √(3/5): 3-point Gauss, exact to degree 5
constexpr double kG3Points[3] = {-kG3, 0.0, kG3};
constexpr double kG3Weights[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};

/// The 3^d tensor Gauss rule on [−1, 1]^d (d = 1, 2, 3).
std::vector<QuadraturePoint> gauss3(int d) {
  std::vector<QuadraturePoint> out;
  for (int k = 0; k < (d == 3 ? 3 : 1); ++k)
    for (int j = 0; j < (d >= 2 ? 3 : 1); ++j)
      for (int i = 0; i < 3; ++i)
        out.push_back(
            {{kG3Points[i], d >= 2 ? kG3Points[j] : 0.0, d == 3 ? kG3Points[k] : 0.0},
             kG3Weights[i] * (d >= 2 ? kG3Weights[j] : 1.0) * (d == 3 ? kG3Weights[k] : 1.0)});
  return out;
}

/// Strang–Fix/Dunavant's 6-point rule on the triangle, exact to degree 4 (weights of the
/// reference area 1/2).
std::vector<QuadraturePoint> triangle6() {
  constexpr double a = 0.44594849091596488632, wa = 0.22338158967801146570;
  constexpr double b = 0.091576213509770743460, wb = 0.10995174365532186764;
  std::vector<QuadraturePoint> out;
  for (const auto& [x, w] : {std::pair{a, wa}, std::pair{b, wb}}) {
    out.push_back({{x, x, 0}, 0.5 * w});
    out.push_back({{1 - 2 * x, x, 0}, 0.5 * w});
    out.push_back({{x, 1 - 2 * x, 0}, 0.5 * w});
  }
  return out;
}

/// Walkington's (Keast's) 14-point rule on the tetrahedron, exact to degree 5, positive
/// weights (of the reference volume 1/6).
std::vector<QuadraturePoint> tetrahedron14() {
  constexpr double a1 = 0.31088591926330060980, w1 = 0.11268792571801585080;
  constexpr double a2 = 0.092735250310891226402, w2 = 0.073493043116361949544;
  constexpr double a3 = 0.045503704125649649492, w3 = 0.042546020777081466438;
  std::vector<QuadraturePoint> out;
  for (const auto& [x, w] : {std::pair{a1, w1}, std::pair{a2, w2}}) {
    const double y = 1 - 3 * x;  // barycentric (x, x, x, y) and its 4 permutations
    out.push_back({{x, x, x}, w / 6});
    out.push_back({{y, x, x}, w / 6});
    out.push_back({{x, y, x}, w / 6});
    out.push_back({{x, x, y}, w / 6});
  }
  const double b = 0.5 - a3;  // barycentric (a, a, b, b): 6 permutations
  const double pts[6][3] = {{a3, a3, b}, {a3, b, a3}, {b, a3, a3},
                            {b, b, a3},  {b, a3, b},  {a3, b, b}};
  for (const auto& p : pts) out.push_back({{p[0], p[1], p[2]}, w3 / 6});
  return out;
}

const std::vector<QuadraturePoint>& second_order_rule(int dim, bool simplex) {
  static const std::vector<QuadraturePoint> line = gauss3(1), quad = gauss3(2), hex = gauss3(3),
                                            tri = triangle6(), tet = tetrahedron14();
  if (simplex) return dim == 2 ? tri : tet;
  return dim == 1 ? line : dim == 2 ? quad : hex;
}

// ---- Shape functions (templated so that the tables and the public API share them) -----------

// Corners of the reference Quad4 and Hex8 in VTK order.
constexpr double kQuadCorner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
constexpr double kHexCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                     {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

template <class V, class M>
void shape_line(const std::array<double, 3>& xi, V& n, M& dn) {
  n.resize(2);
  dn.resize(2, 1);
  n << 0.5 * (1 - xi[0]), 0.5 * (1 + xi[0]);
  dn << -0.5, 0.5;
}

template <class V, class M>
void shape_tri(const std::array<double, 3>& xi, V& n, M& dn) {
  n.resize(3);
  dn.resize(3, 2);
  n << 1 - xi[0] - xi[1], xi[0], xi[1];
  dn << -1, -1, 1, 0, 0, 1;
}

template <class V, class M>
void shape_quad(const std::array<double, 3>& xi, V& n, M& dn) {
  n.resize(4);
  dn.resize(4, 2);
  for (int a = 0; a < 4; ++a) {
    const double sx = kQuadCorner[a][0], sy = kQuadCorner[a][1];
    n[a] = 0.25 * (1 + sx * xi[0]) * (1 + sy * xi[1]);
    dn(a, 0) = 0.25 * sx * (1 + sy * xi[1]);
    dn(a, 1) = 0.25 * sy * (1 + sx * xi[0]);
  }
}

template <class V, class M>
void shape_tet(const std::array<double, 3>& xi, V& n, M& dn) {
  n.resize(4);
  dn.resize(4, 3);
  n << 1 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2];
  dn << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
}

template <class V, class M>
void shape_hex(const std::array<double, 3>& xi, V& n, M& dn) {
  n.resize(8);
  dn.resize(8, 3);
  for (int a = 0; a < 8; ++a) {
    const double sx = kHexCorner[a][0], sy = kHexCorner[a][1], sz = kHexCorner[a][2];
    const double fx = 1 + sx * xi[0], fy = 1 + sy * xi[1], fz = 1 + sz * xi[2];
    n[a] = 0.125 * fx * fy * fz;
    dn(a, 0) = 0.125 * sx * fy * fz;
    dn(a, 1) = 0.125 * sy * fx * fz;
    dn(a, 2) = 0.125 * sz * fx * fy;
  }
}

/// The second-order types through mesh's shape functions (the isoparametric map the cell
/// checks use too), copied into n and the first `dim` columns of dn.
template <class T, class V, class M>
void shape_second_order(T t, int dim, const std::array<double, 3>& xi, V& n, M& dn) {
  const int nn = mesh::n_nodes(t);
  double v[mesh::kMaxCellNodes], g[3 * mesh::kMaxCellNodes];
  mesh::shape_functions(t, xi, v, g);
  n.resize(nn);
  dn.resize(nn, dim);
  for (int a = 0; a < nn; ++a) {
    n[a] = v[a];
    for (int k = 0; k < dim; ++k) dn(a, k) = g[3 * a + k];
  }
}

int facet_dimension(FacetType t) {
  return t == FacetType::Line2 || t == FacetType::Line3 ? 1 : 2;
}

template <class V, class M>
void shape_any(CellType t, const std::array<double, 3>& xi, V& n, M& dn) {
  switch (t) {
    case CellType::Tri3:
      return shape_tri(xi, n, dn);
    case CellType::Quad4:
      return shape_quad(xi, n, dn);
    case CellType::Tet4:
      return shape_tet(xi, n, dn);
    case CellType::Hex8:
      return shape_hex(xi, n, dn);
    default:
      return shape_second_order(t, mesh::dimension(t), xi, n, dn);
  }
}

template <class V, class M>
void shape_any(FacetType t, const std::array<double, 3>& xi, V& n, M& dn) {
  switch (t) {
    case FacetType::Line2:
      return shape_line(xi, n, dn);
    case FacetType::Tri3:
      return shape_tri(xi, n, dn);
    case FacetType::Quad4:
      return shape_quad(xi, n, dn);
    default:
      return shape_second_order(t, facet_dimension(t), xi, n, dn);
  }
}

/// Reference shape values and gradients at one quadrature point.
struct Tabulated {
  NodeVector n;
  NodeGrad dn;
  double weight = 0;
};

/// The element type's quadrature points with N and ∇_ξ N evaluated once (thread-safe static
/// initialisation; the tables are immutable afterwards).
template <class T>
std::vector<Tabulated> tabulate(T t) {
  std::vector<Tabulated> out;
  for (const auto& q : quadrature(t)) {
    Tabulated p;
    shape_any(t, q.xi, p.n, p.dn);
    p.weight = q.weight;
    out.push_back(p);
  }
  return out;
}

const std::vector<Tabulated>& table(CellType t) {
  static const std::vector<Tabulated> tables[] = {
      tabulate(CellType::Tri3),  tabulate(CellType::Quad4), tabulate(CellType::Tet4),
      tabulate(CellType::Hex8),  tabulate(CellType::Tri6),  tabulate(CellType::Quad8),
      tabulate(CellType::Quad9), tabulate(CellType::Tet10), tabulate(CellType::Hex20),
      tabulate(CellType::Hex27)};
  return tables[static_cast<int>(t)];
}

const std::vector<Tabulated>& table(FacetType t) {
  static const std::vector<Tabulated> tables[] = {
      tabulate(FacetType::Line2), tabulate(FacetType::Tri3), tabulate(FacetType::Quad4),
      tabulate(FacetType::Line3), tabulate(FacetType::Tri6), tabulate(FacetType::Quad8),
      tabulate(FacetType::Quad9)};
  return tables[static_cast<int>(t)];
}

std::array<double, 3> centre(CellType t) {
  // The centroid of the reference cell, where cell_strain, cell_stress and cell_heat_flux
  // evaluate (docs/choices.md, "Cell fields at the reference centre").
  switch (mesh::corner_type(t)) {
    case CellType::Tri3:
      return {1.0 / 3, 1.0 / 3, 0};
    case CellType::Tet4:
      return {0.25, 0.25, 0.25};
    default:
      return {0, 0, 0};
  }
}

// ---- Geometry at a point ------------------------------------------------------------------

/// Physical gradients ∇N = ∇_ξN · J⁻¹ (n × dim) and the weight |J|·w at one point of a cell,
/// J_ij = ∂x_i/∂ξ_j = Σ_a x_ai ∂N_a/∂ξ_j.
struct PointData {
  const NodeVector* n = nullptr;
  NodeGrad grad;
  double jxw = 0;
};

template <int D>
void map_point_fixed(const Coords& x, const NodeGrad& dn, double w, PointData& p) {
  Eigen::Matrix<double, D, D> jac;
  jac.noalias() = x.transpose() * dn;
  const double det = jac.determinant();  // closed form for 2×2 and 3×3
  // A kernel on an inverted or degenerate cell would silently produce a wrong operator.
  if (!(det > 0)) throw MeshError("a cell has a non-positive Jacobian (inverted or degenerate)");
  p.grad.resize(dn.rows(), D);
  p.grad.noalias() = dn * jac.inverse();
  p.jxw = det * w;
}

void map_point(const Coords& x, const NodeGrad& dn, double w, PointData& p) {
  if (x.cols() == 2) {
    map_point_fixed<2>(x, dn, w, p);
  } else {
    map_point_fixed<3>(x, dn, w, p);
  }
}

template <class F>
void for_each_point(CellType t, const Coords& x, F&& f) {
  TC_VERIFY(x.rows() == mesh::n_nodes(t) && x.cols() == mesh::dimension(t),
            "a cell's coordinates are its nodes × its dimension");
  PointData p;
  for (const auto& q : table(t)) {
    map_point(x, q.dn, q.weight, p);
    p.n = &q.n;
    f(p);
  }
}

template <class V>
mesh::Point physical(const V& n, const Coords& x) {
  mesh::Point out{0, 0, 0};
  for (Eigen::Index a = 0; a < x.rows(); ++a)
    for (Eigen::Index k = 0; k < x.cols(); ++k) out[k] += n[a] * x(a, k);
  return out;
}

/// Mirrors the upper block triangle (node blocks b ≥ a, d × d each) onto the lower one.
void mirror_blocks(Eigen::MatrixXd& m, Eigen::Index nn, Eigen::Index d) {
  for (Eigen::Index a = 0; a < nn; ++a)
    for (Eigen::Index b = a + 1; b < nn; ++b)
      m.block(d * b, d * a, d, d) = m.block(d * a, d * b, d, d).transpose();
}

/// stiffness_u of a second-order cell as one product: S = Gᵀ W G over the cell's points, with
/// G(p, i·n + a) = ∂_i N_a(x_p) and W the weights J·w, holds every ∫ ∂_i N_a ∂_j N_b at once,
/// and K's entries are sums of three of S's. On Hex20, Hex27 and Tet10 the product (Eigen's
/// blocked kernel) halves the whole assembly of K_u against the point loop (bench/RESULTS.md);
/// first-order cells keep the loop, whose summation order their histories were recorded with.
Eigen::MatrixXd stiffness_u_by_product(CellType t, const Coords& x, double lambda, double mu) {
  const auto nn = x.rows(), d = x.cols();
  const auto points = static_cast<Eigen::Index>(table(t).size());
  Eigen::MatrixXd g(points, d * nn), gw(points, d * nn);
  Eigen::Index row = 0;
  for_each_point(t, x, [&](const PointData& p) {
    for (Eigen::Index i = 0; i < d; ++i)
      for (Eigen::Index a = 0; a < nn; ++a) {
        g(row, i * nn + a) = p.grad(a, i);
        gw(row, i * nn + a) = p.grad(a, i) * p.jxw;
      }
    ++row;
  });
  const Eigen::MatrixXd s = g.transpose() * gw;
  Eigen::MatrixXd k(d * nn, d * nn);
  for (Eigen::Index a = 0; a < nn; ++a)
    for (Eigen::Index b = 0; b < nn; ++b) {
      double trace = 0;
      for (Eigen::Index m = 0; m < d; ++m) trace += s(m * nn + a, m * nn + b);
      for (Eigen::Index i = 0; i < d; ++i)
        for (Eigen::Index j = 0; j < d; ++j)
          k(d * a + i, d * b + j) = lambda * s(i * nn + a, j * nn + b) +
                                    mu * (s(j * nn + a, i * nn + b) + (i == j ? trace : 0.0));
    }
  return k;
}

}  // namespace

// ---- Public reference-element API -----------------------------------------------------------

std::span<const QuadraturePoint> quadrature(CellType t) {
  switch (t) {
    case CellType::Tri3:
      return kTri3;
    case CellType::Quad4:
      return kQuad2x2;
    case CellType::Tet4:
      return kTet4;
    case CellType::Hex8:
      return kHex2x2x2;
    default:
      return second_order_rule(mesh::dimension(t), mesh::corner_type(t) == CellType::Tri3 ||
                                                       mesh::corner_type(t) == CellType::Tet4);
  }
}

std::span<const QuadraturePoint> quadrature(FacetType t) {
  switch (t) {
    case FacetType::Line2:
      return kLine2;
    case FacetType::Tri3:
      return kTri3;
    case FacetType::Quad4:
      return kQuad2x2;
    default:
      return second_order_rule(facet_dimension(t), t == FacetType::Tri6);
  }
}

void shape(CellType t, const std::array<double, 3>& xi, Eigen::VectorXd& n, Eigen::MatrixXd& dn) {
  shape_any(t, xi, n, dn);
}

void shape(FacetType t, const std::array<double, 3>& xi, Eigen::VectorXd& n, Eigen::MatrixXd& dn) {
  shape_any(t, xi, n, dn);
}

std::vector<CellPoint> cell_points(CellType t, const Coords& x) {
  std::vector<CellPoint> out;
  for_each_point(t, x, [&](const PointData& p) { out.push_back({*p.n, p.grad, p.jxw}); });
  return out;
}

// ---- Kernels ------------------------------------------------------------------------------

Eigen::MatrixXd mass_u(CellType t, const Coords& x, double rho) {
  // m_u(φ_a^i, φ_b^j) = δ_ij ∫ ρ N_a N_b (3.2): the scalar mass on each component.
  const auto nn = x.rows(), d = x.cols();
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(d * nn, d * nn);
  for_each_point(t, x, [&](const PointData& p) {
    const NodeVector& n = *p.n;
    for (Eigen::Index a = 0; a < nn; ++a)
      for (Eigen::Index b = 0; b < nn; ++b) {
        const double v = rho * n[a] * n[b] * p.jxw;
        for (Eigen::Index k = 0; k < d; ++k) m(d * a + k, d * b + k) += v;
      }
  });
  return m;
}

Eigen::MatrixXd stiffness_u(CellType t, const Coords& x, double lambda, double mu) {
  // a_u(φ_b^j, φ_a^i) = ∫ ε(φ_a^i) : C : ε(φ_b^j) with Hooke's law (2.5):
  //   λ ∂_i N_a ∂_j N_b + μ (∂_j N_a ∂_i N_b + δ_ij ∇N_a·∇N_b).
  // In 2D the same formula with i, j ∈ {x, y} is plane strain (ε_zz = 0) of the 3D material.
  // The matrix is symmetric: node blocks b ≥ a are integrated, the rest mirrored.
  if (mesh::order(t) == 2) return stiffness_u_by_product(t, x, lambda, mu);
  const auto nn = x.rows(), d = x.cols();
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(d * nn, d * nn);
  for_each_point(t, x, [&](const PointData& p) {
    const NodeGrad& g = p.grad;
    for (Eigen::Index a = 0; a < nn; ++a)
      for (Eigen::Index b = a; b < nn; ++b) {
        const double mu_gg = mu * g.row(a).dot(g.row(b)) * p.jxw;
        for (Eigen::Index i = 0; i < d; ++i) {
          const double lga = lambda * g(a, i) * p.jxw, mga = mu * p.jxw * g(b, i);
          for (Eigen::Index j = 0; j < d; ++j)
            k(d * a + i, d * b + j) += lga * g(b, j) + mga * g(a, j);
          k(d * a + i, d * b + i) += mu_gg;
        }
      }
  });
  mirror_blocks(k, nn, d);
  return k;
}

Eigen::MatrixXd coupling_u_theta(CellType t, const Coords& x, double beta) {
  // a_uθ(N_b, φ_a^k) = −∫ β N_b ∂_k N_a: the weak form of div(−β(θ − θ₀)I) in (2.5) with the
  // total stress kept whole (docs/choices.md), so no boundary term appears.
  const auto nn = x.rows(), d = x.cols();
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(d * nn, nn);
  for_each_point(t, x, [&](const PointData& p) {
    const NodeVector& n = *p.n;
    for (Eigen::Index a = 0; a < nn; ++a)
      for (Eigen::Index k = 0; k < d; ++k) {
        const double s = -beta * p.grad(a, k) * p.jxw;
        for (Eigen::Index b = 0; b < nn; ++b) c(d * a + k, b) += s * n[b];
      }
  });
  return c;
}

Eigen::MatrixXd mass_theta(CellType t, const Coords& x, double rho_cp) {
  // m_θ(N_b, N_a) = ∫ c N_a N_b with c = ρ c_p (2.8, 3.3).
  const auto nn = x.rows();
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(nn, nn);
  for_each_point(
      t, x, [&](const PointData& p) { m.noalias() += (rho_cp * p.jxw) * *p.n * p.n->transpose(); });
  return m;
}

Eigen::MatrixXd stiffness_theta(CellType t, const Coords& x, double kappa) {
  // a_θ(N_b, N_a) = ∫ κ ∇N_a·∇N_b (2.8, 3.3).
  const auto nn = x.rows();
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(nn, nn);
  for_each_point(t, x, [&](const PointData& p) {
    k.noalias() += (kappa * p.jxw) * p.grad * p.grad.transpose();
  });
  return k;
}

Eigen::VectorXd cell_load(CellType t, const Coords& x, const Func& f) {
  // ∫ f N_a: the volume part of f_u (per component) and f_θ (3.2, 3.3).
  Eigen::VectorXd v = Eigen::VectorXd::Zero(x.rows());
  for_each_point(t, x, [&](const PointData& p) {
    const double value = f ? f(physical(*p.n, x)) : 1.0;
    v += (value * p.jxw) * *p.n;
  });
  return v;
}

Eigen::VectorXd facet_load(FacetType t, const Coords& x, const Func& f) {
  // ∫_facet f N_a dS: the Neumann parts of f_u and f_θ (2.3, 2.10). The surface element is
  // |∂x/∂ξ| (edge) or |∂x/∂ξ × ∂x/∂η| (face); the facet lives in the body's `dim` space.
  TC_VERIFY(x.rows() == mesh::n_nodes(t), "a facet's coordinates are its nodes'");
  Eigen::VectorXd v = Eigen::VectorXd::Zero(x.rows());
  SmallMatrix tangents;
  for (const auto& q : table(t)) {
    tangents.resize(x.cols(), q.dn.cols());
    tangents.noalias() = x.transpose() * q.dn;  // dim × (facet dim)
    double measure = 0;
    if (tangents.cols() == 1) {
      measure = tangents.col(0).norm();
    } else {
      TC_VERIFY(x.cols() == 3, "a face lives in 3D");
      const Eigen::Vector3d t1 = tangents.col(0), t2 = tangents.col(1);
      measure = t1.cross(t2).norm();
    }
    const double value = f ? f(physical(q.n, x)) : 1.0;
    v += (value * measure * q.weight) * q.n;
  }
  return v;
}

Eigen::MatrixXd facet_mass(FacetType t, const Coords& x) {
  // ∫_facet N_a N_b dS with the surface element of facet_load (film boundaries, h∫θv).
  TC_VERIFY(x.rows() == mesh::n_nodes(t), "a facet's coordinates are its nodes'");
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(x.rows(), x.rows());
  SmallMatrix tangents;
  for (const auto& q : table(t)) {
    tangents.resize(x.cols(), q.dn.cols());
    tangents.noalias() = x.transpose() * q.dn;
    const double measure =
        tangents.cols() == 1
            ? tangents.col(0).norm()
            : Eigen::Vector3d(tangents.col(0)).cross(Eigen::Vector3d(tangents.col(1))).norm();
    m.noalias() += (measure * q.weight) * (q.n * q.n.transpose());
  }
  return m;
}

// ---- Post-processing ----------------------------------------------------------------------

Eigen::Matrix3d cell_strain(CellType t, const Coords& x, const Eigen::VectorXd& u_e) {
  // ε = ½(∇u + ∇uᵀ) (2.2); in 2D the plane-strain ε_zz = ε_xz = ε_yz = 0.
  NodeVector n;
  NodeGrad dn;
  shape_any(t, centre(t), n, dn);
  PointData p;
  map_point(x, dn, 1.0, p);
  const auto d = x.cols();
  Eigen::Matrix3d grad_u = Eigen::Matrix3d::Zero();
  for (Eigen::Index a = 0; a < x.rows(); ++a)
    for (Eigen::Index i = 0; i < d; ++i)
      for (Eigen::Index j = 0; j < d; ++j) grad_u(i, j) += u_e[d * a + i] * p.grad(a, j);
  return 0.5 * (grad_u + grad_u.transpose());
}

Eigen::Matrix3d cell_stress(CellType t, const Coords& x, const Eigen::VectorXd& u_e,
                            const Eigen::VectorXd& dtheta_e, double lambda, double mu,
                            double beta) {
  // σ = λ tr ε I + 2με − β(θ − θ₀)I (2.5, docs/choices.md); in 2D ε_zz = 0 (plane strain)
  // but σ_zz = λ tr ε − βΔθ is not.
  NodeVector n;
  NodeGrad dn;
  shape_any(t, centre(t), n, dn);
  const Eigen::Matrix3d eps = cell_strain(t, x, u_e);
  const double dtheta = n.dot(dtheta_e);
  return (lambda * eps.trace() - beta * dtheta) * Eigen::Matrix3d::Identity() + 2 * mu * eps;
}

Eigen::Vector3d cell_heat_flux(CellType t, const Coords& x, const Eigen::VectorXd& theta_e,
                               double kappa) {
  // Fourier's law q = −κ∇θ (2.8).
  NodeVector n;
  NodeGrad dn;
  shape_any(t, centre(t), n, dn);
  PointData p;
  map_point(x, dn, 1.0, p);
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  q.head(x.cols()) = -kappa * p.grad.transpose() * theta_e;
  return q;
}

double von_mises(const Eigen::Matrix3d& s) {
  const double a = s(0, 0) - s(1, 1), b = s(1, 1) - s(2, 2), c = s(2, 2) - s(0, 0);
  return std::sqrt(0.5 * (a * a + b * b + c * c) +
                   3 * (s(0, 1) * s(0, 1) + s(1, 2) * s(1, 2) + s(0, 2) * s(0, 2)));
}

// ---- Gathering coordinates ------------------------------------------------------------------

namespace {
Coords gather(const mesh::Mesh& m, std::span<const int> nodes) {
  Coords x(static_cast<Eigen::Index>(nodes.size()), m.dim());
  for (size_t a = 0; a < nodes.size(); ++a)
    for (int k = 0; k < m.dim(); ++k) x(static_cast<Eigen::Index>(a), k) = m.point(nodes[a])[k];
  return x;
}
}  // namespace

Coords cell_coords(const mesh::Mesh& m, int c) {
  return gather(m, m.cell(c));
}

Coords facet_coords(const mesh::Mesh& m, const mesh::Facet& f) {
  return gather(m, f.node_span());
}

}  // namespace tc::fem
