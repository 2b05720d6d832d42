#pragma once
// The mortar discretisation of one slave–master interface (thesis §4.3–4.4; segment-based
// integration after Puso & Laursen 2004 and Popp, Gitterle, Gee, Wall 2010; dual basis after
// Wohlmuth 2000, on the overlapped part of each face after Popp, Wohlmuth, Gee, Wall 2012).
// Stages as in LLNL Tribol: search (search.hpp), geometry and clipping (geometry.hpp),
// integration (integration.hpp), assembly (assembly.hpp).
//
// Multipliers live on the slave nodes: λ_h = Σ_k λ_k ψ_k. With φ the nodal shape functions,
//   D_kj = ∫ ψ_k φ_j^s dS,   M_kj = ∫ ψ_k (φ_j^m ∘ projection) dS,
// integrated over the part of the slave surface that the master covers. The constraint rows
// of (4.3) and the weighted gap of (2.6), with n_k the slave's averaged outward nodal normal:
//   B_s[normal k] = Σ_j D_kj n_kᵀ (slave dofs of j),  B_m[normal k] = −Σ_j M_kj n_kᵀ (...),
//   g_k = n_k·(Σ_j M_kj x_j^m − Σ_j D_kj x_j^s)  (≥ 0 when open; B_n Δu ≤ g),
// and the same with the tangents τ_l in the tangential rows.
//
// Second-order faces (Line3; Tri6, Quad8, Quad9), either side, against either order: the
// multipliers of a Tri6 or Quad8 slave face are built on the transformed basis φ̃ = Tφ of
// integration.hpp's BasisTransformation (Popp, Wohlmuth, Gee, Wall 2012, §4.4.1), and D, M
// stay over the physical dofs: D = diag(d̃) T⁻ᵀ is then not diagonal in the mid-edge rows
// (docs/theory.md, "Second-order slave faces"). Every slave node, vertex and mid-edge, carries
// a multiplier.
//
// Contract:
//  - Both meshes must outlive the pair (it keeps pointers to them); the pair is movable.
//  - The constructor evaluates the reference configuration (an update() with no displacement).
//  - Every accessor refers to the last update(); references returned by them are invalidated
//    by the next update().
//  - Sequential: every rank that calls it computes the whole interface (matrices on
//    PETSC_COMM_SELF); not collective.
#include <array>
#include <span>
#include <string>
#include <vector>

#include "tc/contact/assembly.hpp"
#include "tc/contact/contact_rows.hpp"
#include "tc/contact/integration.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/mesh/mesh.hpp"

namespace tc::contact {

enum class MultiplierBasis { standard, dual };
[[nodiscard]] const char* name(MultiplierBasis b);

struct MortarOptions {
  MultiplierBasis basis = MultiplierBasis::dual;
  /// Master faces farther than this from the slave face along its normal are skipped: a master
  /// face is a candidate when its bounding box meets the box of the prism swept by the slave
  /// face moved by ±radius along its centre normal (current configuration). 0 = automatic:
  /// the largest facet diameter of the two surfaces in the configuration of the update, i.e.
  /// one element layer, enough for any contact that can close within a step that moves the
  /// surfaces less than an element.
  double search_radius = 0;
  /// A slave node is a contact node when its weight ∫ψ_k exceeds this fraction of the area of
  /// its slave faces. The default keeps every node that the master really covers (Σ D stays
  /// the overlapped area to 1e-12); raise it (e.g. 1e-4) to drop nodes touched only by a
  /// sliver of overlap, whose rows are tiny and make the dual QP (6.9) ill-conditioned.
  double weight_threshold = 1e-12;
  /// α of the basis transformation of Tri6 and Quad8 slave faces (integration.hpp's
  /// BasisTransformation): each vertex function takes α of its two mid-edge neighbours. In
  /// (0, ½) with Tri6 faces and (⅛, ½) with Quad8 faces (positive weights); the default is
  /// 4C's ⅕ (docs/choices.md, "α by measurement").
  double vertex_share = kVertexShare;
  /// 3D second-order faces whose edges are curved (a mid-edge node off its corners' chord,
  /// geometry.hpp's curved_edges) are clipped on their sub-facets, `curved_face_divisions` per
  /// edge (sub_facets; 1 to kMaxDivisions): 1 clips them on their corners' polygon, the chord of
  /// each curved edge (the default: sub-facets divide the weights' O(h²/R²) segmentation
  /// error by divisions² at 2.5–4 times the mortar time and leave the transfer and the gaps
  /// unchanged; docs/choices.md). Faces with straight edges are always clipped on their
  /// corners' polygon.
  int curved_face_divisions = 1;
};

/// Wall-clock seconds of the stages of the last update().
struct MortarTimings {
  double search = 0, geometry = 0, integration = 0, assembly = 0;
};

/// L_θγ of §4.4 split into the blocks over each body's full node numbering: ss (N_s × N_s),
/// sm (N_s × N_m), ms (N_m × N_s), mm (N_m × N_m).
struct ThermalContact {
  core::SparseMatrix ss, sm, ms, mm;
};

/// d_θγ of §4.4: nodal heat inputs over each body's nodes [W] and their sum, the friction
/// work of the step over τ (physics::ContactCoupling::heat_step).
struct FrictionalHeat {
  std::vector<double> slave, master;
  double total = 0;
};

class MortarPair {
 public:
  /// Throws MeshError when a boundary is missing, the dimensions differ, a facet type does
  /// not fit the dimension (Line2, Line3 in 2D; Tri3, Quad4, Tri6, Quad8, Quad9 in 3D), or the
  /// slave surface mixes Quad9 faces with Tri6 or Quad8 faces.
  MortarPair(const mesh::Mesh& slave, std::string slave_boundary, const mesh::Mesh& master,
             std::string master_boundary, MortarOptions options = {});

  /// Evaluates the interface in the configuration X + u (u interleaved: dof d·j + k; an empty
  /// span is the reference configuration). Everything below refers to the last update().
  void update(std::span<const double> u_slave = {}, std::span<const double> u_master = {});

  [[nodiscard]] int dim() const { return dim_; }
  [[nodiscard]] const MortarOptions& options() const { return options_; }
  /// The search radius used by the last update (the automatic one when options say 0).
  [[nodiscard]] double search_radius() const { return radius_; }

  /// Contact node k (row block k of rows()) → slave mesh node, ascending. A slave node is a
  /// contact node when its multiplier has a positive weight ∫ψ_k over the overlapped surface
  /// (more than options().weight_threshold of the area of its faces). The list may change
  /// between updates.
  [[nodiscard]] const std::vector<int>& contact_nodes() const { return contact_nodes_; }
  /// Contact index of a slave mesh node, −1 when it is not a contact node.
  [[nodiscard]] int contact_index(int slave_node) const { return contact_index_[slave_node]; }

  /// B_s, B_m node-major (row dim·k: normal of contact node k, dim·k + 1 + l: tangent l),
  /// columns each body's displacement dofs; gap g_k; weights ∫ψ_k over the overlap. A copy.
  [[nodiscard]] ContactRows rows() const;
  /// Per contact node: the slave's outward averaged nodal normal (unit) and tangents l = 0
  /// (2D, 3D) and 1 (3D), orthonormal with it.
  [[nodiscard]] const std::vector<std::array<double, 3>>& normals() const { return normals_; }
  [[nodiscard]] const std::vector<std::array<double, 3>>& tangents(int l) const;
  [[nodiscard]] const std::vector<double>& gap() const { return gap_; }
  [[nodiscard]] const std::vector<double>& weights() const { return weights_; }
  /// Per contact node: the least covered fraction of its slave faces (the integral over the
  /// overlap against the face's projected area): ≥ 1 where the master covers every face of the
  /// node (a warped or curved face's integral exceeds its projection), < 1 at the edge of the
  /// overlap, where ψ_k lives on the covered part alone and changes as the bodies slide.
  [[nodiscard]] const std::vector<double>& coverage() const { return coverage_; }

  /// D (contact nodes × slave nodes; diagonal, D_kk = ∫ψ_k, with the dual basis, except the
  /// mid-edge rows of Tri6 and Quad8 faces, whose row sum is ∫ψ_k) and M (contact nodes ×
  /// master nodes), scalar.
  [[nodiscard]] const core::SparseMatrix& d_matrix() const { return d_; }
  [[nodiscard]] const core::SparseMatrix& m_matrix() const { return m_; }

  /// L_θγ of §4.4: β_C ∫ γ [θ][χ] dS with γ = Σ_k γ_k φ̃_k^s (γ per contact node; φ̃ = φ but
  /// on Tri6 and Quad8 slave faces, BasisTransformation). The
  /// matrices are the pair's own: the next call overwrites their values (update() leaves the
  /// returned ones as they are); copy them to keep them.
  [[nodiscard]] ThermalContact thermal_conductance(std::span<const double> gamma,
                                                   double beta_c) const;

  [[nodiscard]] const MortarTimings& timings() const { return timings_; }
  /// The mortar segments of the last update (slave face, master face, clip cell): one per
  /// overlapping pair of faces, or per overlapping pair of their sub-facets where one is curved.
  [[nodiscard]] const std::vector<MortarSegment>& segments() const { return segments_; }
  /// Area (length in 2D) of the slave surface covered by the master in the last update.
  [[nodiscard]] double overlap_area() const { return overlap_area_; }

 private:
  void set_positions(std::span<const double> u_slave, std::span<const double> u_master);
  void search();
  void build_segments();
  void integrate();
  void assemble();
  [[nodiscard]] core::SparseMatrix directional_rows(const Csr& csr, double sign,
                                                    PetscInt n_cols) const;
  /// Calls f(segment, plane, placed slave face, warped, placed master face) per segment.
  template <class F>
  void for_each_segment(F&& f) const;

  const mesh::Mesh* slave_;  // not owned (pointers, so that the pair can be move-assigned)
  const mesh::Mesh* master_;
  std::string slave_name_, master_name_;
  MortarOptions options_;
  int dim_;
  std::vector<mesh::Facet> slave_facets_, master_facets_;

  // State of the last update.
  std::vector<Vec3> xs_, xm_;  // current positions of the surface nodes (others unused)
  std::vector<FacetPoints> slave_points_, master_points_;
  std::vector<FacePlane> planes_;
  std::vector<char> warped_;
  // Sub-facets of the curved faces (curved_face_divisions > 1): index into subfacets_, or −1.
  std::vector<int> slave_sub_, master_sub_;
  std::vector<SubFacets> subfacets_;
  std::vector<Vec3> node_normals_;  // averaged normal per slave node
  std::vector<double> face_area_;   // full area of each slave face (projected, for thresholds)
  double radius_ = 0;
  Csr candidates_;                       // master faces near each slave face (cols only)
  std::vector<MortarSegment> segments_;  // grouped by slave face
  std::vector<int> face_segments_;       // segments_[face_segments_[e], face_segments_[e + 1])
  Csr d_rows_, m_rows_;                  // by slave node
  double overlap_area_ = 0;
  std::vector<int> contact_nodes_, contact_index_;
  std::vector<std::array<double, 3>> normals_, tangents_[2];
  std::vector<double> gap_, weights_, coverage_;
  std::vector<double> face_cover_;  // per slave face: covered integral / projected area (0: none)
  core::SparseMatrix d_, m_, b_slave_, b_master_;
  MortarTimings timings_;
  // L_θγ is linear in γ and the geometry is fixed between updates, while the fixed point
  // (6.3) asks for L at every iteration. The first thermal_conductance after an update stores
  // per segment the integrals ∫ φ̃_c^s φ_a φ_b dS over the slave facet's nodes c (ss, sm, mm
  // blocks) with the positions of their (a, b) entries in L's values, and PETSc matrices
  // with L's pattern; each call then sums β_C γ_c times the integrals into the values
  // (composing and assembling L anew per call was 5 % of example 05).
  struct ConductanceMoments {
    int segment;  // index in segments_
    int ns, nm;   // nodes of the slave and the master facet
    int stride;   // N: 4 when both facets are of first order, else 9 (kFacetNodes)
    std::vector<double> ss, sm, mm;               // [c][a][b] at (c N + a) N + b
    std::vector<int> at_ss, at_sm, at_ms, at_mm;  // (a, b) at a N + b → entry in the values
  };
  void build_conductance() const;
  mutable std::vector<ConductanceMoments> conductance_moments_;
  mutable std::vector<core::SparseMatrix> conductance_;  // ss, sm, ms, mm; empty until built
};

}  // namespace tc::contact
