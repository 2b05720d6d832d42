#pragma once
// Heat across the open gap (issue 38): the conductance h ≥ 0 at each contact node of a pair
// from the gap of its rows (a table, gas conduction) and the faces' temperatures (radiation),
// which ContactHeatCoupling adds to β_C,k γ_k in L_θγ.
#include <vector>

#include "tc/contact/contact_rows.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/model/problem.hpp"

namespace tc::physics {

/// Stefan–Boltzmann's constant σ [W/(m²K⁴)] (CODATA 2018, exact in the SI).
inline constexpr double kStefanBoltzmann = 5.670374419e-8;

/// h(g) = h_table(g⁺) + k_gas/(g⁺ + g₀) [W/(m²K)], g⁺ = max(g, 0): at closure (g = 0) h(0),
/// which stays added to β_C p_n in contact, so the conductance has no jump as the gap closes.
[[nodiscard]] double gap_conductance(const GapConductance& law, double gap);

/// h_rad = σε(θ_s² + θ_m²)(θ_s + θ_m): the net radiation σε(θ_s⁴ − θ_m⁴) between two parallel
/// grey faces (ε = GapConductance::effective_emissivity) as a conductance times θ_s − θ_m,
/// exactly (the secant of θ⁴).
[[nodiscard]] double gap_radiation(double emissivity, double theta_s, double theta_m);

/// θ of both faces at each contact node of a mortar pair: θ_s at the slave node, θ_m =
/// (Mθ_m)_k/(D1)_k (master_at_nodes), and whether the master covers the node ((D1)_k > 0).
struct GapFaces {
  std::vector<double> slave, master;
  std::vector<char> covered;
};
[[nodiscard]] GapFaces gap_faces(const contact::MortarPair& mortar, const core::Vector& theta_slave,
                                 const core::Vector& theta_master);

/// h(g_k) per contact node of `rows`, g_k = (weighted gap)_k / (∫ψ_k), the gap at the node in
/// the rows' configuration (t^k) for the dual basis (D diagonal, Σ_j M_kj = D_kk where the master
/// covers ψ_k); 0 at a node of no weight. With `faces` (a law with radiation), + h_rad at the
/// faces' temperatures where the master covers the node.
[[nodiscard]] std::vector<double> nodal_gap_conductance(const GapConductance& law,
                                                        const contact::ContactRows& rows,
                                                        const GapFaces* faces = nullptr);

}  // namespace tc::physics
