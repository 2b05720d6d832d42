// CaseReader: [[boundary]] (supports, loads, heat) and [contact] (the pairs, their laws).
#include <fmt/format.h>

#include <algorithm>

#include "tc/io/case/case_reader_detail.hpp"
#include "tc/io/checks/case_checks.hpp"

namespace tc::io::detail {

void CaseReader::read_boundaries(const TableReader& root) {
  const auto* a = tables(root, "boundary");
  if (!a) return;
  for (size_t i = 0; i < a->size(); ++i) read_boundary(*a->get(i)->as_table(), i);
}

void CaseReader::read_boundary(const toml::table& t, size_t index) {
  const TableReader b(t, at("boundary", index), issues_, schema::section("boundary"));
  physics::BoundaryCondition bc;
  const auto body = body_index(b, "body", p_.bodies);
  if (const auto where = b.string("where")) {
    bc.where = *where;
    if (body) check_boundary_name(b, "where", p_.bodies[*body], mesh_built_[*body], *where);
    if (b.has("displacement"))
      check_name(b, "where", *where, "the history.csv columns reaction_<body>_<where>_x|y|z");
    else if (b.has("force"))
      check_name(b, "where", *where, "the history.csv columns force_<body>_<where>_x|y|z");
  }
  bc.body = body.value_or(0);
  if (const auto* n = b.get("displacement"))
    if (const auto d = read_components(*n, b.key("displacement"), issues_, dim_, true))
      bc.displacement = *d;
  // "free" is accepted in a traction too (no traction on that component), so one entry can
  // mix displaced and loaded components: displacement = [0.0, "free"], traction = ["free", p].
  if (const auto* n = b.get("traction"))
    if (const auto p = read_components(*n, b.key("traction"), issues_, dim_, true))
      bc.traction = *p;
  for (int k = 0; k < 3; ++k)
    if (bc.displacement[k] && bc.traction[k])
      issues_.add(b.line("traction"), at(b.key("traction"), k),
                  fmt::format("found both a displacement and a traction on component {}, "
                              "expected one of them (\"free\" displacement with a traction)",
                              k));
  // A resultant force per component through a rigid coupling (load control): "free" leaves a
  // component uncoupled, so force = ["free", "free", -200.0] presses along z only.
  if (const auto* n = b.get("force"))
    if (const auto f = read_components(*n, b.key("force"), issues_, dim_, true)) bc.force = *f;
  for (int k = 0; k < 3; ++k)
    if (bc.force[k] && (bc.displacement[k] || bc.traction[k]))
      issues_.add(b.line("force"), at(b.key("force"), k),
                  fmt::format("found both a force and a {} on component {}, expected one of "
                              "them (\"free\" in the other)",
                              bc.displacement[k] ? "displacement" : "traction", k));
  if (const auto* n = b.get("temperature"))
    bc.temperature =
        read_time_table(*n, b.key("temperature"), issues_, range_of(b.spec("temperature")));
  if (const auto* n = b.get("heat_flux"))
    bc.heat_flux = read_time_table(*n, b.key("heat_flux"), issues_, range_of(b.spec("heat_flux")));
  if (b.has("temperature") && b.has("heat_flux"))
    b.issue("heat_flux",
            "found both temperature and heat_flux, expected one of them per "
            "[[boundary]] (add another [[boundary]] for the other)");
  read_boundary_heat(b, bc);
  if (body)
    check_boundary_heat_scale(b, bc, p_.bodies[*body], mesh_built_[*body],
                              p_.physics.reference_temperature);
  for (const auto* k : {"film", "radiation"})
    if (b.has("temperature") && b.has(k))
      b.issue(k, fmt::format("found both temperature and {} on one face, expected one of them: "
                             "a prescribed temperature leaves nothing for the {} to change",
                             k, k));
  if (!b.has("displacement") && !b.has("traction") && !b.has("force") && !b.has("temperature") &&
      !b.has("heat_flux") && !b.has("film") && !b.has("radiation"))
    issues_.add(b.line(), b.path(),
                "prescribes nothing; expected at least one of displacement, traction, force, "
                "temperature, heat_flux, film, radiation");
  p_.boundaries.push_back(std::move(bc));
}

namespace {

/// Member k of a film or radiation table: a number or a time table within its range.
std::optional<core::TimeTable> table_member(const TableReader& t, std::string_view k) {
  const auto* n = t.get(k);
  return n ? read_time_table(*n, t.key(k), t.issues(), range_of(t.spec(k))) : std::nullopt;
}

}  // namespace

void CaseReader::read_boundary_heat(const TableReader& b, physics::BoundaryCondition& bc) {
  if (const auto f = b.sub_table("film")) {
    const auto h = table_member(*f, "coefficient");
    const auto ambient = table_member(*f, "ambient");
    if (h && ambient) bc.film = physics::Film{*h, *ambient};
  }
  if (const auto r = b.sub_table("radiation")) {
    const auto e = table_member(*r, "emissivity");
    const auto ambient = table_member(*r, "ambient");
    if (e && ambient) bc.radiation = physics::Radiation{*e, *ambient};
  }
}

void CaseReader::read_contacts(const TableReader& root) {
  const auto* n = root.get("contact");
  if (!n) return;
  std::vector<TableReader> pairs;
  if (const auto* t = n->as_table()) {
    pairs.push_back(read_contact(*t, "contact"));
  } else if (const auto* a = n->as_array(); a && a->is_array_of_tables()) {
    for (size_t i = 0; i < a->size(); ++i)
      pairs.push_back(read_contact(*a->get(i)->as_table(), at("contact", i)));
  } else {
    root.issue("contact", fmt::format("found {}, expected a [contact] table (one pair) or one or "
                                      "more [[contact]] tables",
                                      describe(*n)));
    return;
  }
  check_contact_pairs(p_.contacts, pairs, p_.bodies);
}

TableReader CaseReader::read_contact(const toml::table& table, std::string path) {
  const TableReader t(table, std::move(path), issues_, schema::section("contact"));
  physics::ContactSettings c;
  if (const auto name = t.string("name")) {
    check_pair_name(t, *name);
    c.name = *name;
  }
  auto side = [&](std::string_view key, int& body, std::string& where) -> bool {
    const auto s = t.sub_table(key);
    if (!s) return false;
    if (key == "master" && s->has("rigid")) return read_rigid_tool(*s, c);
    refuse_tool_keys(*s, key);
    for (const auto* k : {"body", "where"})
      if (!s->has(k))
        s->issue(k, fmt::format("missing; expected {}{}",
                                k == std::string_view("body") ? "the name of a body"
                                                              : "a boundary of that body",
                                key == "master" ? " (or rigid = \"plane\" for a rigid tool)" : ""));
    const auto b = body_index(*s, "body", p_.bodies);
    const auto w = s->string("where");
    if (b && w) check_boundary_name(*s, "where", p_.bodies[*b], mesh_built_[*b], *w);
    body = b.value_or(-1);
    where = w.value_or("");
    return b && w;
  };
  const bool slave_ok = side("slave", c.slave_body, c.slave_where);
  const bool master_ok = side("master", c.master_body, c.master_where);
  if (slave_ok && master_ok && c.slave_body == c.master_body)
    issues_.add(t.line("master"), join(t.key("master"), "body"),
                fmt::format("found the slave's body \"{}\", expected a different body",
                            p_.bodies[c.master_body].name));
  if (const auto* n = t.get("friction"))
    if (const auto f =
            read_temperature_table(*n, t.key("friction"), issues_, range_of(t.spec("friction"))))
      c.friction = *f;
  if (const auto v = t.boolean("heat_conduction")) c.heat_conduction = *v;
  if (const auto v = t.boolean("frictional_heating")) c.frictional_heating = *v;
  read_gap_conductance(t, c);
  if (c.rigid_master && !c.rigid_master->temperature)
    check_adiabatic_tool(t);
  else
    read_conductance(t, c);
  p_.contacts.push_back(std::move(c));
  return t;
}

namespace {

/// A temperature at which both conductances vanish, if any. Both are ≥ 0, linear between the
/// union of their table points and constant beyond: their sum vanishes somewhere iff it does
/// at one of those points (or anywhere, when both are constants).
std::optional<double> both_conductances_zero(const core::TemperatureTable& gs,
                                             const core::TemperatureTable& gm) {
  std::vector<double> at(gs.temperatures());
  at.insert(at.end(), gm.temperatures().begin(), gm.temperatures().end());
  if (at.empty()) at.push_back(0.0);
  std::sort(at.begin(), at.end());
  for (const double t : at)
    if (gs(t) + gm(t) == 0) return t;
  return std::nullopt;
}

}  // namespace

void CaseReader::read_conductance(const TableReader& contact, physics::ContactSettings& c) {
  if (const auto g = contact.sub_table("conductance")) {
    const auto law = [&](std::string_view k) -> std::optional<core::TemperatureTable> {
      const auto* n = g->get(k);
      return n ? read_temperature_table(*n, g->key(k), issues_, range_of(g->spec(k)))
               : std::nullopt;
    };
    const auto gs = law("slave");
    const auto gm = law("master");
    if (!gs || !gm) return;
    c.conductance_slave = *gs;
    c.conductance_master = *gm;
  } else if (contact.has("conductance")) {
    return;  // not a table: reported
  }
  // A gap conductance conducts on its own: β_C may be 0 then (δ_C is needed for friction).
  const bool needed = (c.heat_conduction && !c.gap_conductance) ||
                      (c.frictional_heating && c.friction.max_value() > 0);
  const auto zero = both_conductances_zero(c.conductance_slave, c.conductance_master);
  if (!needed || !zero) return;
  const bool constant = c.conductance_slave.is_constant() && c.conductance_master.is_constant();
  contact.issue("conductance",
                fmt::format("found {}, expected {{ slave = γ_C^s, master = γ_C^m }} with at "
                            "least one > 0{}: with both zero β_C and δ_C of (2.13) are "
                            "undefined (or set heat_conduction = false{})",
                            !contact.has("conductance") ? "none"
                            : constant                  ? "both conductances 0"
                                       : fmt::format("both conductances 0 at θ = {} K", *zero),
                            constant ? "" : " at every temperature",
                            c.friction.max_value() > 0 ? " and frictional_heating = false" : ""));
}

void CaseReader::read_gap_conductance(const TableReader& contact, physics::ContactSettings& c) {
  const auto g = contact.sub_table("gap_conductance");
  if (!g) return;
  physics::GapConductance law;
  if (const auto* n = g->get("table"))
    if (const auto t = read_gap_table(*n, g->key("table"), issues_, range_of(g->spec("table"))))
      law.table = *t;
  if (const auto k = g->number("gas_conductivity")) law.gas_conductivity = *k;
  if (const auto g0 = g->number("gas_offset")) law.gas_offset = *g0;
  if (const auto e = g->number("emissivity_slave")) law.emissivity_slave = *e;
  if (const auto e = g->number("emissivity_master")) law.emissivity_master = *e;
  if (law.gas_conductivity > 0 && !g->has("gas_offset"))
    g->issue("gas_offset",
             "missing; expected g₀ > 0 [m] of k_gas/(g + g₀) with gas_conductivity > 0 (the "
             "gas conducts k_gas/g₀ at closure)");
  if (!c.heat_conduction)
    contact.issue("gap_conductance",
                  "found a gap conductance with heat_conduction = false; expected "
                  "heat_conduction = true (the gap conducts through the same term) or no "
                  "gap_conductance");
  c.gap_conductance = law;
}

}  // namespace tc::io::detail
