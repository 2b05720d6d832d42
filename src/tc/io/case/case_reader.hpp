#pragma once
// The case file (case-format.md): TOML read with toml++, validated completely before any
// work. Every problem found is collected and thrown together as one InputError whose
// issues read `FILE:LINE: KEY: what was found, what was expected`.
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include "tc/io/vtk/vtkhdf.hpp"
#include "tc/model/problem.hpp"

namespace tc::io {

/// Reads, validates and builds the meshes of a case. Throws InputError (all issues).
/// `overrides`: `--set KEY=VALUE` of the command line, put into the parsed file before it is
/// validated (case-format.md, "Overrides"); an issue they cause names `--set KEY=VALUE`.
[[nodiscard]] physics::Problem read_case(const std::filesystem::path& file,
                                         std::span<const std::string> overrides = {});
/// The same, with the field files `[output] format` chose (vtkhdf.hpp) in `field_files`.
[[nodiscard]] physics::Problem read_case(const std::filesystem::path& file,
                                         std::span<const std::string> overrides,
                                         FieldFiles& field_files);

/// The line and bytes (as \xNN) of the first non-ASCII character outside TOML strings and
/// comments, where TOML has no use for one (read_case refuses the file: see its comment).
[[nodiscard]] std::optional<std::pair<int, std::string>> stray_non_ascii(std::string_view text);

}  // namespace tc::io
