// libFuzzer target: our half of the Gmsh reader, tc::mesh::detail::build_mesh, on arbitrary
// arrays of the kind libgmsh hands over (node tags with gaps and repeats, coordinates including
// NaN, Inf and coincident points, element blocks of any type and length, boundary groups that
// name missing or interior facets). libgmsh itself is prebuilt and not instrumented, and is
// not memory-safe on malformed files (docs/robustness.md), so this is the target that holds
// our code to "read or MeshError, never a crash". Coordinates are mostly drawn from a small
// lattice so that valid and nearly valid cells are common.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "tc/core/error.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"

namespace {

using tc::mesh::detail::RawBlock;
using tc::mesh::detail::RawMesh;

std::size_t tag(FuzzedDataProvider& in) {
  return in.ConsumeIntegralInRange<std::size_t>(0, 40);
}

double coordinate(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange<int>(0, 15)) {
    case 0:
      return std::numeric_limits<double>::quiet_NaN();
    case 1:
      return std::numeric_limits<double>::infinity();
    case 2:
      return in.ConsumeFloatingPoint<double>();
    default:
      return 0.5 * in.ConsumeIntegralInRange<int>(-2, 2);
  }
}

RawBlock block(FuzzedDataProvider& in, RawMesh& raw) {
  RawBlock b;
  b.type = in.ConsumeIntegralInRange<int>(0, 9);  // gmsh types 1–5 are ours, others refused
  raw.type_names[b.type] = "type" + std::to_string(b.type);
  const int n = in.ConsumeIntegralInRange<int>(0, 48);
  for (int i = 0; i < n; ++i) b.nodes.push_back(tag(in));
  return b;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  RawMesh raw;
  const int dim = in.ConsumeBool() ? 3 : 2;
  const int n_nodes = in.ConsumeIntegralInRange<int>(0, 40);
  for (int i = 0; i < n_nodes; ++i) {
    raw.node_tags.push_back(in.ConsumeBool() ? static_cast<std::size_t>(i + 1) : tag(in));
    for (int k = 0; k < 3; ++k) raw.coords.push_back(k == 2 && dim == 2 ? 0.0 : coordinate(in));
  }
  const int n_blocks = in.ConsumeIntegralInRange<int>(0, 3);
  for (int i = 0; i < n_blocks; ++i) raw.cells.push_back(block(in, raw));
  const int n_groups = in.ConsumeIntegralInRange<int>(0, 3);
  for (int i = 0; i < n_groups; ++i) {
    raw.groups.push_back({in.ConsumeBool() ? "left" : "right", {}});
    const int nb = in.ConsumeIntegralInRange<int>(0, 2);
    for (int j = 0; j < nb; ++j) raw.groups.back().blocks.push_back(block(in, raw));
  }
  try {
    const auto mesh = tc::mesh::detail::build_mesh(raw, dim, "fuzz.msh");
    (void)mesh;
  } catch (const tc::Error&) {  // MeshError: the documented rejection
  }
  return 0;
}
