// Dual mortar on curved second-order surfaces: clipping on the corners' chords against
// clipping on sub-facets (MortarOptions::curved_face_divisions 1 against 2; docs/choices.md,
// "Clipping curved second-order faces on sub-facets").
//
// Set-up: two blocks of second-order cells (Tet10, Hex20, Hex27) mapped onto concentric
// spherical shells, (x, y, z) ↦ radius R + t z, longitude (x − ½)S, latitude L₀ + (y − ½)S
// (R = 1, t = 0.2, S = 1, L₀ = 0.5: the slave patch spans latitudes 0 to 1 rad). Every node,
// mid-edge and centre ones included, is mapped, so the faces' edges follow the images of
// straight parameter lines: lines of latitude have the geodesic curvature tan(lat)/R, their
// mid-edge nodes leave the corners' chords in the tangent plane by O(h²/R), and the corners'
// polygon of a face is not the projection of its boundary. The slave (n × n cells on the
// patch) is covered by a larger master meshed differently (1.25 n cells over 1.45 times the
// span; non-matching everywhere).
//
// Quantities, with their independent computations:
//  - the weights d̃_k = ∫ψ_k (= ∫φ̃_k, biorthogonality) against ∫_S φ̃_k dS integrated on the
//    slave facets themselves (8 × 8 Gauss on the reference cell, no projection, no clipping):
//    the slave is wholly covered, so the two are the same integral of the same surface and
//    differ only by the segmentation's geometric error; Σ D = Σ M = Σ d̃_k against the slave
//    surface's area the same way (Σ M = Σ D by the partition of unity of the master functions);
//  - the transfer D⁻¹M f_m of smooth fields (linear and quadratic in x) onto the slave nodes
//    against f(x_k), surfaces at zero gap;
//  - the weighted gap of the shells δ apart: g_k/d̃_k against δ (the projection along the slave
//    face's normal adds δ(1/cos θ − 1) = O(δ h²/R²), the same for both clippings).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "mortar_fixtures.hpp"
#include "tc/contact/integration.hpp"
#include "tc/core/error.hpp"
#include "tc/mesh/second_order.hpp"

namespace tc::test {
namespace {

using contact::MortarOptions;
using contact::MortarPair;
using mesh::CellType;

constexpr double kRadius = 1, kThickness = 0.2, kSpan = 1, kLatitude = 0.5;

mesh::Point on_sphere(const mesh::Point& p) {
  const double r = kRadius + kThickness * p[2];
  const double lon = (p[0] - 0.5) * kSpan, lat = kLatitude + (p[1] - 0.5) * kSpan;
  return {r * std::cos(lat) * std::cos(lon), r * std::cos(lat) * std::sin(lon), r * std::sin(lat)};
}

/// A box as cells of `element`, every node (second-order ones included) mapped onto the shell.
mesh::Mesh shell(const mesh::Mesh& box, CellType element) {
  const CellType corners = mesh::corner_type(element);
  mesh::Mesh m = corners == CellType::Tet4 ? mesh::split_into_simplices(box) : box;
  m = mesh::order(element) == 2 ? mesh::to_second_order(m, element) : m;
  return moved(m, [](int, const mesh::Point& p) { return on_sphere(p); });
}

struct Surfaces {
  CellType slave, master;
};

/// ∫ φ̃_k dS over the slave facets (φ̃ = Tφ, the transformed basis) and their area, by 8 × 8
/// Gauss on each reference cell: the integrands are smooth, and 8 points per direction leave
/// a quadrature error below 1e-14 of the weights here (4 points change them by < 1e-12).
struct Reference {
  std::map<int, double> weight;
  double area = 0;
};
Reference reference(const mesh::Mesh& m, const std::string& boundary) {
  Reference r;
  const auto line = contact::gauss_line(8);
  for (const auto& f : m.boundary(boundary)) {
    const bool tri = mesh::corner_type(f.type) == mesh::FacetType::Tri3;
    const auto tr = contact::basis_transformation(f.type);
    auto add = [&](const contact::Vec2& xi, double w) {
      const auto s = contact::facet_shape(f.type, xi);
      contact::Vec3 dx{0, 0, 0}, dy{0, 0, 0};
      for (int a = 0; a < s.n; ++a) {
        dx = dx + s.dphi[a][0] * m.point(f.nodes[a]);
        dy = dy + s.dphi[a][1] * m.point(f.nodes[a]);
      }
      const double ds = w * contact::norm(contact::cross(dx, dy));
      r.area += ds;
      for (int a = 0; a < s.n; ++a) {
        double phi = 0;
        for (int b = 0; b < s.n; ++b) phi += tr.t[a][b] * s.phi[b];
        r.weight[f.nodes[a]] += ds * phi;
      }
    };
    if (tri) {
      for (const auto& g : contact::gauss_triangle(8)) add({g.r, g.s}, 0.5 * g.w);
    } else {
      for (const auto& u : line)
        for (const auto& v : line) add({2 * u.s - 1, 2 * v.s - 1}, 4 * u.w * v.w);
    }
  }
  return r;
}

double linear(const mesh::Point& x) {
  return 0.3 + 1.7 * x[0] - 0.9 * x[1] + 0.4 * x[2];
}
double quadratic(const mesh::Point& x) {
  return 0.3 + 1.7 * x[0] - 0.9 * x[1] + 0.4 * x[2] + 0.8 * x[0] * x[0] - 1.1 * x[0] * x[1] +
         0.6 * x[1] * x[2] - 0.5 * x[2] * x[2];
}

struct Measured {
  double h = 0;
  double area = 0;       // |Σ D − A_h| / A_h
  double weight = 0;     // max_k |d̃_k − ∫φ̃_k| / max_k ∫φ̃_k
  double weight_l1 = 0;  // Σ_k |d̃_k − ∫φ̃_k| / Σ_k ∫φ̃_k
  double linear = 0;     // transfer errors, max over slave nodes / max |f|
  double quadratic = 0;
  double gap = 0;           // max_k |g_k/d̃_k − δ| / δ
  double microseconds = 0;  // update() per contact node
  size_t segments = 0, contact_nodes = 0;
};

constexpr double kDelta = 1e-3;  // the shells' distance for the gap

Measured measure(const Surfaces& s, int n, int divisions) {
  Measured out;
  out.h = kSpan / n;
  const int nm = (5 * n) / 4;
  const auto make = [&](double gap) {
    return std::pair{shell(slave_block(3, 0, 1, n, gap / kThickness), s.slave),
                     shell(master_block(3, -0.2, 1.25, nm), s.master)};
  };
  MortarOptions options;
  options.curved_face_divisions = divisions;
  {
    const auto [slave, master] = make(0);
    MortarPair pair(slave, "zmin", master, "zmax", options);
    const Reference ref = reference(slave, "zmin");
    out.area = std::abs(sum_of(pair.d_matrix()) - ref.area) / ref.area;
    // Σ M = Σ D: the master functions sum to 1 at every point.
    EXPECT_NEAR(sum_of(pair.m_matrix()), sum_of(pair.d_matrix()), 1e-12 * ref.area);
    double wmax = 0, diff = 0, total = 0;
    EXPECT_EQ(pair.contact_nodes().size(), ref.weight.size());
    for (const auto& [node, w] : ref.weight) {
      const int k = pair.contact_index(node);
      const double d = k >= 0 ? pair.weights()[static_cast<size_t>(k)] : 0.0;
      out.weight = std::max(out.weight, std::abs(d - w));
      wmax = std::max(wmax, w);
      diff += std::abs(d - w);
      total += w;
    }
    out.weight /= wmax;
    out.weight_l1 = diff / total;
    out.linear = transfer(pair, slave, master, linear).error;
    out.quadratic = transfer(pair, slave, master, quadratic).error;
    out.segments = pair.segments().size();
    out.contact_nodes = pair.contact_nodes().size();
    const int repeats = 1;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < repeats; ++i) pair.update();
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.microseconds = 1e6 * t / repeats / static_cast<double>(out.contact_nodes);
  }
  {
    const auto [slave, master] = make(kDelta);
    const MortarPair pair(slave, "zmin", master, "zmax", options);
    for (size_t k = 0; k < pair.gap().size(); ++k)
      out.gap = std::max(out.gap, std::abs(pair.gap()[k] / pair.weights()[k] - kDelta) / kDelta);
  }
  return out;
}

double rate(double coarse, double fine) {
  return std::log2(coarse / fine);  // h halves between levels
}

void print(const char* name, int divisions, const std::vector<Measured>& rows) {
  std::printf("[ measure  ] %s, %s\n", name,
              divisions == 1 ? "corners' chords" : "sub-facets (2 per edge)");
  std::printf(
      "| h | ΣD − A | max weight err | L1 weight err (rate) | linear transfer (rate) | "
      "quadratic transfer (rate) | gap (rate) | segments | µs per contact node |\n");
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    auto rt = [&](double Measured::*m) { return i == 0 ? 0.0 : rate(rows[i - 1].*m, r.*m); };
    std::printf(
        "| %.4f | %.2e | %.2e | %.2e (%.2f) | %.2e (%.2f) | %.2e (%.2f) | %.2e (%.2f) | %zu | "
        "%.1f |\n",
        r.h, r.area, r.weight, r.weight_l1, rt(&Measured::weight_l1), r.linear,
        rt(&Measured::linear), r.quadratic, rt(&Measured::quadratic), r.gap, rt(&Measured::gap),
        r.segments, r.microseconds);
  }
}

class CurvedMortar : public ::testing::TestWithParam<Surfaces> {};

// Measured (h = S/4, S/8, S/16; the rates between levels): the weights' L1 error with chords
// 1.37e-2, 3.60e-3, 9.26e-4 (Tet10; rate 1.93, 1.96), 9.98e-3, 2.59e-3, 6.59e-4 (Hex20),
// 1.03e-2, 2.63e-3, 6.64e-4 (Hex27): O(h²/R²); with sub-facets 3.16e-3, 8.29e-4, 2.11e-4 (Tet10),
// 2.48e-3, 6.45e-4, 1.64e-4 (Hex20), 2.55e-3, 6.54e-4, 1.65e-4 (Hex27): the same rate, 0.23–0.25
// of the chords' (each chord's sagitta is ¼ of the edge's). |ΣD − A|/A likewise (1.07e-2 → 2.67e-3
// on Tet10 at S/4). The transfers and the gaps agree between the two to 2–3 digits (linear
// transfer rates 2.7–4.1, gap rates 2.8–4.0): D and M are integrated over the same domain with
// the same maps, so biorthogonality keeps D⁻¹M and g_k/d̃_k consistent whatever the domain.
// Asserted on S/4 and S/8 (the finest level's dense solves cost minutes): the chords' weight
// error converges at ≥ 1.7 (measured ≥ 1.93), the sub-facets' weight and area errors are
// ≤ 0.3 of the chords' (measured 0.23–0.25; ¼ by the sagitta), the linear transfer and the gap
// are the same within 5 % (measured ≤ 2 %) and converge at ≥ 2.5 (measured ≥ 2.8).
TEST_P(CurvedMortar, SubFacetsDivideTheWeightsErrorAndLeaveTransferAndGapAlone) {
  const auto s = GetParam();
  const std::string name = std::string(mesh::name(s.slave)) + " on " + mesh::name(s.master);
  std::vector<Measured> chords, sub;
  for (const int n : {4, 8}) {
    chords.push_back(measure(s, n, 1));
    sub.push_back(measure(s, n, 2));
  }
  print(name.c_str(), 1, chords);
  print(name.c_str(), 2, sub);
  EXPECT_GT(rate(chords[0].weight_l1, chords[1].weight_l1), 1.7);
  for (size_t i = 0; i < chords.size(); ++i) {
    EXPECT_LT(sub[i].weight_l1, 0.3 * chords[i].weight_l1) << i;
    EXPECT_LT(sub[i].area, 0.3 * chords[i].area) << i;
    EXPECT_NEAR(sub[i].linear, chords[i].linear, 0.05 * chords[i].linear) << i;
    EXPECT_NEAR(sub[i].gap, chords[i].gap, 0.05 * chords[i].gap) << i;
  }
  for (const auto* r : {&chords, &sub}) {
    EXPECT_GT(rate((*r)[0].linear, (*r)[1].linear), 2.5);
    EXPECT_GT(rate((*r)[0].gap, (*r)[1].gap), 2.5);
  }
}

TEST(CurvedMortarFaces, StraightEdgedFacesKeepTheCornersPolygon) {
  // A flat box of Hex20 cells: no face has curved edges, so sub-facets change nothing, to the
  // bit (the same clip calls in the same order).
  const auto slave = mesh::to_second_order(slave_block(3, 0, 1, 3), CellType::Hex20);
  const auto master = mesh::to_second_order(master_block(3, -0.2, 1.25, 4), CellType::Hex20);
  MortarOptions sub;
  sub.curved_face_divisions = 2;
  const MortarPair a(slave, "zmin", master, "zmax"), b(slave, "zmin", master, "zmax", sub);
  ASSERT_EQ(a.segments().size(), b.segments().size());
  expect_same_rows(b.rows(), a.rows(), 0.0);
  EXPECT_THROW(MortarPair(slave, "zmin", master, "zmax", MortarOptions{.curved_face_divisions = 5}),
               Error);
}

INSTANTIATE_TEST_SUITE_P(Pairs, CurvedMortar,
                         ::testing::Values(Surfaces{CellType::Tet10, CellType::Tet10},
                                           Surfaces{CellType::Hex20, CellType::Hex20},
                                           Surfaces{CellType::Hex27, CellType::Hex27},
                                           Surfaces{CellType::Tet10, CellType::Hex20}),
                         [](const auto& info) {
                           return std::string(mesh::name(info.param.slave)) + "_on_" +
                                  mesh::name(info.param.master);
                         });

}  // namespace
}  // namespace tc::test
