#pragma once
// Heat across the open gap (issue 38): the conductance h(g) ≥ 0 at each contact node of a pair
// from the gap of its rows, which ContactHeatCoupling adds to β_C,k γ_k in L_θγ.
#include <vector>

#include "tc/contact/contact_rows.hpp"
#include "tc/model/problem.hpp"

namespace tc::physics {

/// h(g) = h_table(g⁺) + k_gas/(g⁺ + g₀) [W/(m²K)], g⁺ = max(g, 0): at closure (g = 0) h(0),
/// which stays added to β_C p_n in contact, so the conductance has no jump as the gap closes.
[[nodiscard]] double gap_conductance(const GapConductance& law, double gap);

/// h(g_k) per contact node of `rows`, g_k = (weighted gap)_k / (∫ψ_k), the gap at the node in
/// the rows' configuration (t^k) for the dual basis (D diagonal, Σ_j M_kj = D_kk where the master
/// covers ψ_k); 0 at a node of no weight.
[[nodiscard]] std::vector<double> nodal_gap_conductance(const GapConductance& law,
                                                        const contact::ContactRows& rows);

}  // namespace tc::physics
