// Element kernels (fem/element.hpp) against closed forms, on regular and distorted cells of
// every type. The closed forms avoid the code under test: cell measures and ∫∇N_a come from
// the divergence theorem on the cell's faces (fixture code below, own shape functions), the
// plane-strain stiffness from the engineering B-matrix with D(E, ν).
//
// Tolerances: all integrands here are polynomials that the kernels' rules integrate exactly
// (or rational on distorted Quad4/Hex8, where the identities tested are exact anyway, e.g.
// Σ_a ∇N_a = 0), so only rounding remains: O(10) operations per entry on O(1) data give
// ~1e-15; 1e-12 (relative to the matrix's scale) leaves margin, and any wrong term, sign or
// factor in a kernel shows up at O(1e-2) or more.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/fem/element.hpp"
#include "tc/mesh/box.hpp"

using namespace tc::fem;
using tc::mesh::CellType;
using tc::mesh::FacetType;

namespace {

constexpr double kLambda = 1.3, kMu = 0.7, kBeta = 0.9, kRho = 2.5, kKappa = 1.7;
constexpr double kTol = 1e-12;

const CellType kAllTypes[] = {CellType::Tri3, CellType::Quad4, CellType::Tet4, CellType::Hex8};

Coords rows(std::initializer_list<std::initializer_list<double>> r) {
  Coords x(static_cast<Eigen::Index>(r.size()), static_cast<Eigen::Index>(r.begin()->size()));
  Eigen::Index i = 0;
  for (const auto& row : r) {
    Eigen::Index j = 0;
    for (const double v : row) x(i, j++) = v;
    ++i;
  }
  return x;
}

/// Reference-shaped cells (unit square/cube, right-angled simplices).
Coords regular(CellType t) {
  switch (t) {
    case CellType::Tri3:
      return rows({{0, 0}, {1, 0}, {0, 1}});
    case CellType::Quad4:
      return rows({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    case CellType::Tet4:
      return rows({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
    case CellType::Hex8:
      return rows(
          {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}});
    default:  // second order: fem_second_order_test
      break;
  }
  return {};
}

/// Distorted cells: general simplices, a non-parallelogram quad, a hex with warped faces.
Coords distorted(CellType t) {
  switch (t) {
    case CellType::Tri3:
      return rows({{0.1, 0.2}, {1.3, 0.1}, {0.4, 1.5}});
    case CellType::Quad4:
      return rows({{0, 0}, {2, 0.2}, {1.7, 1.4}, {-0.3, 1.1}});
    case CellType::Tet4:
      return rows({{0, 0, 0}, {1.2, 0.1, 0}, {0.2, 1.1, 0.1}, {0.1, 0.3, 0.9}});
    case CellType::Hex8:
      return rows({{0.05, -0.1, 0.0},
                   {1.1, 0.05, -0.1},
                   {1.2, 1.1, 0.1},
                   {-0.1, 0.9, 0.05},
                   {0.1, 0.05, 1.1},
                   {0.95, -0.05, 0.9},
                   {1.15, 1.2, 1.05},
                   {0.05, 1.0, 0.95}});
    default:  // second order: fem_second_order_test
      break;
  }
  return {};
}

// ---- Divergence-theorem fixtures: B(a, k) = ∮ N_a n_k dS = ∫ ∂_k N_a dx. -------------------

/// Faces of each cell type, counter-clockwise seen from outside (VTK order).
std::vector<std::vector<int>> faces(CellType t) {
  switch (t) {
    case CellType::Tri3:
      return {{0, 1}, {1, 2}, {2, 0}};
    case CellType::Quad4:
      return {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
    case CellType::Tet4:
      return {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    case CellType::Hex8:
      return {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {0, 4, 7, 3}};
    default:  // second order: fem_second_order_test
      break;
  }
  return {};
}

Eigen::MatrixXd boundary_moments(CellType t, const Coords& x) {
  const auto d = x.cols();
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(x.rows(), d);
  for (const auto& f : faces(t)) {
    if (f.size() == 2) {  // straight edge: ∫ N_a = L/2, n L = (t_y, −t_x)
      const Eigen::Vector2d tan = (x.row(f[1]) - x.row(f[0])).transpose();
      const Eigen::RowVector2d nl(tan[1], -tan[0]);
      for (const int a : f) b.row(a) += 0.5 * nl;
    } else if (f.size() == 3) {  // planar triangle: ∫ N_a = A/3, n A = ½ e1 × e2
      const Eigen::Vector3d e1 = (x.row(f[1]) - x.row(f[0])).transpose();
      const Eigen::Vector3d e2 = (x.row(f[2]) - x.row(f[0])).transpose();
      for (const int a : f) b.row(a) += (e1.cross(e2) / 6).transpose();
    } else {  // bilinear face: ∫ N_a x_ξ × x_η dξdη, biquadratic → 2×2 Gauss is exact
      const double g = 1 / std::sqrt(3.0), s[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (const double xi : {-g, g})
        for (const double eta : {-g, g}) {
          Eigen::Vector3d dxi = Eigen::Vector3d::Zero(), deta = Eigen::Vector3d::Zero();
          double n[4];
          for (int c = 0; c < 4; ++c) {
            n[c] = 0.25 * (1 + s[c][0] * xi) * (1 + s[c][1] * eta);
            dxi += 0.25 * s[c][0] * (1 + s[c][1] * eta) * x.row(f[c]).transpose();
            deta += 0.25 * s[c][1] * (1 + s[c][0] * xi) * x.row(f[c]).transpose();
          }
          for (int c = 0; c < 4; ++c) b.row(f[c]) += n[c] * dxi.cross(deta).transpose();
        }
    }
  }
  return b;
}

/// |cell| = (1/d) ∫ div x = (1/d) Σ_a x_a · B(a, :).
double measure(CellType t, const Coords& x) {
  return x.cwiseProduct(boundary_moments(t, x)).sum() / static_cast<double>(x.cols());
}

/// Rigid motions as interleaved nodal vectors: d translations and d(d−1)/2 rotations.
std::vector<Eigen::VectorXd> rigid_modes(const Coords& x) {
  const auto n = x.rows(), d = x.cols();
  std::vector<Eigen::VectorXd> out;
  for (Eigen::Index k = 0; k < d; ++k) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(d * n);
    for (Eigen::Index a = 0; a < n; ++a) r[d * a + k] = 1;
    out.push_back(r);
  }
  for (Eigen::Index i = 0; i < d; ++i)
    for (Eigen::Index j = i + 1; j < d; ++j) {  // rotation in the (i, j) plane
      Eigen::VectorXd r = Eigen::VectorXd::Zero(d * n);
      for (Eigen::Index a = 0; a < n; ++a) {
        r[d * a + i] = -x(a, j);
        r[d * a + j] = x(a, i);
      }
      out.push_back(r);
    }
  return out;
}

/// Nodal values of the linear displacement u = G x, interleaved.
Eigen::VectorXd linear_u(const Coords& x, const Eigen::MatrixXd& grad) {
  const auto n = x.rows(), d = x.cols();
  Eigen::VectorXd u(d * n);
  for (Eigen::Index a = 0; a < n; ++a) u.segment(d * a, d) = grad * x.row(a).transpose();
  return u;
}

Eigen::MatrixXd some_gradient(Eigen::Index d) {
  Eigen::Matrix3d g;
  g << 0.3, -0.2, 0.5, 0.7, -0.4, 0.1, -0.6, 0.25, 0.2;
  return g.topLeftCorner(d, d);
}

int count_small_eigenvalues(const Eigen::MatrixXd& k) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(k);
  const double top = es.eigenvalues().cwiseAbs().maxCoeff();
  int small = 0;
  for (const double e : es.eigenvalues()) small += std::abs(e) < 1e-10 * top;  // rounding ~1e-15
  return small;
}

/// Runs `body(type, coords)` on the regular and the distorted cell of every type (one test
/// process for all: each process pays the PETSc/MPI start-up).
template <class F>
void for_every_cell(F&& body) {
  for (const auto t : kAllTypes)
    for (const bool warped : {false, true}) {
      SCOPED_TRACE(std::string(tc::mesh::name(t)) + (warped ? " distorted" : " regular"));
      body(t, warped ? distorted(t) : regular(t));
    }
}

}  // namespace

// ---- Reference element ----------------------------------------------------------------------

TEST(Reference, QuadratureWeightsSumToReferenceMeasure) {
  const double expected[] = {0.5, 4.0, 1.0 / 6, 8.0};  // Tri3, Quad4, Tet4, Hex8
  for (const auto t : kAllTypes) {
    double s = 0;
    for (const auto& q : quadrature(t)) s += q.weight;
    EXPECT_NEAR(s, expected[static_cast<int>(t)], 1e-15) << tc::mesh::name(t);
  }
  double line = 0;
  for (const auto& q : quadrature(FacetType::Line2)) line += q.weight;
  EXPECT_NEAR(line, 2.0, 1e-15);
}

TEST(Reference, QuadratureIntegratesQuadraticsExactly) {
  // ∫ ξ² over the reference triangle is 1/12, over the tetrahedron 1/60, over [−1,1]^d 2^d/3.
  const double expected[] = {1.0 / 12, 4.0 / 3, 1.0 / 60, 8.0 / 3};
  for (const auto t : kAllTypes) {
    double s = 0;
    for (const auto& q : quadrature(t)) s += q.weight * q.xi[0] * q.xi[0];
    EXPECT_NEAR(s, expected[static_cast<int>(t)], 1e-15) << tc::mesh::name(t);
  }
}

TEST(Reference, ShapeFunctionsAreNodalAndSumToOne) {
  for (const auto t : kAllTypes) {
    // Reference node positions: the shape functions' own nodes.
    const Coords ref = t == CellType::Quad4 || t == CellType::Hex8
                           ? Coords((2 * regular(t).array() - 1).matrix())
                           : regular(t);
    Eigen::VectorXd n;
    Eigen::MatrixXd dn;
    for (Eigen::Index a = 0; a < ref.rows(); ++a) {
      std::array<double, 3> xi{0, 0, 0};
      for (Eigen::Index k = 0; k < ref.cols(); ++k) xi[k] = ref(a, k);
      shape(t, xi, n, dn);
      for (Eigen::Index b = 0; b < ref.rows(); ++b)
        EXPECT_NEAR(n[b], a == b ? 1.0 : 0.0, 1e-15) << tc::mesh::name(t);
      EXPECT_NEAR(dn.colwise().sum().norm(), 0.0, 1e-15);  // Σ_a ∇N_a = 0
    }
  }
}

// ---- Kernels on every cell type, regular and distorted ---------------------------------------

TEST(EveryCell, MassesSumToDensityTimesMeasure) {
  for_every_cell([](CellType t, const Coords& x) {
    const double vol = measure(t, x);
    ASSERT_GT(vol, 0);
    const auto d = static_cast<double>(x.cols());
    const auto mu = mass_u(t, x, kRho);
    EXPECT_NEAR(mu.sum(), d * kRho * vol, kTol * vol);
    EXPECT_NEAR((mu - mu.transpose()).norm(), 0.0, kTol * mu.norm());
    EXPECT_NEAR(mass_theta(t, x, kRho).sum(), kRho * vol, kTol * vol);
    EXPECT_NEAR(cell_load(t, x).sum(), vol, kTol * vol);
    // cell_load with f = 1 is the row sum of the unit mass (Σ_b N_b = 1).
    const Eigen::VectorXd rowsum = mass_theta(t, x, 1.0).rowwise().sum();
    EXPECT_NEAR((cell_load(t, x) - rowsum).norm(), 0.0, kTol * vol);
  });
}

TEST(EveryCell, RigidMotionsSpanTheKernelOfTheStiffness) {
  for_every_cell([](CellType t, const Coords& x) {
    const auto k = stiffness_u(t, x, kLambda, kMu);
    EXPECT_NEAR((k - k.transpose()).norm(), 0.0, kTol * k.norm());
    for (const auto& r : rigid_modes(x)) EXPECT_LT((k * r).norm(), kTol * k.norm() * r.norm());
    // Full integration: no spurious (hourglass) modes besides the rigid ones.
    const auto d = x.cols();
    EXPECT_EQ(count_small_eigenvalues(k), d * (d + 1) / 2);
  });
}

TEST(EveryCell, LinearDisplacementGivesTheExactStrainEnergy) {
  for_every_cell([](CellType t, const Coords& x) {
    // u = G x has constant ε = sym G, so uᵀ K u = |cell| (λ (tr ε)² + 2μ ε:ε) (2.5) exactly,
    // also in 2D plane strain (ε_zz = 0).
    const auto g = some_gradient(x.cols());
    const Eigen::MatrixXd eps = 0.5 * (g + g.transpose());
    const double density = kLambda * eps.trace() * eps.trace() + 2 * kMu * eps.squaredNorm();
    const auto u = linear_u(x, g);
    const double energy = u.dot(stiffness_u(t, x, kLambda, kMu) * u);
    EXPECT_NEAR(energy, measure(t, x) * density, kTol * std::abs(energy));
  });
}

TEST(EveryCell, CouplingOnAConstantTemperatureIsMinusBetaIntegralOfDivergence) {
  for_every_cell([](CellType t, const Coords& x) {
    // (K_uθ 1)[d·a+k] = −β ∫ ∂_k N_a = −β ∮ N_a n_k.
    const auto c = coupling_u_theta(t, x, kBeta);
    ASSERT_EQ(c.rows(), x.rows() * x.cols());
    ASSERT_EQ(c.cols(), x.rows());
    const Eigen::VectorXd got = c * Eigen::VectorXd::Ones(x.rows());
    const Eigen::MatrixXd b = boundary_moments(t, x);
    for (Eigen::Index a = 0; a < x.rows(); ++a)
      for (Eigen::Index k = 0; k < x.cols(); ++k)
        EXPECT_NEAR(got[x.cols() * a + k], -kBeta * b(a, k), kTol) << a << ", " << k;
    // uᵀ K_uθ 1 = −β ∫ div u = −β tr(G) |cell| for u = G x.
    const auto g = some_gradient(x.cols());
    const double expected = -kBeta * g.trace() * measure(t, x);
    EXPECT_NEAR(linear_u(x, g).dot(got), expected, kTol * std::abs(expected) + kTol);
  });
}

TEST(EveryCell, ConductionHasConstantsInItsKernelAndTheExactDirichletEnergy) {
  for_every_cell([](CellType t, const Coords& x) {
    const auto k = stiffness_theta(t, x, kKappa);
    EXPECT_NEAR((k - k.transpose()).norm(), 0.0, kTol * k.norm());
    EXPECT_LT((k * Eigen::VectorXd::Ones(x.rows())).norm(), kTol * k.norm());
    EXPECT_EQ(count_small_eigenvalues(k), 1);
    // θ = g·x: θᵀ K_θ θ = κ |g|² |cell|.
    const Eigen::VectorXd g = Eigen::Vector3d(0.4, -1.1, 0.7).head(x.cols());
    const Eigen::VectorXd theta = x * g;
    EXPECT_NEAR(theta.dot(k * theta), kKappa * g.squaredNorm() * measure(t, x),
                kTol * theta.dot(k * theta));
  });
}

TEST(EveryCell, CellLoadIntegratesLinearFunctionsExactly) {
  for_every_cell([](CellType t, const Coords& x) {
    // A linear f is exactly Σ_b f_b N_b (isoparametric), so ∫ f N_a = Σ_b M_ab f_b with M the
    // unit mass (verified above) and Σ_a ∫ f N_a = Σ_b f_b ∫ N_b.
    const Func f = [](const tc::mesh::Point& p) { return 1 + p[0] - 2 * p[1] + 3 * p[2]; };
    const auto load = cell_load(t, x, f);
    const Eigen::VectorXd unit = mass_theta(t, x, 1.0).rowwise().sum();
    Eigen::VectorXd fa(x.rows());
    for (Eigen::Index a = 0; a < x.rows(); ++a) {
      tc::mesh::Point p{0, 0, 0};
      for (Eigen::Index k = 0; k < x.cols(); ++k) p[k] = x(a, k);
      fa[a] = f(p);
    }
    // f = Σ_b f_b N_b, so ∫ f N_a = Σ_b M_ab f_b (M the unit mass, exact for these rules).
    EXPECT_NEAR((load - mass_theta(t, x, 1.0) * fa).norm(), 0.0, kTol * fa.norm());
    EXPECT_NEAR(load.sum(), unit.dot(fa), kTol * fa.norm());
  });
}

TEST(EveryCell, StressAndFluxOfLinearFieldsAreExact) {
  for_every_cell([](CellType t, const Coords& x) {
    const auto d = x.cols();
    const auto g = some_gradient(d);
    const Eigen::MatrixXd eps = 0.5 * (g + g.transpose());
    // Uniform Δθ: the centre value is exact whatever the interpolation.
    const Eigen::VectorXd dtheta = Eigen::VectorXd::Constant(x.rows(), 2.0);
    const auto s = cell_stress(t, x, linear_u(x, g), dtheta, kLambda, kMu, kBeta);
    Eigen::Matrix3d e3 = Eigen::Matrix3d::Zero();
    e3.topLeftCorner(d, d) = eps;  // plane strain: ε_zz = 0 in 2D
    const Eigen::Matrix3d expected =
        (kLambda * eps.trace() - kBeta * 2.0) * Eigen::Matrix3d::Identity() + 2 * kMu * e3;
    EXPECT_NEAR((s - expected).norm(), 0.0, kTol * expected.norm());
    const Eigen::VectorXd gt = Eigen::Vector3d(0.4, -1.1, 0.7).head(d);
    const Eigen::VectorXd theta = x * gt;
    const auto q = cell_heat_flux(t, x, theta, kKappa);
    Eigen::Vector3d q_expected = Eigen::Vector3d::Zero();
    q_expected.head(d) = -kKappa * gt;
    EXPECT_NEAR((q - q_expected).norm(), 0.0, kTol);
  });
}

// ---- Hand computations --------------------------------------------------------------------

TEST(HandComputed, ConsistentMassOfUnitSquareAndTriangle) {
  // Quad4 on [0,1]²: ∫ N_a N_b = (1/36)·[4 2 1 2]-circulant; Tri3 of area A: A/12·(1 + δ_ab).
  const auto mq = mass_theta(CellType::Quad4, regular(CellType::Quad4), 36.0);
  const double row[4] = {4, 2, 1, 2};
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) EXPECT_NEAR(mq(a, b), row[(b - a + 4) % 4], kTol);
  const auto x = distorted(CellType::Tri3);
  const double area = measure(CellType::Tri3, x);
  const auto mt = mass_u(CellType::Tri3, x, 12.0 / area);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      EXPECT_NEAR(mt(2 * a, 2 * b), a == b ? 2.0 : 1.0, kTol);
      EXPECT_NEAR(mt(2 * a, 2 * b + 1), 0.0, kTol);  // no coupling between components
    }
}

TEST(HandComputed, PlaneStrainTriangleEqualsEngineeringBTransposeDB) {
  // Constant-strain triangle with D of plane strain in (E, ν):
  //   D = E/((1+ν)(1−2ν)) [[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, (1−2ν)/2]], K = A BᵀDB,
  // B rows (ε_xx, ε_yy, γ_xy), b_a = ∂N_a/∂x = (y_b − y_c)/2A, c_a = (x_c − x_b)/2A.
  const double e = 3.0, nu = 0.3;
  const double lambda = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
  Eigen::Matrix3d dm;
  dm << 1 - nu, nu, 0, nu, 1 - nu, 0, 0, 0, (1 - 2 * nu) / 2;
  dm *= e / ((1 + nu) * (1 - 2 * nu));
  const auto x = distorted(CellType::Tri3);
  const double area =
      0.5 * ((x(1, 0) - x(0, 0)) * (x(2, 1) - x(0, 1)) - (x(2, 0) - x(0, 0)) * (x(1, 1) - x(0, 1)));
  Eigen::Matrix<double, 3, 6> bm = Eigen::Matrix<double, 3, 6>::Zero();
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const double dx = (x(b, 1) - x(c, 1)) / (2 * area), dy = (x(c, 0) - x(b, 0)) / (2 * area);
    bm(0, 2 * a) = dx;
    bm(1, 2 * a + 1) = dy;
    bm(2, 2 * a) = dy;
    bm(2, 2 * a + 1) = dx;
  }
  const Eigen::MatrixXd expected = area * bm.transpose() * dm * bm;
  const auto k = stiffness_u(CellType::Tri3, x, lambda, mu);
  EXPECT_NEAR((k - expected).norm(), 0.0, kTol * expected.norm());
}

TEST(HandComputed, PlaneStrainUnitSquareEntries) {
  // N_0 = (1−x)(1−y) on [0,1]²: K(0x,0x) = ∫ (λ+2μ)(∂_x N_0)² + μ(∂_y N_0)² = (λ+3μ)/3,
  // K(0x,0y) = (λ+μ) ∫ ∂_x N_0 ∂_y N_0 = (λ+μ)/4, K(0x,2x) = −(λ+2μ)/6 − μ/6 (N_2 = xy).
  const auto k = stiffness_u(CellType::Quad4, regular(CellType::Quad4), kLambda, kMu);
  EXPECT_NEAR(k(0, 0), (kLambda + 3 * kMu) / 3, kTol);
  EXPECT_NEAR(k(0, 1), (kLambda + kMu) / 4, kTol);
  EXPECT_NEAR(k(0, 4), -(kLambda + 3 * kMu) / 6, kTol);
}

// ---- Facets -------------------------------------------------------------------------------

TEST(FacetLoad, SumsToTheFacetMeasureAndIntegratesLinearFunctions) {
  const Func f = [](const tc::mesh::Point& p) { return 1 + p[0] - 2 * p[1] + 3 * p[2]; };
  const auto value_at = [&](const Coords& x, Eigen::Index a) {
    tc::mesh::Point p{0, 0, 0};
    for (Eigen::Index k = 0; k < x.cols(); ++k) p[k] = x(a, k);
    return f(p);
  };
  // Edge in 2D: length 5; ∫ f N_a = L (2 f_a + f_b)/6 for linear f.
  const Coords edge = rows({{1, 1}, {4, 5}});
  const auto le = facet_load(FacetType::Line2, edge, f);
  EXPECT_NEAR(facet_load(FacetType::Line2, edge).sum(), 5.0, kTol);
  EXPECT_NEAR(le[0], 5.0 * (2 * value_at(edge, 0) + value_at(edge, 1)) / 6, kTol);
  // Triangle in 3D: area ½|e1 × e2|; ∫ f N_a = A (f_a + Σ_b f_b)/12.
  const Coords tri = rows({{0.1, 0, 0.2}, {1.2, 0.3, 0}, {0.2, 0.9, 0.7}});
  const Eigen::Vector3d e1 = (tri.row(1) - tri.row(0)).transpose();
  const Eigen::Vector3d e2 = (tri.row(2) - tri.row(0)).transpose();
  const double area = 0.5 * e1.cross(e2).norm();
  const auto lt = facet_load(FacetType::Tri3, tri, f);
  EXPECT_NEAR(facet_load(FacetType::Tri3, tri).sum(), area, kTol);
  double sum_f = 0;
  for (int a = 0; a < 3; ++a) sum_f += value_at(tri, a);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(lt[a], area * (value_at(tri, a) + sum_f) / 12, kTol);
  // Planar non-parallelogram quad in 3D (the plane z = x + y): area from its two triangles.
  const Coords quad = rows({{0, 0, 0}, {2, 0.2, 2.2}, {1.7, 1.4, 3.1}, {-0.3, 1.1, 0.8}});
  double quad_area = 0;
  for (const auto& [i, j, k] : {std::array{0, 1, 2}, std::array{0, 2, 3}}) {
    const Eigen::Vector3d a = (quad.row(j) - quad.row(i)).transpose();
    const Eigen::Vector3d b = (quad.row(k) - quad.row(i)).transpose();
    quad_area += 0.5 * a.cross(b).norm();
  }
  EXPECT_NEAR(facet_load(FacetType::Quad4, quad).sum(), quad_area, kTol);
}

TEST(FacetLoad, CoordsComeFromTheMesh) {
  const auto m = tc::mesh::make_box(3, {0, 0, 0}, {2, 1, 1}, {2, 1, 1});
  double area = 0;
  for (const auto& f : m.boundary("zmax")) {
    const auto x = facet_coords(m, f);
    ASSERT_EQ(x.rows(), 4);
    ASSERT_EQ(x.cols(), 3);
    area += facet_load(f.type, x).sum();
  }
  EXPECT_NEAR(area, 2.0, kTol);
  const auto x = cell_coords(m, 1);
  EXPECT_EQ(x.row(0), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(x.row(6), Eigen::RowVector3d(2, 1, 1));
}

// ---- Post-processing and errors ----------------------------------------------------------

TEST(VonMises, UniaxialAndPureShear) {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  s(0, 0) = -5;
  EXPECT_NEAR(von_mises(s), 5.0, 1e-14);
  s.setZero();
  s(1, 2) = s(2, 1) = 2;
  EXPECT_NEAR(von_mises(s), 2 * std::sqrt(3.0), 1e-14);
  EXPECT_NEAR(von_mises(7 * Eigen::Matrix3d::Identity()), 0.0, 1e-14);  // hydrostatic
}

TEST(Kernels, InvertedCellIsReported) {
  Coords x = regular(CellType::Quad4);
  x.row(1).swap(x.row(3));  // clockwise
  EXPECT_THROW((void)stiffness_u(CellType::Quad4, x, kLambda, kMu), tc::MeshError);
  Coords t = regular(CellType::Tet4);
  t.row(1).swap(t.row(2));
  EXPECT_THROW((void)mass_theta(CellType::Tet4, t, 1.0), tc::MeshError);
}
