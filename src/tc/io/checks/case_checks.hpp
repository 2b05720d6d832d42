#pragma once
// Private to the io layer: the checks of a case that span sections, apart from the parsing of
// each table (case_reader_detail.hpp). Those that need one entry and the bodies (a name that
// must be a body, a boundary its mesh has, a cut its mesh allows) run as the entry is read;
// the others once every section has been read without an issue (check_across_sections).
#include <toml++/toml.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tc/io/schema/table_reader.hpp"
#include "tc/model/problem.hpp"

namespace tc::io::detail {

/// Index of the body named at member k, or an issue listing the bodies.
std::optional<int> body_index(const TableReader& t, std::string_view k,
                              const std::vector<physics::Body>& bodies);

/// Issue when the body's mesh (if built) has no boundary named `where` (member k of t).
void check_boundary_name(const TableReader& t, std::string_view k, const physics::Body& body,
                         bool mesh_built, const std::string& where);

/// Issue when the body's mesh cannot be cut into its subdomains (as the run would find).
void check_subdomains(const TableReader& b, const physics::Body& body, bool mesh_built);

/// Issue when a film or radiation on boundary `bc` is so strong against the body's
/// conduction that double precision cannot carry its heat (docs/choices.md, "Film and
/// radiation bounded by the Biot number").
void check_boundary_heat_scale(const TableReader& b, const physics::BoundaryCondition& bc,
                               const physics::Body& body, bool mesh_built,
                               double reference_temperature);

/// Names (a default for a lone pair, required for several, unique, columns apart) and slave
/// surfaces (one pair each, no mirrored pair) across the pairs; `pairs[i]` is the table of
/// contacts[i].
void check_contact_pairs(std::vector<physics::ContactSettings>& contacts,
                         const std::vector<TableReader>& pairs,
                         const std::vector<physics::Body>& bodies);

/// The checks of a problem read without issue, each only while the ones before found none:
/// boundary conflicts, load control, reaction columns, quasistatic bodies held, massless
/// cells of the modified mass scheme. `root` gives the lines.
void check_across_sections(const physics::Problem& p, const toml::table& root, Issues& issues);

}  // namespace tc::io::detail
