// Patch tests (Zienkiewicz–Taylor; as in Serac's solid_statics_patch): on distorted meshes of
// every element type, a field the elements represent exactly and whose discrete equations hold
// exactly is reproduced at the interior nodes when its values are imposed on the boundary.
//  - elasticity: u = a + G x (constant stress), K_u u = 0 in the interior;
//  - conduction: θ = c + g·x, K_θ θ = 0 in the interior;
//  - thermal stress: uniform ΔT with the free expansion u = αΔT x, K_u u = −K_uθ ΔT 1
//    (σ = 0 in 3D; in 2D plane strain σ = −λαΔT I_2 is constant, so the interior equations
//    hold as well);
//  - second order (Tri6, Quad8, Quad9, Tet10, Hex20, Hex27), the same on curved cells (every
//    interior node moved, mid-edge ones too: isoparametric cells reproduce linear fields), and
//    quadratic fields, which the second-order spaces hold, on straight-edged cells (corners
//    moved, Quad9/Hex27's bilinear map keeps x², xy, … in Q2; serendipity Quad8/Hex20 hold P2
//    only on affine cells, so theirs are sheared): a quadratic displacement with its constant
//    body force, a quadratic temperature with its constant source, and the free thermal
//    expansion of a linear temperature, stress-free.
// All matrices come from fem::assemble_body with steel constants, so the test also covers the
// assembly (interleaved dofs, 4.1) and the Material moduli.
//
// Tolerance 1e-10 relative: the fields are reproduced exactly in exact arithmetic; the solve
// loses ~cond(K_interior)·1e-16 ≲ 1e2·1e-16 on these ≤ 5³-node meshes, so 1e-10 is a wide
// margin, while an inconsistent element (wrong gradient, under-integration of a distorted cell,
// wrong coupling sign or factor) misses by O(1e-3) or more.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "support/problems.hpp"
#include "support/test_meshes.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/mesh/reference_cell.hpp"
#include "tc/mesh/second_order.hpp"

using namespace tc;
using mesh::CellType;

namespace {

using test::steel;

/// A distorted mesh of [0,1]^d: n cells per axis, interior nodes moved by up to 0.2 h (small
/// enough that every cell stays convex; the kernels throw on an inverted cell). Second order:
/// up to 0.08 h, mid-edge nodes included, which curves the cells' edges while keeping every
/// Jacobian positive (a mid-edge node must stay well within the middle half of its edge).
mesh::Mesh distorted_box(CellType t) {
  const bool second = mesh::order(t) == 2;
  const int n = mesh::dimension(t) == 2 ? (second ? 3 : 5) : (second ? 2 : 3);
  return test::perturb(test::unit_box(t, n), (second ? 0.08 : 0.2) / n, 2024);
}

/// Dofs (with `block` components per node) of the given nodes.
std::vector<PetscInt> node_dofs(const std::vector<int>& nodes, int block) {
  std::vector<PetscInt> out;
  for (const int a : nodes)
    for (int k = 0; k < block; ++k) out.push_back(block * a + k);
  return out;
}

/// Sorted nodes of the xmin, ymin (and zmin) faces: enough to remove every rigid motion.
std::vector<int> min_face_nodes(const mesh::Mesh& m) {
  std::set<int> s;
  for (const char* name : {"xmin", "ymin", "zmin"})
    if (m.has_boundary(name))
      for (const int a : m.boundary_nodes(name)) s.insert(a);
  return {s.begin(), s.end()};
}

using Field = std::function<double(const mesh::Point&, int)>;

/// Imposes `exact` on the `fixed` nodes (default: the whole boundary), solves K x = f and
/// returns max |x − exact| over all dofs relative to max |exact|.
double patch_error(const mesh::Mesh& m, const core::SparseMatrix& k, std::vector<double> f,
                   int block, const Field& exact, std::vector<int> fixed_nodes = {}) {
  if (fixed_nodes.empty()) fixed_nodes = test::all_boundary_nodes(m);
  const auto fixed = node_dofs(fixed_nodes, block);
  std::vector<double> values;
  for (const PetscInt i : fixed) values.push_back(exact(m.point(int(i) / block), int(i) % block));
  const auto x = test::solve_dirichlet(k, std::move(f), fixed, values);
  EXPECT_LT(fixed.size(), x.size()) << "the patch has no interior dofs";
  double err = 0, scale = 0;
  for (int a = 0; a < m.n_nodes(); ++a)
    for (int c = 0; c < block; ++c) {
      const double e = exact(m.point(a), c);
      err = std::max(err, std::abs(x[block * a + c] - e));
      scale = std::max(scale, std::abs(e));
    }
  return err / scale;
}

class Patch : public ::testing::TestWithParam<CellType> {};

std::string type_name(const ::testing::TestParamInfo<CellType>& info) {
  return mesh::name(info.param);
}

}  // namespace

TEST_P(Patch, LinearDisplacementIsReproduced) {
  const auto m = distorted_box(GetParam());
  const int d = m.dim();
  const auto mats = fem::assemble_body(m, steel());
  // u = a + G x with a non-symmetric G: translation, rotation and every strain component.
  const double a[3] = {1e-3, -2e-3, 0.5e-3};
  const double g[3][3] = {{1e-3, 2e-3, -1e-3}, {-0.5e-3, 3e-3, 1.5e-3}, {2e-3, -1e-3, 0.7e-3}};
  const Field exact = [&](const mesh::Point& p, int k) {
    double u = a[k];
    for (int j = 0; j < d; ++j) u += g[k][j] * p[j];
    return u;
  };
  const std::vector<double> zero(static_cast<size_t>(d * m.n_nodes()), 0.0);
  EXPECT_LT(patch_error(m, mats.stiffness_u, zero, d, exact), 1e-10);
}

TEST_P(Patch, LinearTemperatureIsReproduced) {
  const auto m = distorted_box(GetParam());
  const auto mats = fem::assemble_body(m, steel());
  const Field exact = [](const mesh::Point& p, int) {
    return 300 + 20 * p[0] - 35 * p[1] + 12 * p[2];
  };
  const std::vector<double> zero(static_cast<size_t>(m.n_nodes()), 0.0);
  EXPECT_LT(patch_error(m, mats.stiffness_theta, zero, 1, exact), 1e-10);
}

TEST_P(Patch, UniformHeatingGivesFreeExpansion) {
  const auto m = distorted_box(GetParam());
  const int d = m.dim();
  const auto mat = steel();
  const auto mats = fem::assemble_body(m, mat);
  const double dT = 80, alpha = mat.thermal_expansion;
  core::Vector dtheta(m.n_nodes()), rhs(d * m.n_nodes());
  dtheta.fill(dT);
  mats.coupling_u_theta.mult(dtheta, rhs);
  rhs.scale(-1.0);  // K_u u = −K_uθ (θ − θ₀)  (thesis 5.3, quasistatic)
  const Field exact = [&](const mesh::Point& p, int k) { return alpha * dT * p[k]; };
  // (a) Everything prescribed on the boundary, as in the displacement patch test.
  EXPECT_LT(patch_error(m, mats.stiffness_u, rhs.to_std(), d, exact), 1e-10);
  // (b) But then K_uθ 1 vanishes on every interior row (Σ ∫ ∂_k N_a = 0 inside), so (a) cannot
  // see the coupling. Hence also: u prescribed only on the min faces; on the max faces the
  // traction of the free expansion's total stress σ = ((dλ + 2μ)α − β)ΔT I_d (zero in 3D;
  // −λαΔT in 2D plane strain) is applied. Now u = αΔT x everywhere requires K_uθ's rows on
  // the free faces, its sign and β = (3λ + 2μ)α to be right.
  const double lambda = mat.lame_lambda(), mu = mat.lame_mu();
  const double s = ((d * lambda + 2 * mu) * alpha - mat.thermal_stress_modulus()) * dT;
  auto f = rhs.to_std();
  const char* max_faces[] = {"xmax", "ymax", "zmax"};
  for (int k = 0; k < d; ++k) {
    const auto w = fem::boundary_integrals(m, max_faces[k]);  // ∫ N_a dS, normal e_k
    for (int a = 0; a < m.n_nodes(); ++a) f[d * a + k] += s * w[a];
  }
  EXPECT_LT(patch_error(m, mats.stiffness_u, f, d, exact, min_face_nodes(m)), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(EveryElement, Patch,
                         ::testing::Values(CellType::Quad4, CellType::Tri3, CellType::Hex8,
                                           CellType::Tet4, CellType::Tri6, CellType::Quad8,
                                           CellType::Quad9, CellType::Tet10, CellType::Hex20,
                                           CellType::Hex27),
                         type_name);

// ---- Second order: quadratic fields ---------------------------------------------------------

namespace {

/// [0,1]^d in cells of type t with straight edges: the first-order box's interior corners
/// moved by up to 0.2 h, then the second-order nodes placed on the straight edges; Quad8 and
/// Hex20 on an affine (sheared) box instead.
mesh::Mesh straight_box(CellType t) {
  const int d = mesh::dimension(t), n = d == 2 ? 3 : 2;
  const bool serendipity = t == CellType::Quad8 || t == CellType::Hex20;
  auto lin = mesh::make_box(d, {0, 0, 0}, {1, 1, 1}, {n, n, n});
  if (!serendipity) lin = test::perturb(lin, 0.2 / n, 7);
  const auto corners = mesh::corner_type(t);
  if (corners == CellType::Tri3 || corners == CellType::Tet4) lin = mesh::split_into_simplices(lin);
  auto m = mesh::to_second_order(lin, t);
  if (serendipity && d == 2) m.transform({{{1, 0.3, 0}, {0.1, 1, 0}, {0, 0, 1}}}, {0.2, -0.1, 0});
  if (serendipity && d == 3)
    m.transform({{{1, 0.3, 0.2}, {0.1, 1, -0.2}, {0, 0.15, 1}}}, {0.2, -0.1, 0.05});
  return m;
}

class QuadraticPatch : public ::testing::TestWithParam<CellType> {};

/// u_i = ½ xᵀ H_i x + G x, H_i symmetric; the body force f = −div σ is constant:
/// f_i = −((λ + μ) Σ_k (H_k)_ki + μ tr H_i).
const double kH[3][3][3] = {{{2e-3, 1e-3, -1e-3}, {1e-3, -3e-3, 0.5e-3}, {-1e-3, 0.5e-3, 1e-3}},
                            {{-1e-3, 2e-3, 0}, {2e-3, 1e-3, -2e-3}, {0, -2e-3, 3e-3}},
                            {{0.5e-3, 0, 1e-3}, {0, 2e-3, 1e-3}, {1e-3, 1e-3, -1e-3}}};

}  // namespace

TEST_P(QuadraticPatch, QuadraticDisplacementWithItsBodyForce) {
  const auto m = straight_box(GetParam());
  const int d = m.dim();
  const auto mat = steel();
  const double lambda = mat.lame_lambda(), mu = mat.lame_mu();
  const auto mats = fem::assemble_body(m, mat);
  const Field exact = [&](const mesh::Point& p, int i) {
    double u = 1e-3 * (i + 1) * p[(i + 1) % d];
    for (int j = 0; j < d; ++j)
      for (int k = 0; k < d; ++k) u += 0.5 * kH[i][j][k] * p[j] * p[k];
    return u;
  };
  const auto w = fem::volume_integrals(m);  // ∫ N_a
  std::vector<double> f(static_cast<size_t>(d * m.n_nodes()), 0.0);
  for (int i = 0; i < d; ++i) {
    double fi = 0;
    for (int k = 0; k < d; ++k) fi -= (lambda + mu) * kH[k][k][i] + mu * kH[i][k][k];
    for (int a = 0; a < m.n_nodes(); ++a) f[d * a + i] = fi * w[a];
  }
  EXPECT_LT(patch_error(m, mats.stiffness_u, f, d, exact), 1e-10);
}

TEST_P(QuadraticPatch, QuadraticTemperatureWithItsSource) {
  const auto m = straight_box(GetParam());
  const auto mat = steel();
  const auto mats = fem::assemble_body(m, mat);
  // θ = 300 + 20x − 35y + 12z + 40x² − 25xy + 30y² + 15yz − 20z²: −κΔθ = −κ(80 + 60 − 40).
  const bool three = m.dim() == 3;
  const Field exact = [&](const mesh::Point& p, int) {
    return 300 + 20 * p[0] - 35 * p[1] + 12 * p[2] + 40 * p[0] * p[0] - 25 * p[0] * p[1] +
           30 * p[1] * p[1] + 15 * p[1] * p[2] - 20 * p[2] * p[2];
  };
  const double source = -mat.thermal_conductivity * (80 + 60 - (three ? 40 : 0));
  auto f = fem::volume_integrals(m);
  for (double& v : f) v *= source;
  EXPECT_LT(patch_error(m, mats.stiffness_theta, f, 1, exact), 1e-10);
}

TEST_P(QuadraticPatch, LinearTemperatureExpandsFreelyWithoutStress) {
  // Δθ = a + b·x: the strain c Δθ I (c = β/(2(λ + μ)) in-plane in 2D plane strain, α in 3D) is
  // compatible, u_i = c (a x_i + (b·x) x_i − ½ b_i |x|²), and σ = 0 (in 2D its in-plane part).
  const auto m = straight_box(GetParam());
  const int d = m.dim();
  const auto mat = steel();
  const auto mats = fem::assemble_body(m, mat);
  const double lambda = mat.lame_lambda(), mu = mat.lame_mu(), beta = mat.thermal_stress_modulus();
  const double c = d == 2 ? beta / (2 * (lambda + mu)) : mat.thermal_expansion;
  const double a = 30, b[3] = {80, -50, 40};
  const auto dtheta = [&](const mesh::Point& p) {
    double t = a;
    for (int k = 0; k < d; ++k) t += b[k] * p[k];
    return t;
  };
  const Field exact = [&](const mesh::Point& p, int i) {
    double r2 = 0;
    for (int k = 0; k < d; ++k) r2 += p[k] * p[k];
    return c * (dtheta(p) * p[i] - 0.5 * b[i] * r2);
  };
  std::vector<double> nodal;
  for (int n = 0; n < m.n_nodes(); ++n) nodal.push_back(dtheta(m.point(n)));
  const core::Vector th = core::Vector::from(nodal);
  core::Vector rhs(d * m.n_nodes());
  mats.coupling_u_theta.mult(th, rhs);
  rhs.scale(-1.0);
  EXPECT_LT(patch_error(m, mats.stiffness_u, rhs.to_std(), d, exact), 1e-10);
  // The stress of the exact field at each cell centre vanishes (in-plane in 2D), to rounding
  // against the scale βΔθ.
  double worst = 0, scale = 0;
  for (int e = 0; e < m.n_cells(); ++e) {
    const auto x = fem::cell_coords(m, e);
    const auto nodes = m.cell(e);
    Eigen::VectorXd ue(d * x.rows()), te(x.rows());
    for (Eigen::Index n = 0; n < x.rows(); ++n) {
      te[n] = dtheta(m.point(nodes[n]));
      for (int k = 0; k < d; ++k) ue[d * n + k] = exact(m.point(nodes[n]), k);
    }
    const auto s = fem::cell_stress(m.cell_type(e), x, ue, te, lambda, mu, beta);
    worst = std::max(worst, s.topLeftCorner(d, d).cwiseAbs().maxCoeff());
    scale = std::max(scale, beta * te.cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-10 * scale);
}

INSTANTIATE_TEST_SUITE_P(SecondOrder, QuadraticPatch,
                         ::testing::Values(CellType::Tri6, CellType::Quad8, CellType::Quad9,
                                           CellType::Tet10, CellType::Hex20, CellType::Hex27),
                         type_name);

// ---- Assembly bookkeeping ------------------------------------------------------------------

TEST(Assembly, NodeGraphOfABox) {
  // On a Quad4 box a corner node touches 4 nodes (itself included), an edge node 6, an
  // interior node 9; on a Hex8 box an interior node touches 27.
  const auto q = mesh::make_box(2, {0, 0, 0}, {1, 1, 0}, {3, 3, 0});
  const auto g = fem::node_graph(q);
  ASSERT_EQ(g.offsets.size(), size_t(q.n_nodes() + 1));
  EXPECT_EQ(g.degree(0), 4);
  EXPECT_EQ(g.degree(1), 6);
  EXPECT_EQ(g.degree(5), 9);
  const std::vector<int> row0(g.columns.begin() + g.offsets[0], g.columns.begin() + g.offsets[1]);
  EXPECT_EQ(row0, (std::vector<int>{0, 1, 4, 5}));  // sorted
  const auto h = mesh::make_box(3, {0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  EXPECT_EQ(fem::node_graph(h).degree(13), 27);  // the centre node
}

TEST(Assembly, PreallocationIsExactAndMatricesAreConsistent) {
  for (const auto t : {CellType::Tri3, CellType::Hex8}) {
    const auto m = distorted_box(t);
    const auto mat = steel();
    const auto mats = fem::assemble_body(m, mat);
    for (const auto* a : {&mats.mass_u, &mats.stiffness_u, &mats.coupling_u_theta, &mats.mass_theta,
                          &mats.stiffness_theta}) {
      MatInfo info;
      TC_PETSC(MatGetInfo(a->get(), MAT_LOCAL, &info));
      EXPECT_EQ(info.mallocs, 0.0) << mesh::name(t);                // no reallocation
      EXPECT_EQ(info.nz_allocated, info.nz_used) << mesh::name(t);  // nothing left unused
    }
    const int d = m.dim();
    EXPECT_EQ(mats.coupling_u_theta.rows(), d * m.n_nodes());
    EXPECT_EQ(mats.coupling_u_theta.cols(), m.n_nodes());
    // 1ᵀ M_θ 1 = ρ c_p |Ω| = ρ c_p (the unit box); 1ᵀ M_u 1 = d ρ |Ω|: relative rounding only.
    core::Vector one_t(m.n_nodes()), one_u(d * m.n_nodes()), work_t(m.n_nodes()),
        work_u(d * m.n_nodes());
    one_t.fill(1.0);
    one_u.fill(1.0);
    EXPECT_NEAR(mats.mass_theta.quadratic_form(one_t, work_t), mat.heat_capacity(),
                1e-12 * mat.heat_capacity());
    EXPECT_NEAR(mats.mass_u.quadratic_form(one_u, work_u), d * mat.density,
                1e-12 * d * mat.density);
    // Volume and boundary integrals of f = 1: |Ω| = 1 and |∂Ω ∩ {x = 1}| = 1.
    double vol = 0, area = 0;
    for (const double v : fem::volume_integrals(m)) vol += v;
    for (const double v : fem::boundary_integrals(m, "xmax")) area += v;
    EXPECT_NEAR(vol, 1.0, 1e-12);
    EXPECT_NEAR(area, 1.0, 1e-12);
  }
}

TEST(Assembly, ErrorNormsOfKnownFields) {
  // On [0,1]^d with u_h = 0 and exact u = x: ‖u‖_L2 = √(1/3), |u|_H1 = 1 per component; with
  // u_h the interpolant of a linear field the errors vanish. Smooth integrands on affine or
  // distorted cells with a rule exact to degree ≥ 5 on simplices: rounding only (1e-12).
  for (const auto t : {CellType::Quad4, CellType::Tri3, CellType::Hex8, CellType::Tet4}) {
    const auto m = distorted_box(t);
    const int d = m.dim();
    const std::vector<double> zero(static_cast<size_t>(d * m.n_nodes()), 0.0);
    const auto x_k = [](const mesh::Point& p, int k) { return p[k]; };
    const auto e_k = [](const mesh::Point&, int k) { return Eigen::Vector3d::Unit(k); };
    const auto e = fem::error_norms(m, zero, d, x_k, e_k);
    EXPECT_NEAR(e.l2, std::sqrt(d / 3.0), 1e-12) << mesh::name(t);
    EXPECT_NEAR(e.h1, std::sqrt(double(d)), 1e-12) << mesh::name(t);
    std::vector<double> interp;
    for (int a = 0; a < m.n_nodes(); ++a)
      for (int k = 0; k < d; ++k) interp.push_back(m.point(a)[k]);
    const auto z = fem::error_norms(m, interp, d, x_k, e_k);
    EXPECT_LT(z.l2, 1e-14) << mesh::name(t);
    EXPECT_LT(z.h1, 1e-13) << mesh::name(t);
  }
}
