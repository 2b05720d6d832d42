// Thermal contact terms of §4.4 on non-matching, jittered, partially overlapping interfaces in
// 2D and 3D (standard and dual basis; the thermal terms use the nodal φ in both):
//  - L_θγ applied to a constant jump [θ] = a − b with constant γ: the slave rows sum to
//    β_C γ (a − b) × area and the master rows to the opposite; each row of [L_ss L_sm] (and of
//    [L_ms L_mm]) sums to zero (no flux without a jump); L_ms = L_smᵀ; with a nodal γ_k the
//    total is β_C (a − b) Σ_k γ_k weight_k = β_C (a − b) ∫γ;
//  - d_θγ for a uniform tangential relative velocity: slave + master = 𝔉 γ ‖[u̇]_τ‖ × area,
//    split δ_C : 1 − δ_C; a normal relative velocity (plus a common rigid velocity) makes none.
// Tolerances: the integrands are polynomials of degree ≤ 6 integrated exactly (integration.hpp),
// so only round-off remains (≤ 1e-14 relative measured); 1e-12 keeps a margin of 100.
#include <gtest/gtest.h>

#include <random>

#include "mortar_fixtures.hpp"
#include "tc/core/error.hpp"

namespace tc::test {
namespace {

using contact::MortarPair;
using contact::MultiplierBasis;

struct Setup {
  int dim;
  MultiplierBasis basis;
};

class MortarThermal : public ::testing::TestWithParam<Setup> {
 protected:
  void SetUp() override {
    const int d = GetParam().dim;
    // Master offset: covers [0.3, 1] (× [0, 0.75] in 3D) of the slave [0, 1]^(d−1).
    slave_ = jitter(slave_block(d, 0, 1, 9), bottom(d), 0.03, 71);
    master_ = jitter(master_block(d, 0.3, 1.4, 6, -0.2, 0.75), top(d), 0.04, 72);
    if (d == 3) master_ = with_triangles(master_, "zmax", "mixed", 2);
    area_ = d == 2 ? 0.7 : 0.7 * 0.75;
    pair_ = std::make_unique<MortarPair>(slave_, bottom(d), master_, d == 2 ? "ymax" : "mixed",
                                         contact::MortarOptions{GetParam().basis, 0.0});
  }
  [[nodiscard]] std::vector<double> constant(double c) const {
    return std::vector<double>(pair_->contact_nodes().size(), c);
  }

  mesh::Mesh slave_, master_;
  double area_ = 0;
  std::unique_ptr<MortarPair> pair_;
};

/// |value − expected| / |expected|, printed with TC_MORTAR_VERBOSE set.
double relative(const char* what, double value, double expected) {
  const double r = std::abs(value - expected) / std::abs(expected);
  if (std::getenv("TC_MORTAR_VERBOSE")) std::printf("%s: relative error %.2e\n", what, r);
  return r;
}

double total(const std::vector<double>& v) {
  double s = 0;
  for (const double x : v) s += x;
  return s;
}

std::vector<double> plus(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> out(a);
  for (size_t i = 0; i < a.size(); ++i) out[i] += b[i];
  return out;
}

TEST_P(MortarThermal, ConductanceOfAConstantJump) {
  const double beta = 2.5e-3, gamma = 3.7e7, a = 350, b = 300;
  ASSERT_NEAR(pair_->overlap_area(), area_, 1e-12 * area_);
  const auto l = pair_->thermal_conductance(constant(gamma), beta);
  const std::vector<double> ts(slave_.n_nodes(), a), tm(master_.n_nodes(), b);
  const double expected = beta * gamma * (a - b) * area_;
  const auto slave_flux = plus(times(l.ss, ts), times(l.sm, tm));
  const auto master_flux = plus(times(l.ms, ts), times(l.mm, tm));
  EXPECT_LT(relative("L slave rows", total(slave_flux), expected), 1e-12);
  EXPECT_LT(relative("L master rows", total(master_flux), -expected), 1e-12);
  // No jump, no flux: every row vanishes, relative to the row's largest term.
  const std::vector<double> one_s(slave_.n_nodes(), 1.0), one_m(master_.n_nodes(), 1.0);
  const auto rs = plus(times(l.ss, one_s), times(l.sm, one_m));
  const auto rm = plus(times(l.ms, one_s), times(l.mm, one_m));
  const double scale = beta * gamma * area_;
  for (const double r : rs) EXPECT_NEAR(r, 0.0, 1e-14 * scale);
  for (const double r : rm) EXPECT_NEAR(r, 0.0, 1e-14 * scale);
  // L_ms = L_smᵀ and L_ss symmetric (the bilinear form is symmetric).
  const auto sm = entries(l.sm), ms = entries(l.ms), ss = entries(l.ss);
  ASSERT_EQ(sm.size(), ms.size());
  for (const auto& [ij, v] : sm) EXPECT_NEAR(ms.at({ij.second, ij.first}), v, 1e-15 * scale);
  for (const auto& [ij, v] : ss) EXPECT_NEAR(ss.at({ij.second, ij.first}), v, 1e-15 * scale);
}

TEST_P(MortarThermal, ConductanceWithANodalGammaIntegratesGamma) {
  // Affine faces (rectangles of random sizes, triangles): the weights (3 × 3 points) and L
  // (4 × 4) are then both exact. On general quadrilaterals the two rules differ by ~1e-6.
  const int d = GetParam().dim;
  slave_ = jitter_lines(slave_block(d, 0, 1, 9), 0.03, 73);
  master_ = jitter_lines(master_block(d, 0.3, 1.4, 6, -0.2, 0.75), 0.04, 74);
  if (d == 3) master_ = with_triangles(master_, "zmax", "mixed", 2);
  pair_ = std::make_unique<MortarPair>(slave_, bottom(d), master_, d == 2 ? "ymax" : "mixed",
                                       contact::MortarOptions{GetParam().basis, 0.0});
  const double beta = 0.7, a = 2, b = -1;
  std::mt19937 rng(5);
  std::vector<double> gamma = constant(0);
  double integral = 0;  // ∫γ = Σ_k γ_k ∫φ_k = Σ_k γ_k weight_k (both bases)
  for (size_t k = 0; k < gamma.size(); ++k) {
    gamma[k] = 1.0 + rng() / 4294967295.0;
    integral += gamma[k] * pair_->weights()[k];
  }
  const auto l = pair_->thermal_conductance(gamma, beta);
  const std::vector<double> ts(slave_.n_nodes(), a), tm(master_.n_nodes(), b);
  const double expected = beta * (a - b) * integral;
  EXPECT_LT(relative("L nodal gamma", total(plus(times(l.ss, ts), times(l.sm, tm))), expected),
            1e-12);
}

TEST_P(MortarThermal, WrongSizesAreReported) {
  const std::vector<double> short_gamma(pair_->contact_nodes().size() + 1, 1.0);
  EXPECT_THROW((void)pair_->thermal_conductance(short_gamma, 1.0), Error);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MortarThermal,
    ::testing::Values(Setup{2, MultiplierBasis::standard}, Setup{2, MultiplierBasis::dual},
                      Setup{3, MultiplierBasis::standard}, Setup{3, MultiplierBasis::dual}),
    [](const auto& info) {
      return std::to_string(info.param.dim) + "d_" + contact::name(info.param.basis);
    });

}  // namespace
}  // namespace tc::test
