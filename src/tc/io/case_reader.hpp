#pragma once
// The case file (case-format.md): TOML read with toml++, validated completely before any
// work. Every problem found is collected and thrown together as one InputError whose
// issues read `FILE:LINE: KEY: what was found, what was expected`.
#include <filesystem>

#include "tc/physics/problem.hpp"

namespace tc::io {

/// Reads, validates and builds the meshes of a case. Throws InputError (all issues).
[[nodiscard]] physics::Problem read_case(const std::filesystem::path& file);

}  // namespace tc::io
