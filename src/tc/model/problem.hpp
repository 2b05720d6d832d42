#pragma once
// The description of a run, as the case file states it (case-format.md), after validation:
// plain data, filled by io::read_case and consumed by physics::Simulation.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tc/core/table.hpp"
#include "tc/fem/material.hpp"
#include "tc/feti/preconditioner.hpp"
#include "tc/mesh/mesh.hpp"

namespace tc::physics {

using core::TemperatureTable;
using core::TimeTable;

enum class Scheme { dynamic, quasistatic };

/// How Newmark meets contact (dynamic runs with [contact] only): the thesis' plain scheme
/// (5.1–5.4), or the contact-stabilised Newmark of Deuflhard, Krause & Ertel (IJNME 73, 2008),
/// whose predictor is projected onto the admissible set in the mass norm and whose position
/// update drops the last step's contact force: energy then never grows at an impact; or
/// plain Newmark with the modified mass matrix of Hager, Hüeber & Wohlmuth (IJNME 73, 2008):
/// no inertia on the contact boundaries, whose nodes are then in equilibrium at every t^k.
enum class ContactScheme { plain, stabilised, modified_mass };

struct TimeSettings {
  Scheme scheme = Scheme::dynamic;
  double step = 0;  // τ [s]
  double end = 0;   // T [s]
  ContactScheme contact_scheme = ContactScheme::modified_mass;
  [[nodiscard]] int n_steps() const;  // round(end / step)
};

/// The displacement rate of the thermoelastic term θ₀K_uθᵀu̇ of (5.6) in dynamic runs.
enum class ThermoelasticRate {
  step_mean,  ///< (u^{k+1} − u^k)/τ: backward Euler's rate, as θ̇ has in (5.5)
  newmark,    ///< Newmark's u̇^{k+1} = 2/τ(u^{k+1} − u^k) − u̇^k, as (5.6) writes it
};

struct PhysicsSettings {
  double reference_temperature = 293.15;  // θ₀ [K], > 0
  bool thermal_expansion = true;          // K_uθ of (2.5)
  bool thermoelastic_heating = true;      // K_θu of (2.8)
  /// The mean rate by default: Newmark's u̇^{k+1} rings ±Δv from step to step after a jump of
  /// velocity (an impact, a sudden start), and the ringing enters the heat as a source that
  /// alternates in sign (docs/choices.md, "The thermoelastic term at the step's mean rate").
  ThermoelasticRate thermoelastic_rate = ThermoelasticRate::step_mean;
  /// M_θ lumped to its row sums: backward Euler then keeps temperatures between their bounds
  /// (discrete maximum principle on meshes whose K_θ has no positive off-diagonal entries),
  /// where the consistent M_θ overshoots at sharp fronts for τ ≪ ρc_p h²/κ.
  bool lumped_heat_capacity = false;
};

struct Body {
  std::string name;
  /// The held body standing for a contact pair's rigid tool (place_rigid_tools), not a body of
  /// the case file: massless, every node held on the tool's motion and temperature.
  bool rigid_tool = false;
  std::string material_name;
  fem::Material material;
  mesh::Mesh mesh;
  std::filesystem::path mesh_file;           // the Gmsh file it was read from; empty for a box
  double initial_temperature = 0;            // θ at t = 0 [K]
  std::array<double, 3> initial_velocity{};  // u̇ at t = 0
  /// u⁰ from the static equilibrium K u⁰ = f(0) − K_uθ(θ⁰ − θ₀) (dynamic runs), instead of
  /// u⁰ = u_D(0) with the free dofs at 0: a body that starts hot is then already expanded
  /// rather than released with a thermal shock (docs/choices.md, "Initial state").
  bool start_in_equilibrium = false;
  std::array<TimeTable, 3> body_force{};  // f of (2.1) [N/m³]
  TimeTable heat_source{0.0};             // r of (2.8) [W/m³]
  int subdomains = 1;
  /// Why `subdomains = "auto"` chose the count: the estimates it weighed (io::SubdomainChoice's
  /// text, printed by `check` and recorded in summary.json); empty when the case set a number.
  std::string subdomains_reason;
};

/// Stefan–Boltzmann constant σ [W/(m²K⁴)] (CODATA 2018, exact in SI since 2019).
inline constexpr double stefan_boltzmann = 5.670374419e-8;

/// A film (convection, Robin) boundary: q = h (θ − θ∞) leaves the body [W/m²].
struct Film {
  TimeTable coefficient;  // h [W/(m²K)], > 0
  TimeTable ambient;      // θ∞ [K], > 0
};

/// A radiating boundary: q = εσ(θ⁴ − θ∞⁴) leaves the body [W/m²].
struct Radiation {
  TimeTable emissivity;  // ε, in (0, 1]
  TimeTable ambient;     // θ∞ [K], > 0
};

/// One [[boundary]] entry: per component a displacement or a traction (or neither = free).
struct BoundaryCondition {
  int body = 0;  // index into Problem::bodies
  std::string where;
  std::array<std::optional<TimeTable>, 3> displacement;
  std::array<std::optional<TimeTable>, 3> traction;  // p_N [Pa]
  /// A resultant force [N] per component through a rigid coupling (rigid_coupling.hpp): the
  /// face's nodes share that displacement component, and its nodal forces sum to the value.
  std::array<std::optional<TimeTable>, 3> force;
  std::optional<TimeTable> temperature;  // θ_D [K]
  std::optional<TimeTable> heat_flux;    // q_N [W/m²] into the body
  std::optional<Film> film;              // h(θ − θ∞) out of the body
  std::optional<Radiation> radiation;    // εσ(θ⁴ − θ∞⁴) out of the body
};

/// An analytic rigid master of a contact pair (`master = { rigid = "plane", … }`): the plane
/// through `point` with the unit `normal` pointing out of the tool, towards the slave, moved
/// rigidly by `motion`; its thermal side a prescribed temperature (with the pair's conductance
/// law) or, without one, adiabatic. It enters the solver as a held body (rigid_tool.hpp).
struct RigidTool {
  std::array<double, 3> point{0, 0, 0};
  std::array<double, 3> normal{0, 0, 1};
  std::array<TimeTable, 3> motion{};     // the tool's displacement from t = 0 [m]
  std::optional<TimeTable> temperature;  // θ of the tool [K]; none: adiabatic
};

/// The conductance across the gap g at a slave node, h(g) ≥ 0 [W/(m²K)] (`gap_conductance`):
/// a table in g plus gas conduction k_gas/(g + g₀), at g⁺ = max(g, 0), plus radiation between
/// the two grey faces. It is added to the pressure-dependent β_C p_n at every node of the pair,
/// open or closed, so that the conductance is continuous at closure (docs/choices.md, "Gap
/// conductance", "Radiation across the gap").
struct GapConductance {
  TimeTable table{0.0};         // h_table(g), piecewise linear in g [m] (not in time)
  double gas_conductivity = 0;  // k_gas [W/(m·K)] ≥ 0
  double gas_offset = 0;        // g₀ [m], > 0 where k_gas > 0
  double emissivity_slave = 0, emissivity_master = 0;  // ε_s, ε_m ∈ [0, 1] of the two faces
  /// ε of two parallel grey faces, 1/(1/ε_s + 1/ε_m − 1); 0 when either face is 0 (no
  /// radiation).
  [[nodiscard]] double effective_emissivity() const {
    if (!(emissivity_slave > 0 && emissivity_master > 0)) return 0.0;
    return 1.0 / (1.0 / emissivity_slave + 1.0 / emissivity_master - 1.0);
  }
};

/// One contact pair ([[contact]], or the single [contact] table): a slave surface of one body
/// against a master surface of another, with the pair's own interface laws.
struct ContactSettings {
  std::string name;  // unique among the pairs; the suffix of its history.csv columns
  int slave_body = 0, master_body = 1;
  std::string slave_where, master_where;
  /// A rigid tool as the master: master_body and master_where then name the body that
  /// place_rigid_tools made for it (−1 and "" until then).
  std::optional<RigidTool> rigid_master;
  // The interface laws of (2.13), each a number or a table in the interface temperature
  // (physics::InterfaceLaws evaluates them per contact node).
  TemperatureTable friction = 0.0;                                     // 𝔉 ≥ 0
  TemperatureTable conductance_slave = 0.0, conductance_master = 0.0;  // γ_C^s, γ_C^m ≥ 0
  bool heat_conduction = true;
  bool frictional_heating = true;
  /// h(g) across the gap, added to β_C p_n (with heat_conduction only); none: 0.
  std::optional<GapConductance> gap_conductance;
};

/// Where the Tresca → Coulomb update γ = λ_n of (6.3) sits in the fixed point of a step.
enum class FrictionLoop {
  nested,    // iterated inside the mechanical half at the θ of the iteration: QPs only (default)
  staggered  // one update per heat–mechanics iteration, as (6.3) is written
};

/// Which half of each iteration of the staggered fixed point (6.3) comes first (docs/choices.md,
/// "The order of the staggered fixed point"). The fixed point is the same; the iterations to it
/// are not.
enum class CouplingOrder {
  automatic,        // mechanics first where the heat step has the thermoelastic term, else heat
  heat_first,       // as the thesis orders (6.1)–(6.3)
  mechanics_first,  // the mechanical half at θ of the last iterate, then the heat step
};
/// Whether a heat step with (`thermoelastic_heating`) or without the thermoelastic term comes
/// before the mechanical half under `order`. That term, (2/τ) K_θu u^{k+1,p} in (6.1), amplifies
/// the error of the displacement guess by 2/τ; θ enters the mechanics unamplified (K_uθ θ).
[[nodiscard]] bool heat_before_mechanics(CouplingOrder order, bool thermoelastic_heating);

/// The dual QP of the mechanical step with contact (docs/choices.md, FETI):
enum class ContactDual {
  automatic,  // combined where it applies (combined_contact_dual_unavailable), else nested
  nested,     // the contact QP on top of each body's solver (DualContactSolver)
  combined    // one TFETI QP over gluing, Dirichlet and contact multipliers (feti::ContactFeti)
};

/// How the contact conductance L_θγ of §4.4 enters the heat step of the fixed point (6.3).
enum class ConductanceTreatment {
  implicit,  // L θ^{p+1} on the left, solved exactly through the interface (default)
  lagged     // the thesis' (6.2): L θ^p of the previous iterate on the right-hand side
};

/// The Tresca → Coulomb fixed point of a step (friction_fixed_point.hpp): its acceleration and
/// its forcing terms, which leave a QP or a loop inexact only where that cannot change the
/// answer (as in inexact Newton methods; docs/choices.md, "friction loop").
struct FrictionFixedPointSettings {
  bool acceleration = true;  // Aitken's Δ² on γ; off: the plain update γ ← λ_n of (6.3)
  /// A QP to qp_forcing × the last relative residual ‖λ_n(γ) − γ‖/‖λ‖, clamped to
  /// [qp_tolerance, qp_forcing_cap]; the update that ends the loop has a QP to qp_tolerance.
  double qp_forcing = 1e-2;
  double qp_forcing_cap = 1e-3;
  /// Nested loop with thermal expansion: the loop at one θ stops once its residual fell by this
  /// factor (θ, hence u_free and λ, moves in the next heat step).
  double loop_forcing = 1e-2;
  /// Nested loop: the Tresca → Coulomb updates allowed at one θ. The map γ ↦ λ_n(γ) contracts
  /// slowly where friction moves the pressure (a block dragged by its top tilts onto its
  /// leading edge): 12–34 Aitken-relaxed updates per step at the reversals of a quasistatic
  /// slide in plane strain (tests/verification/quasistatic_work_test.cpp), where the plain
  /// update diverges.
  int max_updates = 100;
};

struct SolverSettings {
  double coupling_tolerance = 1e-6;
  int max_coupling_iterations = 20;
  FrictionLoop friction_loop = FrictionLoop::nested;
  CouplingOrder coupling_order = CouplingOrder::automatic;
  FrictionFixedPointSettings friction;
  ConductanceTreatment conductance_treatment = ConductanceTreatment::implicit;
  double qp_tolerance = 1e-8;
  int max_qp_iterations = 2000;
  ContactDual contact_dual = ContactDual::nested;
  /// The nested dual forms F explicitly while it has at most this many rows (0: always
  /// matrix-free); unset: DualContactSettings::explicit_limit as the caller gave it (1500).
  std::optional<int> explicit_dual_limit;
  std::string factorization;  // "" = automatic; "mumps" | "cholmod" | "petsc"
  // FETI (bodies with subdomains > 1, 6.2): relative gluing/Dirichlet residual, iteration cap
  // of the projected CG, preconditioner.
  double feti_tolerance = 1e-10;
  int max_feti_iterations = 1000;
  feti::Preconditioner feti_preconditioner = feti::Preconditioner::dirichlet;
  // Newton's method in the heat step of a body with radiation (or a film whose h changes in
  // time): ‖residual‖ ≤ newton_tolerance × the scale of the equation, iteration cap.
  double newton_tolerance = 1e-10;
  int max_newton_iterations = 50;
  /// E(θ) or ν(θ) a table: K_u, K_uθ are re-assembled and A_u refactorised at the start of a
  /// step once some cell's E or ν at θ^k differs from the factorised one by more than this,
  /// relatively (0: at every change; physics::BodySystem::update_moduli).
  double modulus_tolerance = 1e-3;
  /// A step that fails (a QP, the friction loop or the staggered loop not converged, a
  /// contact law violated) is retried from its start as two steps of τ/2, each of which may be
  /// cut back again: at most this many halvings deep (Simulation::advance; 0 = stop at once).
  int max_cutbacks = 4;
};

/// A `[[probe]]` of the case: point fields recorded after every step in probes.csv
/// (io/output/probes.hpp), at a point of a body's reference configuration (interpolated by the
/// shape functions of the cell holding it) or, when `where` names a boundary, averaged over its
/// nodes.
struct Probe {
  std::string name;
  int body = 0;
  std::array<double, 3> point{0.0, 0.0, 0.0};
  std::string where;                               // a boundary of the body, or "" (point)
  std::vector<std::string> fields{"temperature"};  // of io::probe_fields()
};

struct OutputSettings {
  std::filesystem::path directory = "out";
  int every = 1;
  /// How the .vtu files hold their arrays (io::VtuEncoding): `format` "ascii" or "binary"
  /// (appended raw), `compression` "zlib" for compressed binary.
  enum class Encoding { ascii, binary, zlib };
  Encoding encoding = Encoding::ascii;
  /// contact_<step>.csv with every contact node's state at each written step
  /// (io/output/contact_csv).
  bool contact_csv = false;
  std::vector<Probe> probes;
  /// The checkpoint's policy (io::CheckpointPolicy): after a step once this many steps have
  /// passed since the last one (0: never by count), or this many seconds of wall time (0:
  /// never by time); always at step 0, at a stop and at the end.
  int checkpoint_every = 0;
  double checkpoint_seconds = 10.0;
};

/// `[stability]`: the linear stability analysis of the case's steady sliding
/// (`thermocontact stability`, src/tc/stability; docs/theory.md, "Linear stability").
struct StabilitySettings {
  /// How the rigid tool's normal motion enters the perturbation: held where the case moves it,
  /// or free under its constant normal force (the mean pressure held).
  enum class NormalControl { displacement, force };
  std::vector<double> speeds;  // the tool's sliding speeds [m/s]; empty: the case's own
  int eigenvalues = 4;         // the leading eigenvalues reported per speed
  bool critical_speed = true;  // the speed at which the leading growth rate crosses 0
  bool modes = true;           // the leading mode of each speed as .vtu
  NormalControl normal_control = NormalControl::displacement;
  bool friction_shear = true;    // λ_τ = 𝔉 λ_n s in the mechanics (false: left out)
  std::optional<double> target;  // the shift σ [1/s]; none: κΛ² (stability/eigen.hpp)
  int state_step = 1;            // the step of the case whose state is linearised
};

struct Problem;
/// Why the combined contact dual cannot run this problem ("" when it can): it needs one pair,
/// the quasistatic scheme and both contact bodies decomposed (subdomains > 1: their mechanics
/// solved by TFETI with the floating subdomains' rigid motions).
[[nodiscard]] std::string combined_contact_dual_unavailable(const Problem& p);

struct Problem {
  std::filesystem::path case_file;
  std::string title;
  int dimension = 3;
  TimeSettings time;
  PhysicsSettings physics;
  std::vector<Body> bodies;
  std::vector<BoundaryCondition> boundaries;
  std::vector<ContactSettings> contacts;  // the contact pairs, in the order of the case file
  SolverSettings solver;
  OutputSettings output;
  std::optional<StabilitySettings> stability;  // [stability]; none: not given
  /// The command line's `--set KEY=VALUE`, as given (applied before validation).
  std::vector<std::string> overrides;
  /// What a restart must find unchanged: every key and value of the case (after the
  /// overrides) but those a restart may change, one `key = value` line each (io::read_case).
  std::string content;
  /// Values that are valid but implausible in SI (a modulus in MPa, a temperature in °C):
  /// `FILE:LINE: KEY: …` each, printed by `check` and `run`.
  std::vector<std::string> warnings;
};

}  // namespace tc::physics
