#include "tc/io/case/case_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <span>
#include <sstream>

#include "tc/io/case/case_overrides.hpp"
#include "tc/io/case/case_reader_detail.hpp"
#include "tc/io/checks/case_checks.hpp"
#include "tc/io/files/files.hpp"
#include "tc/io/output/probes.hpp"
#include "tc/io/vtk/vtkhdf.hpp"
#include "tc/model/checks.hpp"
#include "tc/model/rigid_tool.hpp"

namespace tc::io::detail {

using physics::Problem;

namespace {

/// The most steps a run may have: well inside the int step counter, and far more than a run
/// that ends in reasonable time (end = 4294967.301, step = 0.001 wrapped round to 5 steps).
constexpr long kMaxSteps = 100'000'000;

/// Longest `title` (bytes): summary.json holds it and is rewritten after every step.
constexpr size_t kMaxTitleLength = 4096;

}  // namespace

Problem CaseReader::read() {
  p_.case_file = file_;
  const TableReader root(root_, "", issues_, schema::section(""));
  if (const auto t = root.string("title")) {
    // The title is copied into summary.json after every step: a 10 MB title cost 0.25 s a
    // step (issue 42). A title is a line or a paragraph, not a document.
    if (t->size() > kMaxTitleLength)
      root.issue("title", fmt::format("found a title of {} characters, expected at most {}",
                                      t->size(), kMaxTitleLength));
    else
      p_.title = *t;
  }
  read_dimension(root);
  read_time(root);
  read_physics(root);
  read_materials(root);
  read_bodies(root);
  read_boundaries(root);
  read_contacts(root);
  resolve_auto_subdomains(root);
  read_solver(root);
  read_output(root);
  read_probes(root);
  read_stability(root);
  check_across_sections(p_, root_, issues_);
  if (!issues_.empty()) issues_.raise();
  warn_unit_habits();
  // A rigid tool's body once everything it is placed from (the slave, the time) is valid.
  physics::place_rigid_tools(p_);
  return std::move(p_);
}

void CaseReader::read_dimension(const TableReader& root) {
  const auto* n = root.get("dimension");
  if (!n) return;
  const auto* i = n->as_integer();
  if (!i || (i->get() != 2 && i->get() != 3)) {
    root.issue("dimension",
               fmt::format("found {}, expected 2 or 3 (2: plane strain)", describe(*n)));
    return;
  }
  dim_ = static_cast<int>(i->get());
  p_.dimension = dim_;
}

void CaseReader::read_time(const TableReader& root) {
  const auto t = root.sub_table("time");
  if (!t) return;
  if (const auto s = t->choice("scheme"))
    p_.time.scheme = *s == "dynamic" ? physics::Scheme::dynamic : physics::Scheme::quasistatic;
  if (const auto s = t->choice("contact_scheme"))
    p_.time.contact_scheme = *s == "plain"           ? physics::ContactScheme::plain
                             : *s == "modified_mass" ? physics::ContactScheme::modified_mass
                                                     : physics::ContactScheme::stabilised;
  const auto step = t->number("step");
  const auto end = t->number("end");
  if (!step || !end) return;
  p_.time.step = *step;
  p_.time.end = *end;
  const double n = *end / *step;
  // Negated so that inf (end/step overflowing a double) is refused too.
  if (!(std::round(n) <= static_cast<double>(kMaxSteps)))
    t->issue("step", fmt::format("found step = {} with end = {}, which is {:.10g} steps; expected "
                                 "at most {} steps (time.end / time.step)",
                                 *step, *end, n, kMaxSteps));
  else if (n < 1 - 1e-9)
    t->issue("end", fmt::format("found end = {} < step = {}, expected end ≥ step (at least one "
                                "step)",
                                *end, *step));
  else if (std::abs(n - std::round(n)) > 1e-9 * n)  // the contract: round(end/step) steps
    warn("time.end", fmt::format("found end/step = {:.10g}, not a whole number of steps: the run "
                                 "has round(end/step) = {:.0f} steps and ends at t = {:g} s",
                                 n, std::round(n), std::round(n) * *step));
}

void CaseReader::warn(const std::string& key, const std::string& message) {
  int line = 1;
  if (const auto node = root_.at_path(key); node && node.node()) {
    line = std::max(1, static_cast<int>(node.node()->source().begin.line));
  }
  p_.warnings.push_back(fmt::format("{}:{}: {}: {}", file_.string(), line, key, message));
}

void CaseReader::warn_unit_habits() {
  // Thresholds (case-format.md, "Warnings"): below each, no solid a user is likely to model
  // has the value in SI, and the habit named gives it. A warning only: the case runs.
  constexpr double kModulus = 1e6;      // Pa: soft rubber ~1e6; steel in MPa: 2.1e5
  constexpr double kDensity = 10;       // kg/m³: solid foams ≥ ~20; steel in g/cm³: 7.85
  constexpr double kSpecificHeat = 50;  // J/(kg·K): lead 128; steel in kJ/(kg·K): 0.45
  constexpr double kTemperature = 150;  // K: −123 °C; room temperature in °C: 20
  for (const auto& [name, m] : materials_) {
    if (!m) continue;
    const auto path = join("materials", name);
    if (m->young_modulus < kModulus)
      warn(
          path + ".young_modulus",
          fmt::format("found {:g} Pa, below {:g} Pa, softer than rubber: did you give MPa? (steel: "
                      "2.1e11 Pa)",
                      m->young_modulus, kModulus));
    if (m->density < kDensity)
      warn(path + ".density", fmt::format("found {:g} kg/m³, below {:g} kg/m³: did you give g/cm³? "
                                          "(steel: 7850 kg/m³)",
                                          m->density, kDensity));
    if (m->specific_heat < kSpecificHeat)
      warn(path + ".specific_heat",
           fmt::format("found {:g} J/(kg·K), below {:g} J/(kg·K): did you give kJ/(kg·K)? (steel: "
                       "450 J/(kg·K))",
                       m->specific_heat, kSpecificHeat));
  }
  const auto cold = [&](const std::string& key, const std::vector<double>& values) {
    for (const double v : values)
      if (v < kTemperature) {
        warn(key, fmt::format("found {:g} K, below {:g} K: did you give °C? Temperatures are in "
                              "kelvin ({:g} °C = {:g} K)",
                              v, kTemperature, v, v + 273.15));
        return;
      }
  };
  cold("physics.reference_temperature", {p_.physics.reference_temperature});
  for (size_t i = 0; i < p_.bodies.size(); ++i)
    if (root_.at_path(join(at("bodies", i), "initial_temperature")))
      cold(join(at("bodies", i), "initial_temperature"), {p_.bodies[i].initial_temperature});
  for (size_t i = 0; i < p_.boundaries.size(); ++i) {
    const auto& bc = p_.boundaries[i];
    const auto here = at("boundary", i);
    if (bc.temperature) cold(join(here, "temperature"), bc.temperature->values());
    if (bc.film) cold(join(here, "film.ambient"), bc.film->ambient.values());
    if (bc.radiation) cold(join(here, "radiation.ambient"), bc.radiation->ambient.values());
  }
}

void CaseReader::read_physics(const TableReader& root) {
  const auto t = root.sub_table("physics");
  if (!t) return;
  if (const auto s = t->choice("heat_capacity")) p_.physics.lumped_heat_capacity = *s == "lumped";
  if (const auto v = t->number("reference_temperature")) p_.physics.reference_temperature = *v;
  if (const auto v = t->boolean("thermal_expansion")) p_.physics.thermal_expansion = *v;
  if (const auto v = t->boolean("thermoelastic_heating")) p_.physics.thermoelastic_heating = *v;
  if (const auto s = t->choice("thermoelastic_rate"))
    p_.physics.thermoelastic_rate = *s == "newmark" ? physics::ThermoelasticRate::newmark
                                                    : physics::ThermoelasticRate::step_mean;
}

void CaseReader::read_materials(const TableReader& root) {
  const auto* n = root.get("materials");
  if (!n) return;
  const auto* all = n->as_table();
  if (!all || all->empty()) {
    root.issue("materials", fmt::format("found {}, expected one or more [materials.NAME] tables",
                                        all ? "no material" : describe(*n)));
    return;
  }
  for (const auto& [key, value] : *all) {
    const std::string name(key.str());
    const auto path = join("materials", name);
    const auto* t = value.as_table();
    if (!t) {
      issues_.add(line_of(value), path,
                  fmt::format("found {}, expected a table of material constants", describe(value)));
      continue;
    }
    const TableReader m(*t, path, issues_, schema::section("materials.*"));
    const auto rho = reference_density(m, "density");
    const auto e = material_law(m, "young_modulus");
    const auto nu = material_law(m, "poisson_ratio");
    const auto alpha = material_law(m, "thermal_expansion");
    const auto cp = material_law(m, "specific_heat");
    const auto kappa = material_law(m, "thermal_conductivity");
    if (!(rho && e && nu && alpha && cp && kappa)) {
      materials_[name] = std::nullopt;  // the name exists; its constants were reported
      continue;
    }
    fem::Material mat;
    mat.density = *rho;
    mat.laws = {*kappa, *cp, *alpha, *e, *nu};
    mat.young_modulus = e->values().front();
    mat.poisson_ratio = nu->values().front();
    // A constant law is its number; a table's number is set at each body's initial
    // temperature (read_body), here at θ₀ for the checks that read materials alone.
    mat.thermal_expansion = alpha->values().front();
    mat.specific_heat = cp->values().front();
    mat.thermal_conductivity = kappa->values().front();
    mat.evaluate_laws_at(p_.physics.reference_temperature);
    materials_[name] = mat;
  }
}

std::optional<core::TemperatureTable> CaseReader::material_law(const TableReader& m,
                                                               std::string_view k) {
  const auto* n = m.get(k);
  return n ? read_temperature_table(*n, m.key(k), issues_, range_of(m.spec(k)),
                                    "the body's temperature")
           : std::nullopt;
}

std::optional<double> CaseReader::reference_density(const TableReader& m, std::string_view k) {
  // ρ is a number: in the reference (Lagrangian) configuration of the thesis the mass is
  // ρ₀ dV₀, which the temperature does not change; the expansion a ρ(θ) table would describe
  // is α(θ)'s (docs/choices.md, "ρ stays a number"). A table is refused by name, not as a
  // mistyped number.
  if (const auto* n = m.get(k, Need::optional, ""); n && n->is_table()) {
    m.issue(k, fmt::format("found a table, expected a number: {} is the reference density ρ₀ "
                           "(the mass ρ₀ dV₀ of the undeformed body does not change with θ; "
                           "the thermal expansion a ρ(θ) table would describe is given by "
                           "thermal_expansion, a number or a table in θ)",
                           k));
    return std::nullopt;
  }
  return m.number(k);
}

const toml::array* CaseReader::tables(const TableReader& root, std::string_view key) {
  const auto* n = root.get(key);
  if (!n) return nullptr;
  const bool required = root.spec(key).required();
  const auto* a = n->as_array();
  if (!a || (required && a->empty()) || !a->is_array_of_tables()) {
    root.issue(key, fmt::format("found {}, expected one or more [[{}]] tables", describe(*n), key));
    return nullptr;
  }
  return a;
}

void CaseReader::read_solver(const TableReader& root) {
  const auto s = root.sub_table("solver");
  if (!s) return;
  auto& settings = p_.solver;
  if (const auto v = s->number("coupling_tolerance")) settings.coupling_tolerance = *v;
  if (const auto v = s->integer("max_coupling_iterations")) settings.max_coupling_iterations = *v;
  if (const auto v = s->choice("friction_loop"))
    settings.friction_loop =
        *v == "nested" ? physics::FrictionLoop::nested : physics::FrictionLoop::staggered;
  if (const auto v = s->choice("coupling_order"))
    settings.coupling_order = *v == "heat_first"        ? physics::CouplingOrder::heat_first
                              : *v == "mechanics_first" ? physics::CouplingOrder::mechanics_first
                                                        : physics::CouplingOrder::automatic;
  if (const auto v = s->number("qp_tolerance")) settings.qp_tolerance = *v;
  if (const auto v = s->boolean("coupling_acceleration")) settings.friction.acceleration = *v;
  if (const auto v = s->choice("conductance_treatment"))
    settings.conductance_treatment = *v == "implicit" ? physics::ConductanceTreatment::implicit
                                                      : physics::ConductanceTreatment::lagged;
  if (const auto v = s->number("qp_forcing")) settings.friction.qp_forcing = *v;
  if (const auto v = s->number("qp_forcing_cap")) {
    settings.friction.qp_forcing_cap = *v;
    // The forced QP tolerance is clamped to [qp_tolerance, qp_forcing_cap].
    if (*v < settings.qp_tolerance)
      s->issue("qp_forcing_cap", fmt::format("found {:g}, below qp_tolerance = {:g}; expected a "
                                             "number in [qp_tolerance, 1)",
                                             *v, settings.qp_tolerance));
  }
  if (const auto v = s->number("loop_forcing")) settings.friction.loop_forcing = *v;
  if (const auto v = s->integer("max_friction_updates")) settings.friction.max_updates = *v;
  if (const auto v = s->integer("max_qp_iterations")) settings.max_qp_iterations = *v;
  if (const auto v = s->integer("explicit_dual_limit")) settings.explicit_dual_limit = *v;
  if (const auto v = s->integer("max_cutbacks")) {
    // τ/2^20 ≈ 1e-6 τ: deeper is no longer a cut-back but a different time scale
    if (const int most = s->spec("max_cutbacks").max; *v > most)
      s->issue("max_cutbacks",
               fmt::format("found {}, expected 0 to {} halvings of the step", *v, most));
    else
      settings.max_cutbacks = *v;
  }
  if (const auto v = s->choice("factorization")) settings.factorization = *v == "auto" ? "" : *v;
  if (const auto v = s->number("feti_tolerance")) settings.feti_tolerance = *v;
  if (const auto v = s->integer("max_feti_iterations")) settings.max_feti_iterations = *v;
  if (const auto v = s->number("newton_tolerance")) settings.newton_tolerance = *v;
  if (const auto v = s->number("modulus_tolerance")) settings.modulus_tolerance = *v;
  if (const auto v = s->integer("max_newton_iterations")) settings.max_newton_iterations = *v;
  if (const auto v = s->choice("feti_preconditioner"))
    settings.feti_preconditioner = *v == "dirichlet" ? feti::Preconditioner::dirichlet
                                   : *v == "lumped"  ? feti::Preconditioner::lumped
                                                     : feti::Preconditioner::none;
  if (const auto v = s->choice("contact_dual")) {
    settings.contact_dual = *v == "auto"     ? physics::ContactDual::automatic
                            : *v == "nested" ? physics::ContactDual::nested
                                             : physics::ContactDual::combined;
    // A cross-key check: read after [time], [[bodies]] and the contact pairs.
    if (settings.contact_dual == physics::ContactDual::combined && issues_.empty())
      if (const auto why = physics::combined_contact_dual_unavailable(p_); !why.empty())
        s->issue("contact_dual",
                 fmt::format("found \"combined\" but {}; expected \"combined\" only with "
                             "one [contact] pair, scheme = \"quasistatic\" and both contact bodies "
                             "decomposed (subdomains > 1), or \"auto\"/\"nested\"",
                             why));
  }
}

void CaseReader::read_output(const TableReader& root) {
  p_.output.directory = resolve("out");
  const auto o = root.sub_table("output");
  if (!o) return;
  if (const auto d = o->string("directory")) {
    if (d->empty())
      o->issue("directory", "found \"\", expected a folder name");
    else
      p_.output.directory = resolve(*d);
  }
  if (const auto e = o->integer("every")) p_.output.every = *e;
  using Encoding = physics::OutputSettings::Encoding;
  const auto format = o->choice("format");
  const auto compression = o->choice("compression");
  if (format == "binary") p_.output.encoding = Encoding::binary;
  if (format == "vtkhdf") {
    if (vtkhdf_available())
      field_files_ = FieldFiles::vtkhdf;
    else  // a build option, not the case's fault: said so, with what this build can write
      o->issue("format",
               "found \"vtkhdf\", but this thermocontact was built without HDF5 (parallel "
               "HDF5, Debian's libhdf5-openmpi-dev, was not found when it was configured); "
               "expected \"ascii\" or \"binary\"");
  }
  if (compression == "zlib") {  // binary implied when format is not given
    if (format != "ascii" && format != "vtkhdf")
      p_.output.encoding = Encoding::zlib;
    else  // VTK compresses the bytes of binary .vtu arrays only
      o->issue("compression",
               fmt::format("found \"zlib\" with format = \"{}\", expected \"none\" or "
                           "format = \"binary\" (or no format: zlib implies binary)",
                           *format));
  }
  if (const auto e = o->integer("checkpoint_every")) p_.output.checkpoint_every = *e;
  if (const auto t = o->number("checkpoint_seconds")) p_.output.checkpoint_seconds = *t;
  if (const auto c = o->boolean("contact_csv")) p_.output.contact_csv = *c;
}

void CaseReader::read_probes(const TableReader& root) {
  const auto* a = root.has("probe") ? tables(root, "probe") : nullptr;
  if (!a) return;
  for (size_t i = 0; i < a->size(); ++i) {
    const TableReader t(*a->get(i)->as_table(), at("probe", i), issues_, schema::section("probe"));
    physics::Probe probe;
    if (const auto name = t.string("name")) {
      check_pair_name(t, *name);  // the same rule: it prefixes columns
      for (const auto& other : p_.output.probes)
        if (other.name == *name)
          t.issue("name", fmt::format("found \"{}\" again, expected a name of its own (it "
                                      "prefixes probes.csv's columns)",
                                      printable(*name)));
      probe.name = *name;
    }
    const auto body = body_index(t, "body", p_.bodies);
    probe.body = body.value_or(0);
    const bool point = t.has("point"), where = t.has("where");
    if (point == where)
      issues_.add(t.line(), t.path(),
                  point ? "found both point and where, expected one of them"
                        : "locates nothing; expected point = [x, y(, z)] or where = a boundary");
    if (const auto w = t.string("where")) {
      probe.where = *w;
      if (body) check_boundary_name(t, "where", p_.bodies[*body], mesh_built_[*body], *w);
    }
    if (const auto* n = t.get("point"))
      if (const auto x = read_vector(*n, t.key("point"), issues_, dim_)) {
        probe.point = *x;
        if (body && mesh_built_[*body] && !locate_point(p_.bodies[*body].mesh, *x))
          t.issue("point",
                  fmt::format("found [{}], expected a point of body \"{}\" (no cell of "
                              "its mesh holds it)",
                              fmt::join(std::span(x->data(), static_cast<size_t>(dim_)), ", "),
                              printable(p_.bodies[*body].name)));
      }
    p_.output.probes.push_back(std::move(probe));
  }
}

}  // namespace tc::io::detail

namespace tc::io {

std::optional<std::pair<int, std::string>> stray_non_ascii(std::string_view text) {
  // TOML allows non-ASCII only inside strings and comments. toml++ 3.3.0 reaches an
  // unreachable branch (undefined behaviour) on U+00A1–U+0499 and U+2FDE–U+33D7 outside them
  // (is_non_ascii_horizontal_whitespace; found by tests/fuzz/fuzz_case_reader), so such text
  // is refused here, before toml++ sees it.
  int line = 1;
  size_t i = 0;
  const size_t n = text.size();
  auto skip_to = [&](std::string_view close, bool escapes, bool single_line) {
    while (i < n) {
      if (escapes && text[i] == '\\' && i + 1 < n) {
        if (text[i + 1] == '\n') ++line;
        i += 2;
        continue;
      }
      if (text.compare(i, close.size(), close) == 0) {
        i += close.size();
        return;
      }
      if (text[i] == '\n') {
        if (single_line) return;  // an unterminated string: toml++ reports it
        ++line;
      }
      ++i;
    }
  };
  while (i < n) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == '#') {
      while (i < n && text[i] != '\n') ++i;
    } else if (text.compare(i, 3, "\"\"\"") == 0) {
      i += 3;
      skip_to("\"\"\"", true, false);
    } else if (text.compare(i, 3, "\'\'\'") == 0) {
      i += 3;
      skip_to("\'\'\'", false, false);
    } else if (c == '"') {
      ++i;
      skip_to("\"", true, true);
    } else if (c == '\'') {
      ++i;
      skip_to("\'", false, true);
    } else if (static_cast<unsigned char>(c) >= 0x80) {
      std::string bytes;  // the UTF-8 sequence as written
      for (size_t k = i; k < n && k < i + 4 && static_cast<unsigned char>(text[k]) >= 0x80; ++k)
        bytes += fmt::format("\\x{:02X}", static_cast<unsigned char>(text[k]));
      return std::pair{line, bytes};
    } else {
      ++i;
    }
  }
  return std::nullopt;
}

physics::Problem read_case(const std::filesystem::path& file,
                           std::span<const std::string> overrides) {
  FieldFiles ignored = FieldFiles::vtu;
  return read_case(file, overrides, ignored);
}

physics::Problem read_case(const std::filesystem::path& file,
                           std::span<const std::string> overrides, FieldFiles& field_files) {
  if (const auto why = not_a_file(file); !why.empty())
    throw InputError({{file.string(), 1, "(file)", "cannot read the case file: it " + why}});
  std::string text;
  {
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    text = s.str();
  }
  if (const auto stray = stray_non_ascii(text))
    throw InputError({{file.string(), stray->first, "(syntax)",
                       fmt::format("found the non-ASCII bytes {} outside a string or comment, "
                                   "expected ASCII keys, values and punctuation (other "
                                   "characters belong in \"strings\" or # comments)",
                                   stray->second)}});
  toml::table root;
  try {
    root = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    throw InputError({{file.string(), static_cast<int>(e.source().begin.line), "(syntax)",
                       fmt::format("not valid TOML: {}", e.description())}});
  }
  const auto applied = detail::apply_overrides(root, overrides);
  try {
    detail::CaseReader reader(file, root);
    auto problem = reader.read();
    field_files = reader.field_files();
    problem.overrides.assign(overrides.begin(), overrides.end());
    problem.content = detail::case_content(root, applied);
    // A warning about an overridden value names its --set, not a line of the file.
    const auto prefix = file.string() + ":";
    for (auto& w : problem.warnings) {
      if (w.rfind(prefix, 0) != 0) continue;
      const auto key_at = w.find(": ", prefix.size());
      const auto key_end = w.find(": ", key_at + 2);
      if (key_at == std::string::npos || key_end == std::string::npos) continue;
      std::vector<InputIssue> one{{"", 0, w.substr(key_at + 2, key_end - key_at - 2), ""}};
      detail::attribute_issues(one, applied);
      if (one[0].line < 0) w = one[0].file + w.substr(key_at);
    }
    return problem;
  } catch (const InputError& e) {
    if (applied.empty()) throw;
    auto issues = e.issues();
    detail::attribute_issues(issues, applied);
    throw InputError(std::move(issues));
  }
}

}  // namespace tc::io
