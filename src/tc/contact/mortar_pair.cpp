#include "tc/contact/mortar_pair.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>

#include "tc/contact/search.hpp"
#include "tc/core/error.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::contact {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point& t0) {
  const auto now = Clock::now();
  const double s = std::chrono::duration<double>(now - t0).count();
  t0 = now;
  return s;
}

bool facet_fits(mesh::FacetType t, int dim) {
  const bool line = t == mesh::FacetType::Line2 || t == mesh::FacetType::Line3;
  return dim == 2 ? line : !line;
}

std::vector<mesh::Facet> checked_boundary(const mesh::Mesh& m, const std::string& name,
                                          const char* side) {
  if (!m.has_boundary(name)) {
    std::string known;
    for (const auto& b : m.boundary_names()) known += (known.empty() ? "" : ", ") + b;
    throw MeshError(std::string("mortar pair: the ") + side + " mesh has no boundary '" + name +
                    "' (it has: " + known + ")");
  }
  auto facets = m.boundary(name);
  for (const auto& f : facets)
    if (!facet_fits(f.type, m.dim()))
      throw MeshError(std::string("mortar pair: ") + side + " boundary '" + name + "' has a " +
                      mesh::name(f.type) + " facet in a " + std::to_string(m.dim()) + "D mesh");
  return facets;
}

/// Positions X + u of every node (u interleaved; empty = reference configuration).
void positions(const mesh::Mesh& m, std::span<const double> u, const char* side,
               std::vector<Vec3>& x) {
  const int d = m.dim();
  if (!u.empty() && u.size() != static_cast<size_t>(d * m.n_nodes()))
    throw Error(std::string("MortarPair::update: the ") + side + " displacement has " +
                std::to_string(u.size()) + " entries, expected " + std::to_string(d * m.n_nodes()) +
                " (dim × nodes) or none");
  x.resize(m.n_nodes());
  for (int j = 0; j < m.n_nodes(); ++j) {
    x[j] = m.point(j);
    if (!u.empty())
      for (int k = 0; k < d; ++k) x[j][k] += u[d * j + k];
  }
}

void check_size(std::span<const double> v, size_t n, const char* what) {
  if (v.size() != n)
    throw Error(std::string("MortarPair: ") + what + " has " + std::to_string(v.size()) +
                " entries, expected " + std::to_string(n));
}

}  // namespace

const char* name(MultiplierBasis b) {
  return b == MultiplierBasis::dual ? "dual" : "standard";
}

MortarPair::MortarPair(const mesh::Mesh& slave, std::string slave_boundary,
                       const mesh::Mesh& master, std::string master_boundary, MortarOptions options)
    : slave_(&slave),
      master_(&master),
      slave_name_(std::move(slave_boundary)),
      master_name_(std::move(master_boundary)),
      options_(options),
      dim_(slave.dim()) {
  if (master.dim() != dim_)
    throw MeshError("mortar pair: the slave mesh is " + std::to_string(dim_) +
                    "D but the master mesh is " + std::to_string(master.dim()) + "D");
  if (!(options_.search_radius >= 0))
    throw Error("mortar pair: search_radius must be ≥ 0 (0 = automatic), got " +
                std::to_string(options_.search_radius));
  if (options_.curved_face_divisions < 1 || options_.curved_face_divisions > kMaxDivisions)
    throw Error("mortar pair: curved_face_divisions must be in [1, " +
                std::to_string(kMaxDivisions) + "], got " +
                std::to_string(options_.curved_face_divisions));
  if (!(options_.weight_threshold >= 0 && options_.weight_threshold < 1))
    throw Error("mortar pair: weight_threshold must be in [0, 1), got " +
                std::to_string(options_.weight_threshold));
  slave_facets_ = checked_boundary(slave, slave_name_, "slave");
  master_facets_ = checked_boundary(master, master_name_, "master");
  check_slave_bases(slave_facets_, slave_name_, options_.vertex_share);
  update();
}

void MortarPair::update(std::span<const double> u_slave, std::span<const double> u_master) {
  timings_ = {};
  conductance_moments_.clear();
  conductance_.clear();
  auto t0 = Clock::now();
  set_positions(u_slave, u_master);
  timings_.geometry += since(t0);
  search();
  timings_.search += since(t0);
  build_segments();
  timings_.geometry += since(t0);
  integrate();
  timings_.integration += since(t0);
  assemble();
  timings_.assembly += since(t0);
}

void MortarPair::set_positions(std::span<const double> u_slave, std::span<const double> u_master) {
  positions(*slave_, u_slave, "slave", xs_);
  positions(*master_, u_master, "master", xm_);
  slave_points_.resize(slave_facets_.size());
  master_points_.resize(master_facets_.size());
  double largest = 0;
  for (size_t e = 0; e < slave_facets_.size(); ++e) {
    slave_points_[e] = facet_points(slave_facets_[e], xs_);
    largest = std::max(largest, facet_size(slave_points_[e]));
  }
  for (size_t f = 0; f < master_facets_.size(); ++f) {
    master_points_[f] = facet_points(master_facets_[f], xm_);
    largest = std::max(largest, facet_size(master_points_[f]));
  }
  radius_ = options_.search_radius > 0 ? options_.search_radius : largest;
}

void MortarPair::search() {
  std::vector<Aabb> boxes(master_points_.size());
  for (size_t f = 0; f < boxes.size(); ++f) boxes[f] = bounding_box(master_points_[f]);
  const AabbTree tree(std::move(boxes));
  candidates_ = Csr{};
  for (const auto& s : slave_points_) {
    // The points within radius_ of the face along its normal n₀ (the direction of projection)
    // fill the prism {x + t n₀ : |t| ≤ r}, whose box is the face's box grown by r|n₀_i| along
    // axis i; a margin of 1e-10 of the face absorbs round-off in the plane.
    const Vec3 n = centre_normal(s);
    const double margin = 1e-10 * facet_size(s);
    const Vec3 grow{radius_ * std::abs(n[0]) + margin, radius_ * std::abs(n[1]) + margin,
                    radius_ * std::abs(n[2]) + margin};
    tree.query(bounding_box(s).inflated(grow), candidates_.cols);
    candidates_.offsets.push_back(static_cast<int>(candidates_.cols.size()));
  }
}

void MortarPair::build_segments() {
  node_normals_ = averaged_normals(slave_facets_, xs_);
  const size_t n_faces = slave_facets_.size();
  planes_.resize(n_faces);
  warped_.assign(n_faces, 0);
  face_area_.assign(n_faces, 0.0);
  segments_.clear();
  face_segments_.assign(1, 0);
  // Curved faces on their sub-facets when asked (docs/choices.md), others on their corners.
  subfacets_.clear();
  auto subdivide = [&](const std::vector<FacetPoints>& faces, std::vector<int>& index) {
    index.assign(faces.size(), -1);
    if (dim_ != 3 || options_.curved_face_divisions < 2) return;
    for (size_t f = 0; f < faces.size(); ++f)
      if (curved_edges(faces[f])) {
        index[f] = static_cast<int>(subfacets_.size());
        subfacets_.push_back(sub_facets(faces[f], options_.curved_face_divisions));
      }
  };
  subdivide(slave_points_, slave_sub_);
  subdivide(master_points_, master_sub_);
  std::array<Polygon, kMaxDivisions * kMaxDivisions> slave_parts, master_parts;
  for (size_t e = 0; e < n_faces; ++e) {
    const FacetPoints& s = slave_points_[e];
    const FacePlane plane = face_plane(s, dim_);
    planes_[e] = plane;
    warped_[e] = warped(s, plane, dim_) ? 1 : 0;
    const Polygon own = project(s, plane).polygon;
    face_area_[e] = dim_ == 2 ? norm(s.x[1] - s.x[0]) : signed_area(own);
    int n_slave_parts = 1;
    if (slave_sub_[e] >= 0) {
      const SubFacets& sub = subfacets_[slave_sub_[e]];
      n_slave_parts = sub.n;
      for (int i = 0; i < sub.n; ++i) slave_parts[i] = project(sub, i, plane);
    }
    for (int i = candidates_.offsets[e]; i < candidates_.offsets[e + 1]; ++i) {
      const int f = candidates_.cols[i];
      const FacetPoints& m = master_points_[f];
      // Only faces that face the slave: skips the far side of a thin or curved master body.
      if (dot(centre_normal(m), plane.normal) >= 0) continue;
      MortarSegment seg{static_cast<int>(e), f, {}};
      if (dim_ == 2) {
        const Interval iv =
            overlap(face_area_[e], plane.project(m.x[0])[0], plane.project(m.x[1])[0]);
        if (!(iv.hi - iv.lo > 1e-14 * face_area_[e])) continue;
        seg.cell.push({iv.lo, 0});
        seg.cell.push({iv.hi, 0});
      } else if (n_slave_parts == 1 && master_sub_[f] < 0) {
        seg.cell = clip(project(m, plane).polygon, own);
        if (seg.cell.n < 3 || !(signed_area(seg.cell) > 1e-14 * face_area_[e])) continue;
      } else {
        // One segment per pair of sub-facets (a face with straight edges is its own only part).
        if (n_slave_parts == 1) slave_parts[0] = own;
        int n_master_parts = 1;
        if (master_sub_[f] >= 0) {
          const SubFacets& sub = subfacets_[master_sub_[f]];
          n_master_parts = sub.n;
          for (int i = 0; i < sub.n; ++i) master_parts[i] = project(sub, i, plane);
        } else {
          master_parts[0] = project(m, plane).polygon;
        }
        for (int i = 0; i < n_master_parts; ++i)
          for (int j = 0; j < n_slave_parts; ++j) {
            if (!boxes_meet(master_parts[i], slave_parts[j])) continue;
            seg.cell = clip(master_parts[i], slave_parts[j]);
            if (seg.cell.n < 3 || !(signed_area(seg.cell) > 1e-14 * face_area_[e])) continue;
            segments_.push_back(seg);
          }
        continue;
      }
      segments_.push_back(seg);
    }
    face_segments_.push_back(static_cast<int>(segments_.size()));
  }
}

template <class F>
void MortarPair::for_each_segment(F&& f) const {
  for (size_t e = 0; e + 1 < face_segments_.size(); ++e) {
    if (face_segments_[e] == face_segments_[e + 1]) continue;
    const PlacedFacet s = place(slave_points_[e], planes_[e]);
    for (int i = face_segments_[e]; i < face_segments_[e + 1]; ++i) {
      const MortarSegment& seg = segments_[i];
      f(seg, planes_[e], s, warped_[e] != 0, place(master_points_[seg.master], planes_[e]));
    }
  }
}

namespace {

using Local = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kFacetNodes, kFacetNodes>;
using LocalVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kFacetNodes, 1>;

Local to_local(const double (&a)[kFacetNodes][kFacetNodes], int n) {
  Local m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = a[i][j];
  return m;
}

}  // namespace

void MortarPair::integrate() {
  Triplets dt(slave_->n_nodes()), mt(slave_->n_nodes());
  overlap_area_ = 0;
  face_cover_.assign(slave_facets_.size(), 0.0);
  std::vector<int> mnodes;                            // master nodes seen by the current slave face
  std::vector<std::array<double, kFacetNodes>> mstd;  // ∫ φ_a^s φ_c^m per local master node c
  for (size_t e = 0; e + 1 < face_segments_.size(); ++e) {
    if (face_segments_[e] == face_segments_[e + 1]) continue;
    const int ns = slave_points_[e].n;
    Local me = Local::Zero(ns, ns);
    LocalVector de = LocalVector::Zero(ns);
    mnodes.clear();
    mstd.clear();
    const PlacedFacet s = place(slave_points_[e], planes_[e]);
    for (int i = face_segments_[e]; i < face_segments_[e + 1]; ++i) {
      const MortarSegment& seg = segments_[i];
      const auto& mf = master_facets_[seg.master];
      std::array<int, kFacetNodes> col{};
      for (int b = 0; b < master_points_[seg.master].n; ++b) {
        const auto it = std::find(mnodes.begin(), mnodes.end(), mf.nodes[b]);
        col[b] = static_cast<int>(it - mnodes.begin());
        if (it == mnodes.end()) {
          mnodes.push_back(mf.nodes[b]);
          mstd.push_back({});
        }
      }
      const PlacedFacet m = place(master_points_[seg.master], planes_[e]);
      const int n_points = mortar_rule(dim_, slave_facets_[e].type, mf.type, false);
      for_each_point(dim_, planes_[e], s, warped_[e] != 0, m, seg.cell, n_points,
                     [&](const MortarPoint& q) {
                       for (int a = 0; a < ns; ++a) {
                         const double wa = q.weight * q.slave.phi[a];
                         de(a) += wa;
                         for (int b = 0; b < ns; ++b) me(a, b) += wa * q.slave.phi[b];
                         for (int b = 0; b < q.master.n; ++b)
                           mstd[col[b]][a] += wa * q.master.phi[b];
                       }
                     });
    }
    const double covered = de.sum();
    // A face covered on less than 1e-12 of its area is a round-off sliver (edges of matching
    // meshes): dropped, since its dual basis would be ill-conditioned and its weight is nil.
    if (!(covered > 1e-12 * face_area_[e])) continue;
    face_cover_[e] = covered / face_area_[e];
    overlap_area_ += covered;
    const auto& nodes = slave_facets_[e].nodes;
    Eigen::MatrixXd mcov(ns, static_cast<Eigen::Index>(mnodes.size()));
    for (size_t c = 0; c < mnodes.size(); ++c)
      for (int a = 0; a < ns; ++a) mcov(a, static_cast<Eigen::Index>(c)) = mstd[c][a];
    const BasisTransformation tr =
        basis_transformation(slave_facets_[e].type, options_.vertex_share);
    Eigen::MatrixXd mface;
    if (!tr.identity()) {
      // The multipliers on φ̃ = Tφ (docs/theory.md, "Second-order slave faces"): d̃ = T d,
      // M̃e = T Me Tᵀ, ∫φ̃_a φ_c^m = (T M_std)_ac; the dual ψ_a = Σ_b A_ab φ̃_b with
      // A = diag(d̃) M̃e⁻¹ has ∫ψ_a φ̃_b = δ_ab d̃_a, so over the physical slave dofs
      // D = ∫ψ φᵀ = A T Me = diag(d̃) T⁻ᵀ (vertex rows diagonal, a mid-edge row −α/(1 − 2α)
      // d̃ at its vertices) and M = A T M_std; the standard basis ψ = φ̃: D = T Me, M = T M_std.
      const Local t = to_local(tr.t, ns);
      const LocalVector dtilde = t * de;
      if (options_.basis == MultiplierBasis::dual) {
        const Local mtilde = t * me * t.transpose();
        mface = dtilde.asDiagonal() * mtilde.ldlt().solve(t * mcov);
        for (int a = 0; a < ns; ++a)
          for (int b = 0; b < ns; ++b)
            if (tr.inv[b][a] != 0) dt.add(nodes[a], nodes[b], dtilde(a) * tr.inv[b][a]);
      } else {
        mface = t * mcov;
        const Local dface = t * me;
        for (int a = 0; a < ns; ++a)
          for (int b = 0; b < ns; ++b) dt.add(nodes[a], nodes[b], dface(a, b));
      }
    } else if (options_.basis == MultiplierBasis::dual) {
      // Biorthogonality on the covered part (Popp et al. 2012): ψ_a = Σ_b A_ab φ_b with
      // A = diag(d) Me⁻¹, so ∫ψ_a φ_b = δ_ab d_a and M_face = A M_std.
      mface = de.asDiagonal() * me.ldlt().solve(mcov);
      for (int a = 0; a < ns; ++a) dt.add(nodes[a], nodes[a], de(a));
    } else {
      mface = mcov;
      for (int a = 0; a < ns; ++a)
        for (int b = 0; b < ns; ++b) dt.add(nodes[a], nodes[b], me(a, b));
    }
    for (int a = 0; a < ns; ++a)
      for (size_t c = 0; c < mnodes.size(); ++c)
        mt.add(nodes[a], mnodes[c], mface(a, static_cast<Eigen::Index>(c)));
  }
  d_rows_ = dt.compress();
  m_rows_ = mt.compress();
}

void MortarPair::assemble() {
  const int n_s = slave_->n_nodes();
  std::vector<double> weight(n_s, 0.0), scale(n_s, 0.0);
  for (int j = 0; j < n_s; ++j)
    for (int i = d_rows_.offsets[j]; i < d_rows_.offsets[j + 1]; ++i) weight[j] += d_rows_.vals[i];
  std::vector<double> cover(n_s, 1.0);
  for (size_t e = 0; e < slave_facets_.size(); ++e)
    for (const int a : slave_facets_[e].node_span()) {
      scale[a] += face_area_[e];
      cover[a] = std::min(cover[a], face_cover_[e]);
    }
  contact_nodes_.clear();
  contact_index_.assign(n_s, -1);
  normals_.clear();
  tangents_[0].clear();
  tangents_[1].clear();
  weights_.clear();
  coverage_.clear();
  gap_.clear();
  for (int j = 0; j < n_s; ++j) {
    if (!(weight[j] > options_.weight_threshold * scale[j])) continue;
    coverage_.push_back(cover[j]);
    contact_index_[j] = static_cast<int>(contact_nodes_.size());
    contact_nodes_.push_back(j);
    const Vec3 n = node_normals_[j];
    Vec3 t0, t1;
    tangents_of(dim_, n, t0, t1);
    normals_.push_back(n);
    tangents_[0].push_back(t0);
    tangents_[1].push_back(t1);
    weights_.push_back(weight[j]);
    // (2.6) weighted: g_j = n_j·(Σ M_jl x_l^m − Σ D_jl x_l^s).
    Vec3 diff{0, 0, 0};
    for (int i = m_rows_.offsets[j]; i < m_rows_.offsets[j + 1]; ++i)
      diff = diff + m_rows_.vals[i] * xm_[m_rows_.cols[i]];
    for (int i = d_rows_.offsets[j]; i < d_rows_.offsets[j + 1]; ++i)
      diff = diff - d_rows_.vals[i] * xs_[d_rows_.cols[i]];
    gap_.push_back(dot(n, diff));
  }
  d_ = to_matrix(d_rows_, contact_nodes_, n_s);
  m_ = to_matrix(m_rows_, contact_nodes_, master_->n_nodes());
  b_slave_ = directional_rows(d_rows_, 1.0, dim_ * n_s);
  b_master_ = directional_rows(m_rows_, -1.0, dim_ * master_->n_nodes());
}

core::SparseMatrix MortarPair::directional_rows(const Csr& csr, double sign,
                                                PetscInt n_cols) const {
  const PetscInt n_rows = dim_ * static_cast<PetscInt>(contact_nodes_.size());
  std::vector<PetscInt> nnz(n_rows);
  for (size_t k = 0; k < contact_nodes_.size(); ++k) {
    const int j = contact_nodes_[k];
    for (int r = 0; r < dim_; ++r) nnz[dim_ * k + r] = dim_ * (csr.offsets[j + 1] - csr.offsets[j]);
  }
  core::SparseMatrix b(n_rows, n_cols, nnz);
  std::vector<PetscInt> cols;
  std::vector<double> vals;
  for (size_t k = 0; k < contact_nodes_.size(); ++k) {
    const int j = contact_nodes_[k];
    for (int r = 0; r < dim_; ++r) {
      const Vec3& dir = r == 0 ? normals_[k] : tangents_[r - 1][k];
      cols.clear();
      vals.clear();
      for (int i = csr.offsets[j]; i < csr.offsets[j + 1]; ++i)
        for (int c = 0; c < dim_; ++c) {
          cols.push_back(dim_ * static_cast<PetscInt>(csr.cols[i]) + c);
          vals.push_back(sign * csr.vals[i] * dir[c]);
        }
      if (cols.empty()) continue;
      const PetscInt row = dim_ * static_cast<PetscInt>(k) + r;
      b.add_values({&row, 1}, cols, vals.data());
    }
  }
  b.assemble();
  return b;
}

ContactRows MortarPair::rows() const {
  ContactRows r;
  r.dim = dim_;
  r.slave = b_slave_.copy();
  r.master = b_master_.copy();
  r.gap = gap_;
  r.weights = weights_;
  r.nodes = contact_nodes_;
  r.directions.reserve(static_cast<size_t>(dim_ * dim_) * normals_.size());
  for (size_t k = 0; k < normals_.size(); ++k)
    for (int row = 0; row < dim_; ++row) {
      const Vec3& dir = row == 0 ? normals_[k] : tangents_[row - 1][k];
      r.directions.insert(r.directions.end(), dir.begin(), dir.begin() + dim_);
    }
  r.d = d_.copy();
  r.m = m_.copy();
  return r;
}

const std::vector<std::array<double, 3>>& MortarPair::tangents(int l) const {
  if (l < 0 || l > dim_ - 2)
    throw Error("MortarPair::tangents: l must be in [0, " + std::to_string(dim_ - 2) + "], got " +
                std::to_string(l));
  return tangents_[l];
}

namespace {

/// The moments of one quadrature point, with N the arrays' extent (shape values beyond a
/// facet's nodes are 0): ss[c][a][b] += w φ̃_c φ_a^s φ_b^s, sm −= w φ̃_c φ_a^s φ_b^m, mm +=
/// w φ̃_c φ_a^m φ_b^m, φ̃ = T φ^s (basis_transformation; φ̃ = φ^s for T = I).
template <int N>
void add_moments(const MortarPoint& q, const BasisTransformation& tr, double* ss, double* sm,
                 double* mm) {
  double ps[N], pm[N], pt[N];  // local copies: the compiler cannot know the moments do not alias q
  std::copy_n(q.slave.phi.begin(), N, ps);
  std::copy_n(q.master.phi.begin(), N, pm);
  std::copy_n(ps, N, pt);
  if (!tr.identity())
    for (int c = 0; c < q.slave.n; ++c) {
      pt[c] = 0;
      for (int d = 0; d < q.slave.n; ++d) pt[c] += tr.t[c][d] * ps[d];
    }
  for (int c = 0; c < q.slave.n; ++c) {
    const double w = pt[c] * q.weight;
    double ws[N], wm[N];
    for (int a = 0; a < N; ++a) ws[a] = w * ps[a], wm[a] = w * pm[a];
    const int base = c * N * N;
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b) {
        ss[base + a * N + b] += ws[a] * ps[b];
        sm[base + a * N + b] -= ws[a] * pm[b];
        mm[base + a * N + b] += wm[a] * pm[b];
      }
  }
}

}  // namespace

void MortarPair::build_conductance() const {
  conductance_moments_.clear();
  for_each_segment([&](const MortarSegment& seg, const FacePlane& plane, const PlacedFacet& s,
                       bool warped, const PlacedFacet& m) {
    ConductanceMoments t{};
    t.segment = static_cast<int>(&seg - segments_.data());
    t.ns = s.facet->n;
    t.nm = m.facet->n;
    const bool first = mesh::order(s.facet->type) == 1 && mesh::order(m.facet->type) == 1;
    const int n = t.stride = first ? 4 : kFacetNodes;
    for (auto* v : {&t.ss, &t.sm, &t.mm}) v->assign(static_cast<size_t>(n * n * n), 0.0);
    for (auto* v : {&t.at_ss, &t.at_sm, &t.at_ms, &t.at_mm})
      v->assign(static_cast<size_t>(n * n), 0);
    const BasisTransformation tr = basis_transformation(s.facet->type, options_.vertex_share);
    const int n_points = mortar_rule(dim_, s.facet->type, m.facet->type, true);
    for_each_point(dim_, plane, s, warped, m, seg.cell, n_points, [&](const MortarPoint& q) {
      if (first)
        add_moments<4>(q, tr, t.ss.data(), t.sm.data(), t.mm.data());
      else
        add_moments<kFacetNodes>(q, tr, t.ss.data(), t.sm.data(), t.mm.data());
    });
    conductance_moments_.push_back(std::move(t));
  });
  // The pattern of each block (every (a, b) of every segment), then each (a, b)'s position.
  const int n_s = slave_->n_nodes(), n_m = master_->n_nodes();
  Triplets pattern[4] = {Triplets(n_s), Triplets(n_s), Triplets(n_m), Triplets(n_m)};
  for (const auto& t : conductance_moments_) {
    const MortarSegment& seg = segments_[t.segment];
    const auto& sn = slave_facets_[seg.slave].nodes;
    const auto& mn = master_facets_[seg.master].nodes;
    for (int a = 0; a < t.ns; ++a)
      for (int b = 0; b < t.ns; ++b) pattern[0].add(sn[a], sn[b], 0.0);
    for (int a = 0; a < t.ns; ++a)
      for (int b = 0; b < t.nm; ++b) {
        pattern[1].add(sn[a], mn[b], 0.0);
        pattern[2].add(mn[b], sn[a], 0.0);
      }
    for (int a = 0; a < t.nm; ++a)
      for (int b = 0; b < t.nm; ++b) pattern[3].add(mn[a], mn[b], 0.0);
  }
  Csr csr[4];
  for (int i = 0; i < 4; ++i) csr[i] = pattern[i].compress();
  auto at = [&](int i, int row, int col) {
    const auto first = csr[i].cols.begin() + csr[i].offsets[row];
    const auto last = csr[i].cols.begin() + csr[i].offsets[row + 1];
    return static_cast<int>(std::lower_bound(first, last, col) - csr[i].cols.begin());
  };
  for (auto& t : conductance_moments_) {
    const MortarSegment& seg = segments_[t.segment];
    const auto& sn = slave_facets_[seg.slave].nodes;
    const auto& mn = master_facets_[seg.master].nodes;
    const int n = t.stride;
    for (int a = 0; a < t.ns; ++a)
      for (int b = 0; b < t.ns; ++b) t.at_ss[a * n + b] = at(0, sn[a], sn[b]);
    for (int a = 0; a < t.ns; ++a)
      for (int b = 0; b < t.nm; ++b) {
        t.at_sm[a * n + b] = at(1, sn[a], mn[b]);
        t.at_ms[a * n + b] = at(2, mn[b], sn[a]);
      }
    for (int a = 0; a < t.nm; ++a)
      for (int b = 0; b < t.nm; ++b) t.at_mm[a * n + b] = at(3, mn[a], mn[b]);
  }
  conductance_.clear();
  for (int i = 0; i < 4; ++i) conductance_.push_back(to_matrix(csr[i], i % 2 == 0 ? n_s : n_m));
}

ThermalContact MortarPair::thermal_conductance(std::span<const double> gamma, double beta_c) const {
  check_size(gamma, contact_nodes_.size(), "gamma (one per contact node)");
  if (conductance_.empty()) build_conductance();
  PetscScalar* values[4] = {};
  for (int i = 0; i < 4; ++i) {
    TC_PETSC(MatSeqAIJGetArray(conductance_[i].get(), &values[i]));
    MatInfo info;
    TC_PETSC(MatGetInfo(conductance_[i].get(), MAT_LOCAL, &info));
    std::fill(values[i], values[i] + static_cast<PetscInt>(info.nz_used), 0.0);
  }
  for (const auto& t : conductance_moments_) {
    const MortarSegment& seg = segments_[t.segment];
    const int ns = t.ns, nm = t.nm, n = t.stride;
    const auto& sn = slave_facets_[seg.slave].nodes;
    // β_C γ_c, γ = Σ_c γ_c φ̃_c^s (0 at slave nodes that are not contact nodes)
    double g[kFacetNodes] = {};
    for (int c = 0; c < ns; ++c)
      if (contact_index_[sn[c]] >= 0) g[c] = beta_c * gamma[contact_index_[sn[c]]];
    auto block = [&](const std::vector<double>& m, int a, int b) {
      double v = 0;
      for (int c = 0; c < ns; ++c) v += g[c] * m[(c * n + a) * n + b];
      return v;
    };
    for (int a = 0; a < ns; ++a)
      for (int b = 0; b < ns; ++b) values[0][t.at_ss[a * n + b]] += block(t.ss, a, b);
    for (int a = 0; a < ns; ++a)
      for (int b = 0; b < nm; ++b) {
        const double v = block(t.sm, a, b);  // L_ms = L_smᵀ to the bit: the same sums
        values[1][t.at_sm[a * n + b]] += v;
        values[2][t.at_ms[a * n + b]] += v;
      }
    for (int a = 0; a < nm; ++a)
      for (int b = 0; b < nm; ++b) values[3][t.at_mm[a * n + b]] += block(t.mm, a, b);
  }
  core::SparseMatrix out[4];
  for (int i = 0; i < 4; ++i) {
    TC_PETSC(MatSeqAIJRestoreArray(conductance_[i].get(), &values[i]));
    out[i] = conductance_[i].share();
  }
  return {std::move(out[0]), std::move(out[1]), std::move(out[2]), std::move(out[3])};
}

}  // namespace tc::contact
