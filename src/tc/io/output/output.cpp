#include "tc/io/output/output.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "tc/core/error.hpp"
#include "tc/core/numeric/collective.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/io/files/files.hpp"
#include "tc/io/vtk/vtkhdf.hpp"

namespace tc::io {

namespace {

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";  // JSON has no NaN/Inf
  return fmt::format("{:.17g}", v);
}

/// summary.stopped.json's reason: it becomes summary.json when the run ends before writing its
/// own, which a second stop signal, a kill after the first (mpirun after SIGTERM) and a disk
/// too full for summary.json all do. It said "a second stop signal" of all of them (issue 42,
/// D12).
std::string stopped_message(const physics::Simulation& sim) {
  return fmt::format(
      "stopped after step {} (t = {:g} s) without its final summary: ended at once by a second "
      "stop signal or killed after a first one, or summary.json could not be written (see the "
      "run's error output); the output of the steps done is whole",
      sim.step(), sim.time());
}

constexpr std::array<const char*, 7> kPhases{
    "assembly", "mortar", "dual_setup", "factorization", "heat_solve", "qp", "mechanical_solve"};

}  // namespace

std::string blas_threads_json() {
  using core::ThreadPolicy;
  const auto& cpus = ThreadPolicy::cpus();
  return fmt::format(
      R"({{"policy": {}, "outside_kernels": {}, "budget": {}, "cpus": {}, "cgroup_quota": {}, )"
      R"("ranks_on_node": {}, "kernels": {}, "threaded_kernels": {}, "most": {}}})",
      json_string(ThreadPolicy::name()), ThreadPolicy::outside_kernels(), ThreadPolicy::budget(),
      cpus.affinity, json_number(cpus.quota), cpus.ranks_on_node, ThreadPolicy::kernels(),
      ThreadPolicy::threaded_kernels(), ThreadPolicy::most_threads());
}

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

OutputWriter::OutputWriter(std::filesystem::path directory, int every, VtuEncoding encoding,
                           FieldFiles files)
    : dir_(std::move(directory)),
      every_(every),
      encoding_(encoding),
      files_(files),
      root_(core::PetscSession::rank() == 0) {}

VtuEncoding OutputWriter::encoding_of(const physics::OutputSettings& output) {
  using E = physics::OutputSettings::Encoding;
  switch (output.encoding) {
    case E::binary:
      return VtuEncoding::binary;
    case E::zlib:
      return VtuEncoding::zlib;
    case E::ascii:
      break;
  }
  return VtuEncoding::ascii;
}

OutputWriter::~OutputWriter() {
  if (history_fd_ >= 0) ::close(history_fd_);
  if (probes_fd_ >= 0) ::close(probes_fd_);
  if (stopped_fd_ >= 0) ::close(stopped_fd_);
}

void OutputWriter::start(const physics::Simulation& sim) {
  auto history = phases_.scope("history");  // the directory, history.csv's header, summary.json
  // Rank 0 alone writes here; the check makes a failure stop every rank (and orders the
  // directory's creation before any rank writes its piece).
  peak_memory_ = peak_memory_json(sim.timers());
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    if (!root_) return;
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec)
      throw Error(
          fmt::format("cannot create output directory {}: {}", printable(dir_), ec.message()));
  });
  // Every rank writes through the directory it opens now (a rank's pieces too).
  core::collective_check(PETSC_COMM_WORLD, "output",
                         [&] { pin_ = std::make_unique<PinnedDirectory>(dir_); });
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    if (!root_) return;
    pvd_ = std::make_unique<PvdCollection>(dir_ / "result.pvd");
    if (resume_) {
      resumed_step_ = sim.step();
      resume_collection(sim);
    }
    open_history(sim);
    struct stat dir {};
    struct stat history {};
    if (::fstat(pin_->fd(), &dir) != 0 || ::fstat(history_fd_, &history) != 0)
      throw OutputError(fmt::format("cannot examine output directory {}: {}", printable(dir_),
                                    std::strerror(errno)));
    directory_id_ = {dir.st_dev, dir.st_ino};
    history_id_ = {history.st_dev, history.st_ino};
    steps_written_ = sim.step();
    write_summary(sim, "running", "");
  });
  if (resume_) resumed_step_ = sim.step();
}

void OutputWriter::open_history(const physics::Simulation& sim) {
  history_fd_ = open_csv("history.csv", sim.history_columns());
  if (!sim.problem().output.probes.empty()) {
    stencils_ = probe_stencils(sim.problem());
    probes_fd_ = open_csv("probes.csv", probe_columns(sim.problem()));
  }
}

int OutputWriter::open_csv(const std::string& name, const std::vector<std::string>& columns) {
  const auto file = dir_ / name;
  std::string header;
  for (const auto& c : columns) header += (header.empty() ? "" : ",") + c;
  header += '\n';
  std::string kept = header;
  if (resume_) {  // the header must match; rows of steps before the restored one stay
    std::ifstream in(file);
    std::string line;
    if (!in)  // history.csv is checked before (check_restart_outputs); probes.csv is not
      throw Error(
          fmt::format("cannot continue {}: it is missing or cannot be read", printable(file)));
    if (!std::getline(in, line) || line + '\n' != header)  // checked before: a race
      throw Error(
          fmt::format("cannot continue {}: its header is not this case's", printable(file)));
    while (std::getline(in, line) && !in.eof()) {  // a last line without '\n' is dropped
      char* end = nullptr;
      const double step = std::strtod(line.c_str(), &end);
      if (end == line.c_str() || step >= resumed_step_) break;
      kept += line + '\n';
    }
  }
  // Kept open as written: the rows go to this file whatever its name points to later.
  return replace_file_for_append(file, kept);
}

void OutputWriter::resume_collection(const physics::Simulation& sim) {
  // Data sets up to the restored step stay (half a step of slack for the printed times).
  const double tau = sim.problem().time.step;
  if (pvd_->load(sim.time() + 0.5 * tau)) return;
  // Missing or not whole (issue 42, D3: it was replaced by one listing only the steps after
  // the checkpoint). The files are there: <body>_<step>.vtu (or .pvtu under MPI), written
  // whole before they were listed; one cut short by a kill is left out.
  const auto whole = [](const std::filesystem::path& f) {
    struct stat st {};
    if (::lstat(f.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
    std::ifstream in(f, std::ios::binary);
    if (f.extension() == ".vtkhdf") {  // renamed to its name once whole: HDF5's signature
      const std::string signature = "\x89HDF\r\n\x1a\n";
      std::string head(signature.size(), '\0');
      return in.read(head.data(), static_cast<std::streamsize>(head.size())) && head == signature;
    }
    const std::string tail = "</VTKFile>\n";
    if (st.st_size < static_cast<off_t>(tail.size())) return false;
    in.seekg(st.st_size - static_cast<off_t>(tail.size()));
    std::string end(tail.size(), '\0');
    return in.read(end.data(), static_cast<std::streamsize>(end.size())) && end == tail;
  };
  for (int k = 0; k <= sim.step(); ++k)
    for (int b = 0; b < sim.n_bodies(); ++b)
      for (const char* ext : {".vtu", ".pvtu", ".vtkhdf"}) {
        const auto name = fmt::format("{}_{:06d}{}", sim.system(b).body().name, k, ext);
        if (!whole(dir_ / name)) continue;
        pvd_->add_existing(k * tau, b, name);
        break;
      }
  pvd_->write_all();
  fmt::print(stderr,
             "warning: {} was missing or damaged: rebuilt from the {} data set(s) of steps 0 to "
             "{} found in {}\n",
             printable(dir_ / "result.pvd"), pvd_->size(), sim.step(), printable(dir_));
}

void OutputWriter::require_in_place() {
  const auto same = [](const char* path, const Identity& id) {
    struct stat st {};
    return ::stat(path, &st) == 0 && st.st_dev == id.device && st.st_ino == id.inode;
  };
  if (same(dir_.c_str(), directory_id_) && same((dir_ / "history.csv").c_str(), history_id_))
    return;
  throw OutputError(fmt::format(
      "output directory {} or its history.csv was deleted or replaced during the run (by "
      "`rm`, or another run after it): the rows written since are in no file there, so this "
      "run cannot end as done",
      printable(dir_)));
}

void OutputWriter::append_history(const std::string& line) {
  // One write() per row: a kill between two rows leaves whole rows only (a regular file's
  // write is not split by a signal once it has started); a row cut short by a full disk is
  // cut off again.
  append_record(history_fd_, dir_ / "history.csv", line);
}

void OutputWriter::step(const physics::Simulation& sim) {
  auto history = phases_.scope("history");  // the row, summary.stopped.json, the peak memory
  peak_memory_ = peak_memory_json(sim.timers());
  try {
    core::collective_check(PETSC_COMM_WORLD, "output", [&] {
      require_finite_row(sim);  // before the row is written: history.csv holds numbers only
      if (!root_) return;
      require_in_place();  // before the row, which would go to a file no longer in dir_
      std::string line;
      for (const double v : sim.history_row())
        line += fmt::format("{}{:.17g}", line.empty() ? "" : ",", v);
      append_history(line + '\n');  // a run killed later still leaves every completed row
      if (probes_fd_ >= 0) {        // after the history row: a restart cuts both at its step
        std::string probes;
        for (const double v : probe_row(sim, stencils_))
          probes += fmt::format("{}{:.17g}", probes.empty() ? "" : ",", v);
        append_record(probes_fd_, dir_ / "probes.csv", probes + '\n');
      }
      steps_written_ = sim.step();
      write_stopped_summary(sim, stopped_message(sim));
      if (stop_ && stop_->load() != 0)  // a kill may follow before finish(): see watch_stop
        (void)::renameat(pin_->fd(), "summary.stopped.json", pin_->fd(), "summary.json");
    });
    // The restored step's fields are those the first run wrote (its contact rows are gone).
    if (sim.step() % every_ == 0 && sim.step() != resumed_step_) write_fields(sim);
  } catch (const Error&) {  // a failed write, or a row refused as not finite
    failed_ = true;         // finish() writes no more fields, only the summary if it can
    throw;
  }
}

namespace {

/// The cells of body `sys` that each of `size` ranks writes: those of the subdomains it owns
/// in FETI (the same dealing, feti::first_subdomain; an undecomposed body is one subdomain,
/// all on one rank). The state is replicated, so every rank has the fields of its cells.
std::vector<std::vector<int>> cells_by_rank(const physics::BodySystem& sys, int size) {
  const int n_sub = std::max(1, static_cast<int>(sys.subdomains().size()));
  std::vector<int> piece_of(static_cast<size_t>(n_sub));  // subdomain → rank
  for (int r = 0; r < size; ++r)
    for (int s = feti::first_subdomain(n_sub, r, size);
         s < feti::first_subdomain(n_sub, r + 1, size); ++s)
      piece_of[static_cast<size_t>(s)] = r;
  std::vector<std::vector<int>> cells(static_cast<size_t>(size));
  const auto& part = sys.cell_subdomain();
  for (int c = 0; c < sys.body().mesh.n_cells(); ++c)
    cells[static_cast<size_t>(piece_of[static_cast<size_t>(part[static_cast<size_t>(c)])])]
        .push_back(c);
  return cells;
}

}  // namespace

void OutputWriter::write_vtkhdf_fields(const physics::Simulation& sim, int b,
                                       const std::string& stem) {
  const int size = core::PetscSession::size(), rank = core::PetscSession::rank();
  const auto& sys = sim.system(b);
  const auto name = stem + ".vtkhdf";
  std::vector<Field> point_data, cell_data;
  std::vector<int> mine;
  // The fields first, each rank alone: a failure here is every rank's before any of them
  // enters HDF5's collective calls (which a rank left out would wait in for ever).
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    if (core::injected_failure("output"))
      throw OutputError(
          fmt::format("cannot write {} (injected by -tc_fail_on_rank)", printable(dir_ / name)));
    body_fields(sim, b, point_data, cell_data);
    mine = std::move(cells_by_rank(sys, size)[static_cast<size_t>(rank)]);
  });
  // write_vtkhdf makes a failure on one rank every rank's itself.
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    write_vtkhdf(dir_ / name, sys.body().mesh, mine, point_data, cell_data, PETSC_COMM_WORLD);
  });
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    if (root_) pvd_->add(sim.time(), b, name);
  });
}

void OutputWriter::write_fields(const physics::Simulation& sim) {
  auto scope = phases_.scope("output");
  const int size = core::PetscSession::size(), rank = core::PetscSession::rank();
  if (sim.problem().output.contact_csv && sim.contact().n_pairs() > 0)
    core::collective_check(PETSC_COMM_WORLD, "output", [&] {
      if (root_)  // before the fields: a .vtu listed in result.pvd has its CSV beside it
        write_file(dir_ / fmt::format("contact_{:06d}.csv", sim.step()), contact_csv(sim));
    });
  for (int b = 0; b < sim.n_bodies(); ++b) {
    const auto& sys = sim.system(b);
    const auto& mesh = sys.body().mesh;
    std::vector<Field> point_data, cell_data;
    const auto stem = fmt::format("{}_{:06d}", sys.body().name, sim.step());
    if (files_ == FieldFiles::vtkhdf) {
      write_vtkhdf_fields(sim, b, stem);
      continue;
    }
    if (size == 1) {
      core::collective_check(PETSC_COMM_WORLD, "output", [&] {
        body_fields(sim, b, point_data, cell_data);
        write_vtu(dir_ / (stem + ".vtu"), mesh, point_data, cell_data, encoding_);
        pvd_->add(sim.time(), b, stem + ".vtu");
      });
      continue;
    }
    // More ranks: each writes the cells of the subdomains it owns as <stem>_<rank>.vtu, and
    // rank 0 lists the pieces in <stem>.pvtu once all are written.
    const auto cells = cells_by_rank(sys, size);
    const auto piece = [&](int r) { return fmt::format("{}_{}.vtu", stem, r); };
    core::collective_check(PETSC_COMM_WORLD, "output", [&] {
      if (core::injected_failure("output"))
        throw OutputError(
            fmt::format("cannot write {} (injected by -tc_fail_on_rank)", piece(rank)));
      body_fields(sim, b, point_data, cell_data);
      if (!cells[static_cast<size_t>(rank)].empty())  // a rank without cells writes no piece
        write_vtu_piece(dir_ / piece(rank), mesh, cells[static_cast<size_t>(rank)], point_data,
                        cell_data, encoding_);
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
  // Nothing more into a directory that is not this run's any more (it may be another run's).
  // Every rank throws when rank 0 finds it so (core::collective_check): main reports it, exit 1.
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    if (root_ && history_fd_ >= 0) require_in_place();
  });
  // The last state is always written, even when `every` skipped it; not after a failed
  // write, which would only fail again (and the step may have no history row).
  if (!failed_ && sim.step() % every_ != 0 && sim.step() != resumed_step_) write_fields(sim);
  peak_memory_ = peak_memory_json(sim.timers());
  core::collective_check(PETSC_COMM_WORLD, "output", [&] {
    if (!root_) return;
    const auto final_status = status.completed ? "completed" : "stopped";
    try {
      write_summary(sim, final_status, status.message);
    } catch (const OutputError& e) {
      fall_back_to_stopped_summary(sim, status.completed
                                            ? std::string(e.what())
                                            : fmt::format("{}; then {}", status.message, e.what()));
      throw;
    }
    if (stopped_fd_ >= 0) ::close(stopped_fd_);
    stopped_fd_ = -1;
    (void)::unlinkat(pin_->fd(), "summary.stopped.json", 0);  // the run ended in order
    // Checked after the last write too: a directory deleted during the last step or the
    // summary is not reported as a run done.
    if (history_fd_ >= 0) require_in_place();
  });
}

void OutputWriter::write_summary(const physics::Simulation& sim, const std::string& status,
                                 const std::string& message, const std::string& file_name) const {
  replace_file(dir_ / file_name, summary_text(sim, status, message));
}

void OutputWriter::fall_back_to_stopped_summary(const physics::Simulation& sim,
                                                const std::string& message) const {
  // The disk is full: no new file can be written, but summary.stopped.json is there (after the
  // last row). Its blocks are rewritten in place with the real reason when the text fits in
  // its size (padded with spaces, which JSON allows after the value: no block is added), then
  // it is renamed over summary.json, which a rename needs no room for. Otherwise it goes as it
  // is: status "stopped", the right steps_done, and a reason that names this case among others.
  auto text = summary_text(sim, "stopped", message);
  const int fd = ::openat(pin_->fd(), "summary.stopped.json", O_WRONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;  // not written yet (a failure before the first row): summary.json stays
  struct stat st {};
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
      text.size() <= static_cast<size_t>(st.st_size)) {
    text.append(static_cast<size_t>(st.st_size) - text.size(), ' ');
    size_t done = 0;
    while (done < text.size()) {
      const auto n = ::pwrite(fd, text.data() + done, text.size() - done, static_cast<off_t>(done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += static_cast<size_t>(n);
    }
    if (done != text.size()) {  // half rewritten: not a summary any more
      ::close(fd);
      return;
    }
  }
  ::close(fd);
  (void)::renameat(pin_->fd(), "summary.stopped.json", pin_->fd(), "summary.json");
}

void OutputWriter::write_stopped_summary(const physics::Simulation& sim,
                                         const std::string& message) {
  // Rewritten in place after every row, never renamed: a rename over an existing file costs
  // 5–6 ms on ext4 (it flushes the new file's data, auto_da_alloc), a step's fixed cost that
  // was most of a small run's "history" phase. The only reader is this process's signal
  // handler, which runs between system calls: it finds the file whole, the previous text or
  // this one (one pwrite; a shorter text is padded with spaces, which JSON allows, so nothing
  // of a longer one is left behind). Its rename of the file over summary.json keeps the open
  // descriptor on it, and the process then ends.
  auto text = summary_text(sim, "stopped", message);
  if (text.size() < stopped_length_) text.append(stopped_length_ - text.size(), ' ');
  stopped_length_ = text.size();
  const auto file = stopped_summary(dir_);
  if (stopped_fd_ < 0) {
    // Created anew through the directory's descriptor, never through a link planted under its
    // name (issue 42, D1), then kept open and rewritten in place.
    (void)::unlinkat(pin_->fd(), "summary.stopped.json", 0);
    stopped_fd_ = ::openat(pin_->fd(), "summary.stopped.json",
                           O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (stopped_fd_ < 0)
      throw OutputError(fmt::format("cannot open {}: {}", file.string(), std::strerror(errno)));
  }
  size_t done = 0;
  while (done < text.size()) {
    const auto n =
        ::pwrite(stopped_fd_, text.data() + done, text.size() - done, static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw OutputError(
          fmt::format("cannot write {}: {}", file.string(), std::strerror(n < 0 ? errno : EIO)));
    done += static_cast<size_t>(n);
  }
}

std::string OutputWriter::summary_text(const physics::Simulation& sim, const std::string& status,
                                       const std::string& message) const {
  const auto& p = sim.problem();
  const std::string phases = phases_json(sim.timers());
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
  out.print("  \"blas_threads\": {},\n", blas_threads_json());
  out.print("  \"subdomains\": {},\n", subdomains);
  // What subdomains = "auto" chose per body and the estimates it weighed (io::choose_subdomains).
  std::string chosen;
  for (const auto& b : p.bodies)
    chosen += fmt::format("{}{}: {{\"subdomains\": {}, \"auto\": {}}}", chosen.empty() ? "" : ", ",
                          json_string(b.name), b.subdomains, json_string(b.subdomains_reason));
  out.print("  \"subdomain_choice\": {{{}}},\n", chosen);
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
  out.print("  \"compliance\": {{{}}},\n", compliance_json(sim));
  out.print("  \"smalbe_outer_iterations\": {},\n", sim.total_smalbe_outer_iterations());
  // The contact laws checked after every step (physics/contact/contact_laws.hpp; case-format.md).
  const auto& laws = sim.contact().laws_checked();
  const auto law = [](const physics::LawViolation& v) {
    return fmt::format(
        "{{\"value\": {}, \"bound\": {}, \"ratio\": {}, \"step\": {}, \"node\": {}}}",
        json_number(v.value), json_number(v.bound), json_number(v.ratio), v.step, v.node);
  };
  out.print("  \"contact_laws\": {{\"penetration\": {}, \"cone\": {}}},\n", law(laws.gap),
            law(laws.cone));
  out.print("  \"cut_back_steps\": {},\n", sim.cut_back_steps());
  out.print("  \"mechanical_refactorisations\": {},\n", sim.mechanical_refactorisations());
  out.print("  \"smallest_step\": {},\n", json_number(sim.smallest_step()));
  out.print("  \"last\": {{\n{}  }}\n", last);
  out.print("}}\n");
  return std::string(out.view());
}

std::string OutputWriter::phases_json(const core::PhaseTimers& t) const {
  // Every phase of the run, each second once (the timers are exclusive): the start-up before
  // the case is read, reading it, the set-up and the solver phases of the simulation, what a
  // step does besides, and the output's own; what none of them holds is `unaccounted`.
  const double total = core::seconds_since_process_start();
  std::string out;
  double sum = 0;
  const auto add = [&](const char* name, double seconds) {
    out += fmt::format("    {}: {},\n", json_string(name), json_number(seconds));
    sum += seconds;
  };
  for (const char* ph : {"startup", "reading"}) add(ph, phases_[ph]);
  add("setup", t["setup"]);
  for (const char* ph : kPhases) add(ph, t[ph]);
  add("step_other", t["step_other"]);
  for (const char* ph : {"history", "output", "checkpoint", "progress"}) add(ph, phases_[ph]);
  out += fmt::format("    \"unaccounted\": {},\n", json_number(total - sum));
  out += fmt::format("    \"total\": {}\n", json_number(total));
  return out;
}

}  // namespace tc::io
