#include "tc/io/output.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "tc/core/collective.hpp"
#include "tc/core/error.hpp"
#include "tc/core/petsc.hpp"
#include "tc/fem/element.hpp"
#include "tc/io/files.hpp"

namespace tc::io {

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";  // JSON has no NaN/Inf
  return fmt::format("{:.17g}", v);
}

constexpr std::array<const char*, 7> kPhases{
    "assembly", "mortar", "dual_setup", "factorization", "heat_solve", "qp", "mechanical_solve"};

}  // namespace

std::string peak_memory_json(const core::PhaseTimers& t) {
  constexpr double gib = 1024.0 * 1024.0 * 1024.0;
  std::vector<double> largest{core::peak_resident_bytes()};
  for (const char* ph : kPhases) largest.push_back(t.peak_growth(ph));
  double smallest = largest.front();
  const bool root = core::PetscSession::rank() == 0;
  core::check_mpi(
      MPI_Reduce(root ? MPI_IN_PLACE : largest.data(), largest.data(),
                 static_cast<int>(largest.size()), MPI_DOUBLE, MPI_MAX, 0, PETSC_COMM_WORLD),
      "MPI_Reduce");
  core::check_mpi(MPI_Reduce(root ? MPI_IN_PLACE : &smallest, &smallest, 1, MPI_DOUBLE, MPI_MIN, 0,
                             PETSC_COMM_WORLD),
                  "MPI_Reduce");
  std::string phases;
  for (size_t i = 0; i < kPhases.size(); ++i)
    phases +=
        fmt::format("{}{}: {:.3f}", i ? ", " : "", json_string(kPhases[i]), largest[i + 1] / gib);
  return fmt::format(R"({{"largest_rank": {:.3f}, "smallest_rank": {:.3f}, "phases": {{{}}}}})",
                     largest.front() / gib, smallest / gib, phases);
}

namespace {

Field vector_field(const std::string& name, const core::Vector& v, int dim) {
  const auto values = v.to_std();
  const size_t n = values.size() / dim;
  Field f{name, 3, std::vector<double>(3 * n, 0.0)};
  for (size_t a = 0; a < n; ++a)
    for (int k = 0; k < dim; ++k) f.values[3 * a + k] = values[dim * a + k];
  return f;
}

/// A NumericalError naming the first value of the step's history row that is not finite:
/// derived quantities (energies, work, forces) overflow where the state they come from is
/// still finite (a 1e300 traction, a 1e308 heat source), so the state's checks in the physics
/// do not see them. Same message shape as physics' require_finite, with the time.
void require_finite_row(const physics::Simulation& sim) {
  const auto& columns = sim.history_columns();
  const auto& row = sim.history_row();
  for (size_t i = 0; i < row.size() && i < columns.size(); ++i) {
    if (std::isfinite(row[i])) continue;
    const char* value = std::isnan(row[i]) ? "NaN" : row[i] > 0 ? "+Inf" : "-Inf";
    throw NumericalError::preformatted(
        fmt::format("history: {} is not finite ({}) (step {}, t = {:g} s)", columns[i], value,
                    sim.step(), sim.time()),
        sim.step(), 0, row[i]);
  }
}

}  // namespace

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<int>(c));
        else
          out += c;
    }
  }
  return out + "\"";
}

void body_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data,
                 std::vector<Field>& cell_data) {
  const auto& sys = sim.system(body);
  const auto& st = sim.state(body);
  const auto& m = sys.body().mesh;
  const auto& mat = sys.body().material;
  const int dim = sys.dim();
  const double theta0 = sim.problem().physics.reference_temperature;
  point_data = {vector_field("displacement", st.u, dim), vector_field("velocity", st.v, dim),
                Field{"temperature", 1, st.theta.to_std()}};

  const auto u = st.u.to_std();
  const auto& theta = point_data.back().values;
  const double beta = sim.problem().physics.thermal_expansion ? mat.thermal_stress_modulus() : 0.0;
  Field vm{"von_mises_stress", 1, {}}, flux{"heat_flux", 3, {}}, sub{"subdomain", 1, {}};
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto nodes = m.cell(c);
    const auto x = fem::cell_coords(m, c);
    Eigen::VectorXd ue(dim * nodes.size()), te(nodes.size()), dte(nodes.size());
    for (size_t a = 0; a < nodes.size(); ++a) {
      for (int k = 0; k < dim; ++k) ue[dim * a + k] = u[dim * nodes[a] + k];
      te[a] = theta[nodes[a]];
      dte[a] = te[a] - theta0;
    }
    const auto type = m.cell_type(c);
    vm.values.push_back(
        fem::von_mises(fem::cell_stress(type, x, ue, dte, mat.lame_lambda(), mat.lame_mu(), beta)));
    const auto q = fem::cell_heat_flux(type, x, te, mat.thermal_conductivity);
    flux.values.insert(flux.values.end(), {q[0], q[1], q[2]});
    sub.values.push_back(sys.cell_subdomain()[static_cast<size_t>(c)]);
  }
  cell_data = {std::move(vm), std::move(flux), std::move(sub)};
  contact_fields(sim, body, point_data);
}

void contact_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data) {
  // On the contact nodes of every pair whose slave is this body (the multipliers live there),
  // zero elsewhere: the pressure and the tangential traction Σ_l λ_τl τ_l (λ times the traction
  // per multiplier: ½ with the contact-stabilised Newmark), the slip velocity
  // Σ_l (B_τlΔu)_k/(w_k τ) τ_l and the conducted heat flux β_C λ_n [θ] out of the slave.
  const auto& contact = sim.contact();
  const auto* dual = sim.dual_solver();
  bool slave = false;
  for (int q = 0; q < contact.n_pairs(); ++q)
    slave = slave || (contact.pair(q).mortar && contact.pair(q).settings->slave_body == body);
  if (!dual || !slave) return;
  const int n = sim.system(body).body().mesh.n_nodes();
  Field pressure{"contact_pressure", 1, std::vector<double>(n, 0.0)};
  Field traction{"tangential_traction", 3, std::vector<double>(3 * n, 0.0)};
  Field slip_velocity{"slip_velocity", 3, std::vector<double>(3 * n, 0.0)};
  Field heat_flux{"contact_heat_flux", 1, std::vector<double>(n, 0.0)};
  const double tau = sim.problem().time.step;
  const double unit = sim.traction_per_multiplier();
  for (int q = 0; q < contact.n_pairs() && q < dual->n_pairs(); ++q) {
    const auto& pr = contact.pair(q);
    const auto* pair = pr.mortar.get();
    if (!pair || pr.settings->slave_body != body) continue;
    const auto& rows = dual->pair_rows(q);
    const int dim = rows.dim;
    const auto lambda = contact.multipliers(q);
    const auto slip = contact.slip(q);
    const auto& flux = pr.heat_flux;
    const bool have_slip = slip.size() == lambda.size() && !lambda.empty();
    if (static_cast<PetscInt>(lambda.size()) != rows.n_rows() ||
        rows.nodes.size() != pair->contact_nodes().size())
      continue;
    for (size_t k = 0; k < rows.nodes.size(); ++k) {
      const int a = rows.nodes[k];
      pressure.values[a] += unit * lambda[dim * k];
      if (flux.size() == rows.nodes.size()) heat_flux.values[a] += flux[k];
      for (int l = 0; l + 1 < dim; ++l) {
        const auto& t = pair->tangents(l)[k];
        const double lt = unit * lambda[dim * k + 1 + l];
        const double w = rows.weights[k];
        const double v = have_slip && w > 0 ? slip[dim * k + 1 + l] / (w * tau) : 0.0;
        for (int i = 0; i < 3; ++i) {
          traction.values[3 * a + i] += lt * t[i];
          slip_velocity.values[3 * a + i] += v * t[i];
        }
      }
    }
  }
  point_data.push_back(std::move(pressure));
  point_data.push_back(std::move(traction));
  point_data.push_back(std::move(slip_velocity));
  point_data.push_back(std::move(heat_flux));
}

OutputWriter::OutputWriter(std::filesystem::path directory, int every)
    : dir_(std::move(directory)), every_(every), root_(core::PetscSession::rank() == 0) {}

OutputWriter::~OutputWriter() {
  if (history_fd_ >= 0) ::close(history_fd_);
}

void OutputWriter::start(const physics::Simulation& sim) {
  // Rank 0 alone writes here; the check makes a failure stop every rank (and orders the
  // directory's creation before any rank writes its piece).
  peak_memory_ = peak_memory_json(sim.timers());
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    if (!root_) return;
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec)
      throw Error(
          fmt::format("cannot create output directory {}: {}", dir_.string(), ec.message()));
    pvd_ = std::make_unique<PvdCollection>(dir_ / "result.pvd");
    if (resume_) {
      resumed_step_ = sim.step();
      // Data sets up to the restored step stay (half a step of slack for the printed times).
      pvd_->load(sim.time() + 0.5 * sim.problem().time.step);
    }
    open_history(sim);
    steps_written_ = sim.step();
    write_summary(sim, "running", "");
  });
  if (resume_) resumed_step_ = sim.step();
}

void OutputWriter::open_history(const physics::Simulation& sim) {
  const auto file = dir_ / "history.csv";
  std::string header;
  for (const auto& c : sim.history_columns()) header += (header.empty() ? "" : ",") + c;
  header += '\n';
  std::string kept = header;
  if (resume_) {  // the header must match; rows of steps before the restored one stay
    std::ifstream in(file);
    std::string line;
    if (!std::getline(in, line) || line + '\n' != header)
      throw Error(fmt::format("cannot continue {}: its header is not this case's", file.string()));
    while (std::getline(in, line) && !in.eof()) {  // a last line without '\n' is dropped
      char* end = nullptr;
      const double step = std::strtod(line.c_str(), &end);
      if (end == line.c_str() || step >= resumed_step_) break;
      kept += line + '\n';
    }
  }
  replace_file(file, kept);
  history_fd_ = ::open(file.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (history_fd_ < 0)
    throw OutputError(fmt::format("cannot open {}: {}", file.string(), std::strerror(errno)));
}

void OutputWriter::append_history(const std::string& line) {
  // One write() per row: a kill between two rows leaves whole rows only (a regular file's
  // write is not split by a signal once it has started); a row cut short by a full disk is
  // cut off again.
  append_record(history_fd_, dir_ / "history.csv", line);
}

void OutputWriter::step(const physics::Simulation& sim) {
  const double t0 = now_seconds();
  peak_memory_ = peak_memory_json(sim.timers());
  try {
    core::collective_check(PETSC_COMM_WORLD, "output", [&] {
      require_finite_row(sim);  // before the row is written: history.csv holds numbers only
      if (!root_) return;
      std::string line;
      for (const double v : sim.history_row())
        line += fmt::format("{}{:.17g}", line.empty() ? "" : ",", v);
      append_history(line + '\n');  // a run killed later still leaves every completed row
      steps_written_ = sim.step();
      write_summary(sim, "stopped",
                    fmt::format("ended at once by a second stop signal after step {} (t = {:g} "
                                "s); the output of the steps done is whole",
                                sim.step(), sim.time()),
                    stopped_summary(dir_).filename().string());
    });
    // The restored step's fields are those the first run wrote (its contact rows are gone).
    if (sim.step() % every_ == 0 && sim.step() != resumed_step_) write_fields(sim);
  } catch (const Error&) {  // a failed write, or a row refused as not finite
    failed_ = true;         // finish() writes no more fields, only the summary if it can
    throw;
  }
  output_seconds_ += now_seconds() - t0;
}

void OutputWriter::write_fields(const physics::Simulation& sim) {
  const int size = core::PetscSession::size(), rank = core::PetscSession::rank();
  for (int b = 0; b < sim.n_bodies(); ++b) {
    const auto& sys = sim.system(b);
    const auto& mesh = sys.body().mesh;
    std::vector<Field> point_data, cell_data;
    const auto stem = fmt::format("{}_{:06d}", sys.body().name, sim.step());
    if (size == 1) {
      core::collective_check(PETSC_COMM_WORLD, "output", [&] {
        body_fields(sim, b, point_data, cell_data);
        write_vtu(dir_ / (stem + ".vtu"), mesh, point_data, cell_data);
        pvd_->add(sim.time(), b, stem + ".vtu");
      });
      continue;
    }
    // More ranks: each writes the cells of the subdomains it owns in FETI (the same dealing,
    // feti::first_subdomain; an undecomposed body is one subdomain) as <stem>_<rank>.vtu, and
    // rank 0 lists the pieces in <stem>.pvtu once all are written. The state is replicated,
    // so every rank has the fields of its cells and points.
    const int n_sub = std::max(1, static_cast<int>(sys.subdomains().size()));
    std::vector<int> piece_of(static_cast<size_t>(n_sub));  // subdomain → rank
    for (int r = 0; r < size; ++r)
      for (int s = feti::first_subdomain(n_sub, r, size);
           s < feti::first_subdomain(n_sub, r + 1, size); ++s)
        piece_of[static_cast<size_t>(s)] = r;
    std::vector<std::vector<int>> cells(static_cast<size_t>(size));
    const auto& part = sys.cell_subdomain();
    for (int c = 0; c < mesh.n_cells(); ++c)
      cells[static_cast<size_t>(piece_of[static_cast<size_t>(part[static_cast<size_t>(c)])])]
          .push_back(c);
    const auto piece = [&](int r) { return fmt::format("{}_{}.vtu", stem, r); };
    core::collective_check(PETSC_COMM_WORLD, "output", [&] {
      if (core::injected_failure("output"))
        throw OutputError(
            fmt::format("cannot write {} (injected by -tc_fail_on_rank)", piece(rank)));
      body_fields(sim, b, point_data, cell_data);
      if (!cells[static_cast<size_t>(rank)].empty())  // a rank without cells writes no piece
        write_vtu_piece(dir_ / piece(rank), mesh, cells[static_cast<size_t>(rank)], point_data,
                        cell_data);
    });
    core::collective_check(PETSC_COMM_WORLD, "output", [&] {
      if (!root_) return;
      std::vector<std::string> pieces;
      for (int r = 0; r < size; ++r)
        if (!cells[static_cast<size_t>(r)].empty()) pieces.push_back(piece(r));
      write_pvtu(dir_ / (stem + ".pvtu"), point_data, cell_data, pieces);
      pvd_->add(sim.time(), b, stem + ".pvtu");
    });
  }
}

void OutputWriter::finish(const physics::Simulation& sim, const physics::RunStatus& status) {
  // The last state is always written, even when `every` skipped it; not after a failed
  // write, which would only fail again (and the step may have no history row).
  if (!failed_ && sim.step() % every_ != 0 && sim.step() != resumed_step_) write_fields(sim);
  peak_memory_ = peak_memory_json(sim.timers());
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    if (!root_) return;
    write_summary(sim, status.completed ? "completed" : "stopped", status.message);
    std::error_code ec;
    std::filesystem::remove(stopped_summary(dir_), ec);  // the run ended in order
  });
}

void OutputWriter::write_summary(const physics::Simulation& sim, const std::string& status,
                                 const std::string& message, const std::string& file_name) const {
  const auto& p = sim.problem();
  const auto& t = sim.timers();
  std::string phases;
  for (const char* ph : kPhases)
    phases += fmt::format("    {}: {},\n", json_string(ph), json_number(t[ph]));
  phases += fmt::format("    \"output\": {}\n", json_number(output_seconds_));
  std::string last;
  const auto& cols = sim.history_columns();
  const auto& row = sim.history_row();
  for (size_t i = 0; i < cols.size(); ++i)
    last += fmt::format("    {}: {}{}\n", json_string(cols[i]), json_number(row[i]),
                        i + 1 < cols.size() ? "," : "");
  int subdomains = 0;
  for (const auto& b : p.bodies) subdomains += b.subdomains;
  TextBuffer out;
  out.print("{{\n");
  out.print("  \"status\": {},\n", json_string(status));
  out.print("  \"steps_done\": {},\n", steps_written_);
  out.print("  \"steps_total\": {},\n", p.time.n_steps());
  out.print("  \"message\": {},\n", json_string(message));
  out.print("  \"title\": {},\n", json_string(p.title));
  out.print("  \"case\": {},\n", json_string(p.case_file.string()));
  std::string overrides;  // --set KEY=VALUE of the command line, in order
  for (const auto& o : p.overrides) overrides += (overrides.empty() ? "" : ", ") + json_string(o);
  out.print("  \"overrides\": [{}],\n", overrides);
  out.print("  \"wall_seconds\": {{\n{}  }},\n", phases);
  out.print("  \"peak_memory_gib\": {},\n", peak_memory_);
  out.print("  \"coupling_iterations\": {},\n", sim.total_coupling_iterations());
  out.print("  \"qp_iterations\": {},\n", sim.total_qp_iterations());
  out.print("  \"operator_applications\": {},\n", sim.total_operator_applications());
  out.print("  \"dofs\": {},\n", sim.n_dofs());
  const auto* dual = sim.dual_solver();
  out.print("  \"multipliers\": {},\n", dual ? dual->n_rows() : 0);
  out.print("  \"ranks\": {},\n", core::PetscSession::size());
  out.print("  \"blas_threads\": {},\n", core::PetscSession::blas_threads());
  out.print("  \"subdomains\": {},\n", subdomains);
  const auto feti = sim.feti_statistics();
  out.print(
      "  \"feti\": {{\"solves\": {}, \"right_hand_sides\": {}, \"iterations\": {}, "
      "\"preconditioner\": {}}},\n",
      feti.solves, feti.right_hand_sides, feti.iterations,
      json_string(subdomains > static_cast<int>(p.bodies.size())
                      ? feti::name(p.solver.feti_preconditioner)
                      : "none"));
  out.print("  \"factorization\": {},\n", json_string(sim.factorization()));
  out.print("  \"dual_operator\": {},\n",
            json_string(dual && dual->n_rows() > 0 ? physics::name(dual->kind()) : "none"));
  const auto* enforcement = sim.contact_enforcement();
  out.print("  \"contact_dual\": {},\n", json_string(enforcement ? enforcement->name() : "none"));
  out.print("  \"smalbe_outer_iterations\": {},\n", sim.total_smalbe_outer_iterations());
  out.print("  \"last\": {{\n{}  }}\n", last);
  out.print("}}\n");
  replace_file(dir_ / file_name, out.view());
}

ProgressLine::ProgressLine(bool terminal)
    : terminal_(terminal), root_(core::PetscSession::rank() == 0), start_(now_seconds()) {}

void ProgressLine::step(const physics::Simulation& sim) {
  if (!root_) return;
  const int n = sim.problem().time.n_steps();
  const int k = sim.step();
  if (k == 0) {
    start_ = now_seconds();
    return;
  }
  const double elapsed = now_seconds() - start_;
  const double eta = elapsed / k * (n - k);
  const auto text =
      fmt::format("step {}/{}  t = {:.4g} s  coupling {}  qp {}  elapsed {:.1f} s  ETA {:.1f} s", k,
                  n, sim.time(), static_cast<int>(sim.history("coupling_iterations")),
                  static_cast<int>(sim.history("qp_iterations")), elapsed, eta);
  if (terminal_) {
    fmt::print(stderr, "\r{:<100}", text);
    std::fflush(stderr);
  } else if (k == n || k % std::max(1, n / 20) == 0) {
    fmt::print("{}\n", text);
    std::fflush(stdout);
  }
}

void ProgressLine::finish(const physics::Simulation&, const physics::RunStatus&) {
  if (root_ && terminal_) fmt::print(stderr, "\n");
}

}  // namespace tc::io
