#pragma once
// Contact rows without the mortar layer, for tests of the dual solve: matching meshes, each
// slave node paired with the master node at the same (x, y) [2D: x], node-to-node rows
// weighted by the slave's nodal areas, normal −e_vertical (the slave lies on top), tangents
// along the other axes, and the gap measured in the configuration X + u.
#include "../../bench/support/matching_rows.hpp"
#include "tc/physics/dual_contact.hpp"

namespace tc::test {

inline physics::ContactRows node_to_node_rows(const mesh::Mesh& slave, const mesh::Mesh& master,
                                              const core::Vector* u_slave = nullptr,
                                              const core::Vector* u_master = nullptr) {
  return bench::matching_rows(slave, master, u_slave, u_master);
}

}  // namespace tc::test
