#pragma once
// Checks of a problem that need its meshes and boundary data (beyond the case file's syntax).
#include "tc/model/problem.hpp"

namespace tc::physics {

/// Number of rigid-body motions (2D: 3, 3D: 6) of body `b` that its displacement boundary
/// conditions leave free. A quasistatic run needs 0: K_u is singular otherwise. A face under
/// load control (force) holds the rotations that would tilt it; the translation along a loaded
/// component counts as held when the body is in contact (the contact holds it).
[[nodiscard]] int free_rigid_modes(const Problem& p, int b);

}  // namespace tc::physics
