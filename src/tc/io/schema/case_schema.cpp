#include "tc/io/schema/case_schema.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <vector>

#include "tc/io/schema/case_schema_parts.hpp"

namespace tc::io::schema {

namespace {

constexpr Range kTemperature = above_zero("a temperature > 0 K");
constexpr Range kFraction{0, 1, false, false, "a number in (0, 1)"};
constexpr Range kEmissivity{0, 1, true, true, "an emissivity in [0, 1]"};

using T = Type;

// ---------------------------------------------------------------------------------------
// The root and [time], [physics]

constexpr Key kRoot[] = {
    {.name = "title",
     .type = T::string,
     .default_value = "\"\"",
     .doc = "echoed in the summary; at most 4096 bytes"},
    {.name = "dimension",
     .type = T::dimension,
     .default_value = "required",
     .doc = "2 (plane strain) or 3",
     .expected = "2 (plane strain) or 3"},
    {.name = "time",
     .type = T::table,
     .default_value = "required",
     .doc = "the time scheme and the steps"},
    {.name = "physics", .type = T::table, .doc = "the thermo-mechanical coupling terms"},
    {.name = "materials",
     .type = T::named_tables,
     .default_value = "required",
     .doc = "[materials.NAME] tables of constants",
     .expected = "[materials.NAME] tables"},
    {.name = "bodies",
     .type = T::tables,
     .default_value = "required",
     .doc = "[[bodies]], one table per body"},
    {.name = "boundary", .type = T::tables, .doc = "[[boundary]], one per loaded or held face"},
    {.name = "contact",
     .type = T::contact_tables,
     .doc = "[contact] (one pair) or [[contact]] tables"},
    {.name = "solver", .type = T::table, .doc = "tolerances, limits and methods"},
    {.name = "output", .type = T::table, .doc = "where and how often results are written"},
    {.name = "probe", .type = T::tables, .doc = "[[probe]], points recorded every step"},
    {.name = "stability",
     .type = T::table,
     .doc = "the linear stability analysis (`thermocontact stability`)"},
};

constexpr std::string_view kSchemes[] = {"dynamic", "quasistatic"};
constexpr std::string_view kContactSchemes[] = {"stabilised", "plain", "modified_mass"};

constexpr Key kTime[] = {
    {.name = "scheme",
     .type = T::choice,
     .choices = kSchemes,
     .default_value = "\"dynamic\"",
     .doc = "Newmark (u) + backward Euler (θ), or no inertia"},
    {.name = "step",
     .type = T::number,
     .range = above_zero("a time step > 0"),
     .default_value = "required",
     .unit = "s",
     .doc = "τ"},
    {.name = "end",
     .type = T::number,
     .range = above_zero("an end time > 0"),
     .default_value = "required",
     .unit = "s",
     .doc = "T; the run has round(end/step) steps"},
    {.name = "contact_scheme",
     .type = T::choice,
     .choices = kContactSchemes,
     .default_value = "\"modified_mass\"",
     .doc = "how Newmark meets contact (dynamic runs)"},
};

constexpr std::string_view kHeatCapacities[] = {"consistent", "lumped"};
constexpr std::string_view kThermoelasticRates[] = {"step_mean", "newmark"};

constexpr Key kPhysics[] = {
    {.name = "reference_temperature",
     .type = T::number,
     .range = kTemperature,
     .default_value = "293.15",
     .unit = "K",
     .doc = "θ₀, the stress-free temperature"},
    {.name = "thermal_expansion",
     .type = T::boolean,
     .default_value = "true",
     .doc = "the K_uθ term of (2.5)"},
    {.name = "thermoelastic_heating",
     .type = T::boolean,
     .default_value = "true",
     .doc = "the K_θu term of (2.8)"},
    {.name = "thermoelastic_rate",
     .type = T::choice,
     .choices = kThermoelasticRates,
     .default_value = "\"step_mean\"",
     .doc = "u̇ in the K_θu term of dynamic runs: (u^{k+1} − u^k)/τ, or Newmark's u̇^{k+1} as (5.6)"},
    {.name = "heat_capacity",
     .type = T::choice,
     .choices = kHeatCapacities,
     .default_value = "\"consistent\"",
     .doc = "M_θ as assembled, or lumped (row sums; HRZ on Tri6, Quad8, Tet10, Hex20)"},
};

constexpr Key kMaterial[] = {
    {.name = "density",
     .type = T::number,
     .range = above_zero("a density > 0"),
     .default_value = "required",
     .unit = "kg/m³",
     .doc = "ρ"},
    {.name = "young_modulus",
     .type = T::temperature_table,
     .range = above_zero("a modulus > 0"),
     .default_value = "required",
     .unit = "Pa",
     .doc = "E; a number or a table in θ (A_u refactorised past modulus_tolerance)"},
    {.name = "poisson_ratio",
     .type = T::temperature_table,
     .range = {0, 0.5, true, false, "a number in [0, 0.5)"},
     .default_value = "required",
     .doc = "ν; a number or a table in θ (A_u refactorised past modulus_tolerance)"},
    {.name = "thermal_expansion",
     .type = T::temperature_table,
     .range = from_zero("a number ≥ 0"),
     .default_value = "required",
     .unit = "1/K",
     .doc = "α; a number or a table of the tangent α(θ), the strain ∫_{θ₀}^{θ} α dθ"},
    {.name = "specific_heat",
     .type = T::temperature_table,
     .range = above_zero("a number > 0"),
     .default_value = "required",
     .unit = "J/(kg·K)",
     .doc = "c_p; the heat equation uses ρ·c_p; a number or a table in θ"},
    {.name = "thermal_conductivity",
     .type = T::temperature_table,
     .range = above_zero("a number > 0"),
     .default_value = "required",
     .unit = "W/(m·K)",
     .doc = "κ; a number or a table in θ"},
};

// ---------------------------------------------------------------------------------------
// [[bodies]]

constexpr std::string_view kInitialStates[] = {"rest", "equilibrium"};

constexpr Key kBody[] = {
    {.name = "name",
     .type = T::name,
     .default_value = "required",
     .doc = "unique; 1–64 letters, digits, _ - . (not first)"},
    {.name = "material",
     .type = T::name,
     .default_value = "required",
     .doc = "a NAME of [materials.NAME]"},
    {.name = "mesh",
     .type = T::table,
     .default_value = "required",
     .doc = "box = { min, max, cells } or file = \"NAME.msh\""},
    {.name = "initial_temperature",
     .type = T::number,
     .range = kTemperature,
     .default_value = "physics.reference_temperature",
     .unit = "K",
     .doc = "θ at t = 0"},
    {.name = "initial_velocity",
     .type = T::vector,
     .default_value = "[0.0, 0.0, 0.0]",
     .unit = "m/s",
     .doc = "u̇ at t = 0"},
    {.name = "initial_state",
     .type = T::choice,
     .choices = kInitialStates,
     .default_value = "\"rest\"",
     .doc = "u⁰ = u_D(0), or the static equilibrium"},
    {.name = "body_force",
     .type = T::components,
     .default_value = "[0.0, 0.0, 0.0]",
     .unit = "N/m³",
     .doc = "f of (2.1); per component a number or a time table"},
    {.name = "heat_source",
     .type = T::time_table,
     .default_value = "0.0",
     .unit = "W/m³",
     .doc = "r of (2.8)"},
    {.name = "subdomains",
     .type = T::subdomains,
     .default_value = "\"auto\"",
     .doc = "FETI subdomains (METIS); 1 = the body itself"},
};

constexpr Key kMesh[] = {
    {.name = "box", .type = T::table, .doc = "a box of hexahedra (quadrilaterals in 2D)"},
    {.name = "file", .type = T::string, .doc = "a Gmsh 4 file, relative to the case file"},
};

constexpr std::string_view kBoxElements[] = {"Quad4", "Quad8", "Quad9", "Tri3", "Tri6",
                                             "Hex8",  "Hex20", "Hex27", "Tet4", "Tet10"};

constexpr Key kBox[] = {
    {.name = "min",
     .type = T::vector,
     .default_value = "required",
     .unit = "m",
     .doc = "the lower corner",
     .expected = "an array of numbers"},
    {.name = "max",
     .type = T::vector,
     .default_value = "required",
     .unit = "m",
     .doc = "the upper corner, > min on every axis",
     .expected = "an array of numbers"},
    {.name = "cells",
     .type = T::counts,
     .default_value = "required",
     .doc = "cells per axis; at most 10⁸ in all",
     .expected = "an array of integers ≥ 1"},
    {.name = "element",
     .type = T::choice,
     .choices = kBoxElements,
     .default_value = "none",
     .doc = "the cells, of the body's dimension: Quad4 (2D) and Hex8 (3D) when absent"},
};

// ---------------------------------------------------------------------------------------
// [[boundary]]

constexpr Key kBoundary[] = {
    {.name = "body", .type = T::name, .default_value = "required", .doc = "the name of a body"},
    {.name = "where",
     .type = T::name,
     .default_value = "required",
     .doc = "a box face (xmin … zmax) or a Gmsh physical group"},
    {.name = "displacement",
     .type = T::components,
     .unit = "m",
     .doc = "per component a number, a time table or \"free\""},
    {.name = "traction",
     .type = T::components,
     .unit = "Pa",
     .doc = "p_N; per component a number, a time table or \"free\""},
    {.name = "force",
     .type = T::components,
     .unit = "N",
     .doc = "a resultant through a rigid coupling (load control)"},
    {.name = "temperature",
     .type = T::time_table,
     .range = kTemperature,
     .unit = "K",
     .doc = "θ_D"},
    {.name = "heat_flux", .type = T::time_table, .unit = "W/m²", .doc = "q_N into the body"},
    {.name = "film", .type = T::table, .doc = "q = h(θ − θ∞) leaves the body"},
    {.name = "radiation", .type = T::table, .doc = "q = εσ(θ⁴ − θ∞⁴) leaves the body"},
};

constexpr Key kFilm[] = {
    {.name = "coefficient",
     .type = T::time_table,
     .range = above_zero("a film coefficient h [W/(m²K)] > 0"),
     .default_value = "required",
     .unit = "W/(m²·K)",
     .doc = "h"},
    {.name = "ambient",
     .type = T::time_table,
     .range = kTemperature,
     .default_value = "required",
     .unit = "K",
     .doc = "θ∞"},
};

constexpr Key kRadiation[] = {
    {.name = "emissivity",
     .type = T::time_table,
     .range = {0, 1, false, true, "an emissivity in (0, 1]"},
     .default_value = "required",
     .doc = "ε"},
    {.name = "ambient",
     .type = T::time_table,
     .range = kTemperature,
     .default_value = "required",
     .unit = "K",
     .doc = "θ∞"},
};

// ---------------------------------------------------------------------------------------
// [contact]

constexpr Key kContact[] = {
    {.name = "name",
     .type = T::string,
     .default_value = "\"contact\"",
     .doc = "required for several pairs: letters, digits, _"},
    {.name = "slave",
     .type = T::table,
     .default_value = "required",
     .doc = "{ body, where }: the slave surface"},
    {.name = "master",
     .type = T::table,
     .default_value = "required",
     .doc = "{ body, where }: the master surface; or a rigid tool { rigid = \"plane\", … }"},
    {.name = "friction",
     .type = T::temperature_table,
     .range = from_zero("a coefficient ≥ 0"),
     .default_value = "0.0",
     .doc = "𝔉 (Coulomb); a number or a table in θ_Γ"},
    {.name = "conductance",
     .type = T::table,
     .doc = "{ slave = γ_C^s, master = γ_C^m }, needed while heat crosses"},
    {.name = "heat_conduction",
     .type = T::boolean,
     .default_value = "true",
     .doc = "the β_C λ_n [θ] term (L_θγ)"},
    {.name = "frictional_heating",
     .type = T::boolean,
     .default_value = "true",
     .doc = "the δ_C 𝔉 λ_n ‖[u̇]_τ‖ term (d_θγ)"},
    {.name = "gap_conductance",
     .type = T::table,
     .doc = "{ table, gas_conductivity, gas_offset, emissivity_slave, emissivity_master }: h "
            "across the gap, added to β_C p_n"},
};

constexpr Key kGapConductance[] = {
    {.name = "table",
     .type = T::gap_table,
     .range = from_zero("a conductance ≥ 0"),
     .default_value = "0.0",
     .unit = "W/(m²·K)",
     .doc = "h_table(g); a number or { gap = [...] (m), value = [...] }"},
    {.name = "gas_conductivity",
     .type = T::number,
     .range = from_zero("a conductivity ≥ 0"),
     .default_value = "0.0",
     .unit = "W/(m·K)",
     .doc = "k_gas of the gas conduction k_gas/(g + g₀)"},
    {.name = "gas_offset",
     .type = T::number,
     .range = above_zero("a length > 0"),
     .unit = "m",
     .doc = "g₀ of k_gas/(g + g₀); needed with k_gas > 0"},
    {.name = "emissivity_slave",
     .type = T::number,
     .range = kEmissivity,
     .default_value = "0.0",
     .doc = "ε_s of the slave face, for radiation σε(θ_s⁴ − θ_m⁴) across the gap"},
    {.name = "emissivity_master",
     .type = T::number,
     .range = kEmissivity,
     .default_value = "0.0",
     .doc = "ε_m of the master face; ε = 1/(1/ε_s + 1/ε_m − 1), none if either is 0"},
};

constexpr std::string_view kRigidShapes[] = {"plane"};

// A side of a pair: a body's surface ({ body, where }, both required), or for the master an
// analytic rigid tool ({ rigid, point, normal, velocity or displacement, temperature }); the
// reader says which keys go together (read_contact).
constexpr Key kSurface[] = {
    {.name = "body", .type = T::name, .doc = "the name of a body (a body's surface)"},
    {.name = "where", .type = T::name, .doc = "a boundary of that body (a body's surface)"},
    {.name = "rigid",
     .type = T::choice,
     .choices = kRigidShapes,
     .doc = "master only: an analytic rigid tool instead of a body's surface"},
    {.name = "point",
     .type = T::vector,
     .unit = "m",
     .doc = "rigid tool: a point of its plane at t = 0"},
    {.name = "normal",
     .type = T::vector,
     .doc = "rigid tool: the plane's normal out of the tool, towards the slave (≠ 0)"},
    {.name = "velocity",
     .type = T::vector,
     .unit = "m/s",
     .doc = "rigid tool: its constant velocity from t = 0 (or displacement; neither: at rest)"},
    {.name = "displacement",
     .type = T::components,
     .unit = "m",
     .doc = "rigid tool: its motion per component, a number or a time table"},
    {.name = "temperature",
     .type = T::time_table,
     .range = kTemperature,
     .unit = "K",
     .doc = "rigid tool: its temperature, a number or a time table; absent: adiabatic"},
};

constexpr Key kConductance[] = {
    {.name = "slave",
     .type = T::temperature_table,
     .range = from_zero("a conductance ≥ 0"),
     .default_value = "required",
     .unit = "W/(m²·K·Pa)",
     .doc = "γ_C^s; a number or a table in θ_Γ"},
    {.name = "master",
     .type = T::temperature_table,
     .range = from_zero("a conductance ≥ 0"),
     .default_value = "required",
     .unit = "W/(m²·K·Pa)",
     .doc = "γ_C^m; a number or a table in θ_Γ"},
};

// ---------------------------------------------------------------------------------------
// [solver], [output]

constexpr std::string_view kCouplingOrders[] = {"auto", "heat_first", "mechanics_first"};
constexpr std::string_view kFrictionLoops[] = {"nested", "staggered"};
constexpr std::string_view kFactorizations[] = {"auto", "mumps", "cholmod", "petsc"};
constexpr std::string_view kPreconditioners[] = {"dirichlet", "lumped", "none"};
constexpr std::string_view kContactDuals[] = {"auto", "nested", "combined"};
constexpr std::string_view kConductanceTreatments[] = {"implicit", "lagged"};

constexpr Key kSolver[] = {
    {.name = "coupling_tolerance",
     .type = T::number,
     .range = kFraction,
     .default_value = "1e-6",
     .doc = "staggered fixed point: relative change of θ and λ"},
    {.name = "max_coupling_iterations",
     .type = T::integer,
     .default_value = "20",
     .doc = "iterations of the staggered fixed point"},
    {.name = "coupling_order",
     .type = T::choice,
     .choices = kCouplingOrders,
     .default_value = "\"auto\"",
     .doc = "which half of each iteration comes first"},
    {.name = "friction_loop",
     .type = T::choice,
     .choices = kFrictionLoops,
     .default_value = "\"nested\"",
     .doc = "where γ = λ_n of (6.3) is updated"},
    {.name = "qp_tolerance",
     .type = T::number,
     .range = kFraction,
     .default_value = "1e-8",
     .doc = "relative norm of the projected gradient"},
    {.name = "max_qp_iterations",
     .type = T::integer,
     .default_value = "2000",
     .doc = "iterations of one QP"},
    {.name = "factorization",
     .type = T::choice,
     .choices = kFactorizations,
     .default_value = "\"auto\"",
     .doc = "the Cholesky package of an undecomposed body"},
    {.name = "feti_tolerance",
     .type = T::number,
     .range = kFraction,
     .default_value = "1e-10",
     .doc = "FETI: ‖B u − c‖ relative to ‖P d‖"},
    {.name = "max_feti_iterations",
     .type = T::integer,
     .default_value = "1000",
     .doc = "iterations of FETI's projected CG"},
    {.name = "feti_preconditioner",
     .type = T::choice,
     .choices = kPreconditioners,
     .default_value = "\"dirichlet\"",
     .doc = "FETI's preconditioner"},
    {.name = "contact_dual",
     .type = T::choice,
     .choices = kContactDuals,
     .default_value = "\"nested\"",
     .doc = "the contact QP: nested or one TFETI QP"},
    {.name = "newton_tolerance",
     .type = T::number,
     .range = kFraction,
     .default_value = "1e-10",
     .doc = "Newton in a heat step with radiation or h(t)"},
    {.name = "modulus_tolerance",
     .type = T::number,
     .range = from_zero("a relative change ≥ 0"),
     .default_value = "1e-3",
     .doc = "E(θ), ν(θ): refactorise A_u when a cell's E or ν moved by more, relatively"},
    {.name = "max_newton_iterations",
     .type = T::integer,
     .default_value = "50",
     .doc = "Newton iterations of one heat step"},
    {.name = "coupling_acceleration",
     .type = T::boolean,
     .default_value = "true",
     .doc = "Aitken's Δ² on γ = λ_n (6.3)"},
    {.name = "conductance_treatment",
     .type = T::choice,
     .choices = kConductanceTreatments,
     .default_value = "\"implicit\"",
     .doc = "L_θγ on the left, or lagged as (6.2)"},
    {.name = "qp_forcing",
     .type = T::number,
     .range = kFraction,
     .default_value = "1e-2",
     .doc = "friction: a QP to this × the last relative residual"},
    {.name = "qp_forcing_cap",
     .type = T::number,
     .range = kFraction,
     .default_value = "1e-3",
     .doc = "the loosest forced QP tolerance, ≥ qp_tolerance"},
    {.name = "loop_forcing",
     .type = T::number,
     .range = kFraction,
     .default_value = "1e-2",
     .doc = "nested loop: the fall that ends it at one θ"},
    {.name = "max_friction_updates",
     .type = T::integer,
     .default_value = "100",
     .doc = "nested loop: updates γ = λ_n at one θ"},
    {.name = "explicit_dual_limit",
     .type = T::integer,
     .min = 0,
     .default_value = "1500",
     .doc = "rows up to which the nested dual forms F"},
    {.name = "max_cutbacks",
     .type = T::integer,
     .min = 0,
     .max = 20,
     .default_value = "4",
     .doc = "halvings of a failed step"},
};

}  // namespace

std::span<const Section> sections() {
  // [output], [[probe]] and [stability]: case_schema_output.cpp.
  static const Section kSections[] = {
      {"", kRoot},
      {"time", kTime},
      {"physics", kPhysics},
      {"materials.*", kMaterial},
      {"bodies", kBody},
      {"bodies.mesh", kMesh},
      {"bodies.mesh.box", kBox},
      {"boundary", kBoundary},
      {"boundary.film", kFilm},
      {"boundary.radiation", kRadiation},
      {"contact", kContact},
      {"contact.slave", kSurface},
      {"contact.master", kSurface},
      {"contact.conductance", kConductance},
      {"contact.gap_conductance", kGapConductance},
      {"solver", kSolver},
      {"output", output_keys()},
      {"probe", probe_keys()},
      {"stability", stability_keys()},
  };
  return kSections;
}

}  // namespace tc::io::schema
