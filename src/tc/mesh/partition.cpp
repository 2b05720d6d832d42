#include "tc/mesh/partition.hpp"

#include <metis.h>

#include <algorithm>
#include <string>

#include "tc/core/error.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::mesh {

namespace {

// Nodes two cells must share to be neighbours in the dual graph: a facet of the smallest kind
// (2 or 3 nodes of an edge in 2D; 3, 4, 6, 8 or 9 of a face in 3D).
idx_t common_nodes(const Mesh& m) {
  int fewest = 9;
  for (int c = 0; c < m.n_cells(); ++c)
    for (const auto& f : local_faces(m.cell_type(c))) fewest = std::min(fewest, n_nodes(f.type));
  return fewest;
}

}  // namespace

std::vector<int> partition_cells(const Mesh& m, int parts) {
  std::vector<int> part(static_cast<size_t>(m.n_cells()), 0);
  if (parts <= 1) return part;
  if (parts > m.n_cells())
    throw MeshError("cannot cut " + std::to_string(m.n_cells()) + " cells into " +
                    std::to_string(parts) + " subdomains");
  std::vector<idx_t> eptr{0}, eind;
  for (int c = 0; c < m.n_cells(); ++c) {
    for (const int v : m.cell(c)) eind.push_back(v);
    eptr.push_back(static_cast<idx_t>(eind.size()));
  }
  idx_t ne = m.n_cells(), nn = m.n_nodes(), ncommon = common_nodes(m), nparts = parts, objval = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_CONTIG] = 1;  // a disconnected part would have a larger kernel
  options[METIS_OPTION_SEED] = 1;    // the same cut on every rank and every run
  std::vector<idx_t> epart(static_cast<size_t>(ne)), npart(static_cast<size_t>(nn));
  const int rc = METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr, &ncommon,
                                    &nparts, nullptr, options, &objval, epart.data(), npart.data());
  if (rc != METIS_OK)
    throw MeshError("METIS could not cut the mesh into " + std::to_string(parts) +
                    " subdomains (code " + std::to_string(rc) + ")");
  std::vector<int> count(static_cast<size_t>(parts), 0);
  for (idx_t c = 0; c < ne; ++c) ++count[static_cast<size_t>(part[c] = epart[c])];
  if (std::find(count.begin(), count.end(), 0) != count.end())
    throw MeshError("METIS left a subdomain empty when cutting " + std::to_string(ne) +
                    " cells into " + std::to_string(parts) + ": use fewer subdomains");
  return part;
}

std::vector<SubMesh> split(const Mesh& m, const std::vector<int>& cell_part, int parts) {
  std::vector<SubMesh> out(static_cast<size_t>(parts));
  for (auto& s : out) s.mesh = Mesh(m.dim());
  std::vector<int> local(static_cast<size_t>(m.n_nodes()), -1);
  for (int p = 0; p < parts; ++p) {
    auto& s = out[static_cast<size_t>(p)];
    std::fill(local.begin(), local.end(), -1);
    std::vector<int> nodes;
    for (int c = 0; c < m.n_cells(); ++c) {
      if (cell_part[static_cast<size_t>(c)] != p) continue;
      nodes.clear();
      for (const int v : m.cell(c)) {
        if (local[static_cast<size_t>(v)] < 0) {
          local[static_cast<size_t>(v)] = s.mesh.add_point(m.point(v));
          s.global_node.push_back(v);
        }
        nodes.push_back(local[static_cast<size_t>(v)]);
      }
      s.mesh.add_cell(m.cell_type(c), nodes);
      s.global_cell.push_back(c);
    }
  }
  return out;
}

}  // namespace tc::mesh
