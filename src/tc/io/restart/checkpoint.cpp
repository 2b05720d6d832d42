#include "tc/io/restart/checkpoint.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "tc/core/bytes.hpp"
#include "tc/core/numeric/collective.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/io/case/case_overrides.hpp"
#include "tc/io/files/files.hpp"

namespace tc::io {

namespace {

constexpr char magic[8] = {'T', 'C', 'C', 'H', 'K', 'P', 'T', '\0'};

std::uint64_t fnv1a(const char* data, size_t n) {
  std::uint64_t h = 1469598103934665603ULL;
  for (size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= 1099511628211ULL;
  }
  return h;
}

class Encoder : public core::ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    core::ByteWriter::put(v);
  }
  template <class T>
  void put(const std::vector<T>& v) {
    put_vector(v);
  }
  std::string finish() {
    put(fnv1a(str().data(), str().size()));
    return std::move(str());
  }
};

/// Reads what Encoder wrote, refusing to run past the end (a damaged file is an error, not a
/// crash).
class Decoder : public core::ByteReader {
 public:
  Decoder(const std::string& bytes, std::string where)
      : core::ByteReader(bytes,
                         [where](const std::string& what) {
                           throw CheckpointError(fmt::format("checkpoint {}: {}", where, what));
                         }),
        where_(std::move(where)) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw CheckpointError(fmt::format("checkpoint {}: {}", where_, what));
  }

 private:
  std::string where_;
};

}  // namespace

std::filesystem::path checkpoint_file(const std::filesystem::path& directory) {
  return directory / "checkpoint.bin";
}

std::uint64_t file_hash(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return 0;
  std::stringstream s;
  s << in.rdbuf();
  const auto text = s.str();
  return fnv1a(text.data(), text.size());
}

std::uint64_t input_hash(const physics::Problem& problem) {
  // The case by its content (io::read_case): a comment, the layout or a key a restart may change
  // (time.end, [output]) leave it; a Problem made in code has none, its file's bytes stand in.
  std::vector<std::uint64_t> hashes{problem.content.empty()
                                        ? file_hash(problem.case_file)
                                        : fnv1a(problem.content.data(), problem.content.size())};
  for (const auto& b : problem.bodies)
    if (!b.mesh_file.empty()) hashes.push_back(file_hash(b.mesh_file));
  return hashes.size() == 1 ? hashes[0]
                            : fnv1a(reinterpret_cast<const char*>(hashes.data()),
                                    hashes.size() * sizeof(std::uint64_t));
}

std::string encode_checkpoint(const physics::Simulation& sim, std::uint64_t case_hash) {
  const auto c = sim.checkpoint();
  Encoder e;
  for (const char ch : magic) e.put(ch);
  e.put(checkpoint_version);
  e.put(case_hash);
  const auto& content = sim.problem().content;
  e.put(std::vector<char>(content.begin(), content.end()));
  e.put(sim.problem().time.step);
  e.put(static_cast<std::int32_t>(sim.problem().dimension));
  e.put(static_cast<std::int32_t>(sim.n_bodies()));
  for (int b = 0; b < sim.n_bodies(); ++b) {
    e.put(static_cast<std::int64_t>(sim.system(b).n_u()));
    e.put(static_cast<std::int64_t>(sim.system(b).n_theta()));
  }
  e.put(static_cast<std::int32_t>(c.step));
  for (const auto& b : c.bodies)
    for (const auto* v : {&b.u, &b.v, &b.a, &b.theta, &b.force, &b.g_free}) e.put(*v);
  e.put(c.lambda);
  e.put(static_cast<std::int32_t>(c.pairs.size()));
  for (const auto& pr : c.pairs) {
    e.put(std::vector<std::int32_t>(pr.lambda_nodes.begin(), pr.lambda_nodes.end()));
    e.put(pr.lambda_tangents);
    const auto& s = pr.contact;
    for (const int i : {s.qp_iterations, s.operator_applications, s.active_nodes, s.slip_nodes})
      e.put(static_cast<std::int32_t>(i));
    for (const double x :
         {s.normal_force, s.tangential_force, s.tangential_force_sum, s.dissipation})
      e.put(x);
    for (const double x : {pr.heat.generated, pr.heat.to_slave, pr.heat.to_master,
                           pr.heat.conducted, pr.heat.gap_conducted})
      e.put(x);
  }
  for (const auto* record : {&c.compliance, &c.stabiliser_compliance, &c.heat_compliance}) {
    e.put(static_cast<std::int32_t>(record->size()));
    for (const auto& v : *record) e.put(std::vector<std::int32_t>(v.begin(), v.end()));
  }
  e.put(c.slip);
  e.put(c.heat_flux);
  e.put(c.row);
  e.put(c.external_work);
  e.put(static_cast<std::int64_t>(c.total_coupling));
  e.put(static_cast<std::int64_t>(c.total_qp));
  e.put(static_cast<std::int64_t>(c.total_applications));
  e.put(static_cast<std::int32_t>(c.last_coupling));
  e.put(c.feti_body_lambda);
  e.put(c.feti_mu);
  e.put(static_cast<std::int64_t>(c.total_smalbe_outer));
  for (const double d : {c.boundary_heat.film, c.boundary_heat.radiation}) e.put(d);
  return e.finish();
}

physics::Checkpoint decode_checkpoint(const std::string& bytes, const physics::Simulation& sim,
                                      std::uint64_t case_hash, const std::string& where) {
  Decoder d(bytes, where);
  if (bytes.size() < sizeof magic + sizeof(std::uint64_t) ||
      std::memcmp(bytes.data(), magic, sizeof magic) != 0)
    d.fail("not a thermocontact checkpoint");
  const auto body_size = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t stored_sum = 0;
  std::memcpy(&stored_sum, bytes.data() + body_size, sizeof stored_sum);
  if (stored_sum != fnv1a(bytes.data(), body_size))
    d.fail("damaged (its checksum does not match its contents)");
  for (size_t i = 0; i < sizeof magic; ++i) (void)d.get<char>();
  if (const auto v = d.get<std::uint32_t>(); v != checkpoint_version)
    d.fail(fmt::format("format version {}, this program reads version {}", v, checkpoint_version));
  // What makes a checkpoint belong to a case: the same file, time step and discretisation.
  const auto& p = sim.problem();
  const auto stored_hash = d.get<std::uint64_t>();
  const auto stored = d.get_vector<char>();
  if (stored_hash != case_hash) {
    // Name the key: the checkpoint holds the content of the case it was written for.
    const auto why =
        detail::content_difference(std::string(stored.begin(), stored.end()), p.content);
    if (!why.empty())
      d.fail(fmt::format(
          "written for a different case: {}. A restart may change only time.end, the [output] "
          "settings and the title (the state in the checkpoint was computed with the rest); "
          "start a new run for another case, or give the same --set options",
          why));
    d.fail(
        "written for a different case file (its contents, or those of a mesh file it reads, "
        "changed since the checkpoint)");
  }
  if (const auto tau = d.get<double>(); tau != p.time.step)
    d.fail(fmt::format("time step {:g} s, the case has {:g} s", tau, p.time.step));
  if (const auto dim = d.get<std::int32_t>(); dim != p.dimension)
    d.fail(fmt::format("dimension {}, the case has {}", dim, p.dimension));
  if (const auto n = d.get<std::int32_t>(); n != sim.n_bodies())
    d.fail(fmt::format("{} bodies, the case has {}", n, sim.n_bodies()));
  for (int b = 0; b < sim.n_bodies(); ++b) {
    const auto nu = d.get<std::int64_t>(), nt = d.get<std::int64_t>();
    if (nu != sim.system(b).n_u() || nt != sim.system(b).n_theta())
      d.fail(fmt::format("body '{}' has {} + {} dofs, the case {} + {}", sim.system(b).body().name,
                         nu, nt, sim.system(b).n_u(), sim.system(b).n_theta()));
  }
  physics::Checkpoint c;
  c.step = d.get<std::int32_t>();
  c.bodies.resize(static_cast<size_t>(sim.n_bodies()));
  for (auto& b : c.bodies)
    for (auto* v : {&b.u, &b.v, &b.a, &b.theta, &b.force, &b.g_free}) *v = d.get_vector<double>();
  c.lambda = d.get_vector<double>();
  const auto n_pairs = d.get<std::int32_t>();
  if (n_pairs != static_cast<std::int32_t>(sim.problem().contacts.size()))
    d.fail(
        fmt::format("{} contact pairs, the case has {}", n_pairs, sim.problem().contacts.size()));
  c.pairs.resize(static_cast<size_t>(n_pairs));
  for (auto& pr : c.pairs) {
    const auto nodes = d.get_vector<std::int32_t>();
    pr.lambda_nodes.assign(nodes.begin(), nodes.end());
    pr.lambda_tangents = d.get_vector<double>();
    auto& s = pr.contact;
    for (int* i : {&s.qp_iterations, &s.operator_applications, &s.active_nodes, &s.slip_nodes})
      *i = d.get<std::int32_t>();
    for (double* x :
         {&s.normal_force, &s.tangential_force, &s.tangential_force_sum, &s.dissipation})
      *x = d.get<double>();
    for (double* x : {&pr.heat.generated, &pr.heat.to_slave, &pr.heat.to_master, &pr.heat.conducted,
                      &pr.heat.gap_conducted})
      *x = d.get<double>();
  }
  for (auto* record : {&c.compliance, &c.stabiliser_compliance, &c.heat_compliance}) {
    const auto n = d.get<std::int32_t>();
    if (n < 0 || n > 2 * sim.n_bodies()) d.fail("a bad compliance record");
    record->resize(static_cast<size_t>(n));
    for (auto& v : *record) {
      const auto x = d.get_vector<std::int32_t>();
      v.assign(x.begin(), x.end());
    }
  }
  c.slip = d.get_vector<double>();
  c.heat_flux = d.get_vector<double>();
  c.row = d.get_vector<double>();
  c.external_work = d.get<double>();
  c.total_coupling = d.get<std::int64_t>();
  c.total_qp = d.get<std::int64_t>();
  c.total_applications = d.get<std::int64_t>();
  c.last_coupling = d.get<std::int32_t>();
  c.feti_body_lambda = d.get_vector<double>();
  c.feti_mu = d.get_vector<double>();
  c.total_smalbe_outer = d.get<std::int64_t>();
  for (double* x : {&c.boundary_heat.film, &c.boundary_heat.radiation}) *x = d.get<double>();
  if (d.position() != body_size) d.fail("unexpected bytes after the data");
  return c;
}

void write_checkpoint(const std::filesystem::path& file, const physics::Simulation& sim,
                      std::uint64_t case_hash) {
  // Atomic: the old checkpoint or the new, never half; a full disk is an OutputError that
  // stops the run and leaves the previous checkpoint.
  replace_file(file, encode_checkpoint(sim, case_hash));
}

namespace {

/// Closes a descriptor on every way out.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

/// "" for a regular file (stat follows symbolic links), else what the file is instead.
std::string not_regular(const struct stat& st) {
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISDIR(st.st_mode)) return "a directory";
  return "not a regular file (a device, pipe or socket)";
}

/// The bytes of a checkpoint file, refused unless it is a regular file, and read up to the size
/// it has: a checkpoint.bin linked to /dev/zero was read until memory ran out. Every length in
/// the data is then checked against these bytes before anything is allocated (ByteReader).
std::string read_regular_file(const std::filesystem::path& file) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; no effect on a regular file.
  const Descriptor d{::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
  if (d.fd < 0 && errno == ENOENT)
    throw CheckpointError(
        fmt::format("no checkpoint {} to restart from (a run writes it after "
                    "every step into its output directory)",
                    printable(file)));
  if (d.fd < 0)
    throw CheckpointError(
        fmt::format("checkpoint {}: cannot be opened: {}", printable(file), std::strerror(errno)));
  struct stat st {};
  if (::fstat(d.fd, &st) != 0)
    throw CheckpointError(fmt::format("checkpoint {}: cannot be examined: {}", printable(file),
                                      std::strerror(errno)));
  if (const auto what = not_regular(st); !what.empty())
    throw CheckpointError(
        fmt::format("checkpoint {}: is {}, expected the checkpoint.bin file "
                    "that a run writes into its output directory",
                    printable(file), what));
  std::string bytes(static_cast<size_t>(st.st_size), '\0');
  size_t done = 0;
  while (done < bytes.size()) {
    const auto n = ::read(d.fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      throw CheckpointError(
          fmt::format("checkpoint {}: cannot be read: {}", printable(file), std::strerror(errno)));
    if (n == 0)
      throw CheckpointError(fmt::format("checkpoint {}: shorter than its size ({} of {} bytes)",
                                        printable(file), done, bytes.size()));
    done += static_cast<size_t>(n);
  }
  return bytes;
}

}  // namespace

physics::Checkpoint read_checkpoint(const std::filesystem::path& file,
                                    const physics::Simulation& sim, std::uint64_t case_hash) {
  return decode_checkpoint(read_regular_file(file), sim, case_hash, printable(file));
}

void check_restart_outputs(const std::filesystem::path& directory) {
  // A restart reads these line by line (the rows and data sets it keeps): each must be a
  // regular file, as a run leaves it, not a link to /dev/zero.
  for (const char* name : {"history.csv", "result.pvd"}) {
    const auto file = directory / name;
    struct stat st {};
    // Missing: history.csv is refused by check_restart_history, result.pvd rebuilt by the
    // OutputWriter from the field files.
    if (::stat(file.c_str(), &st) != 0) continue;
    if (const auto what = not_regular(st); !what.empty())
      throw CheckpointError(
          fmt::format("restart from {}: {} is {}, expected the file that a "
                      "run writes there",
                      printable(directory), printable(file), what));
  }
}

void check_restart_history(const std::filesystem::path& directory, const physics::Simulation& sim) {
  const auto file = directory / "history.csv";
  const int k = sim.step();
  const auto refuse = [&](const std::string& why) {
    throw CheckpointError(
        fmt::format("restart from {}: {} {}; a restart continues the history "
                    "of its checkpoint's run, which must hold steps 0 to {}",
                    printable(directory), printable(file), why, k - 1));
  };
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    if (!std::filesystem::exists(std::filesystem::symlink_status(file))) refuse("is missing");
    refuse(fmt::format("cannot be read ({})", std::strerror(errno)));
  }
  std::string header;
  for (const auto& c : sim.history_columns()) header += (header.empty() ? "" : ",") + c;
  std::string line;
  if (!std::getline(in, line) || in.eof()) refuse("is empty or has no whole header line");
  if (line != header)
    refuse(fmt::format("has a header that is not this case's ({} columns, expected {})",
                       std::count(line.begin(), line.end(), ',') + 1,
                       sim.history_columns().size()));
  int expected = 0;                                              // the step of the next row
  while (expected < k && std::getline(in, line) && !in.eof()) {  // a last line without '\n'
    char* end = nullptr;                                         // is not a whole row
    const double step = std::strtod(line.c_str(), &end);
    if (end == line.c_str() || *end != ',')
      refuse(fmt::format("has a row that does not begin with a step number after step {}",
                         expected - 1));
    if (step != expected)
      refuse(expected == 0 ? fmt::format("begins at step {:g}", step)
                           : fmt::format("jumps from step {} to step {:g}", expected - 1, step));
    ++expected;
  }
  if (expected < k)
    refuse(expected == 0
               ? std::string("has no rows")
               : fmt::format("ends at step {}, before the checkpoint's step {}", expected - 1, k));
}

CheckpointPolicy CheckpointPolicy::of(const physics::OutputSettings& output) {
  return {output.checkpoint_every, output.checkpoint_seconds};
}

bool CheckpointPolicy::due(int steps, double seconds, double cost) const {
  if (every > 0 && steps >= every) return true;
  return this->seconds > 0 && seconds >= std::max(this->seconds, cost_factor * cost);
}

CheckpointWriter::CheckpointWriter(std::filesystem::path directory, std::uint64_t case_hash,
                                   CheckpointPolicy policy)
    : file_(checkpoint_file(directory)),
      case_hash_(case_hash),
      policy_(policy),
      root_(core::PetscSession::rank() == 0) {}

namespace {
double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

void CheckpointWriter::write(const physics::Simulation& sim) {
  const double t0 = now_seconds();
  // Rank 0 writes; a failure there (disk full) must stop every rank, not leave them waiting.
  core::collective_check(PETSC_COMM_WORLD, "checkpoint", [&] {
    if (root_) write_checkpoint(file_, sim, case_hash_);
  });
  written_step_ = sim.step();
  last_time_ = now_seconds();
  last_cost_ = last_time_ - t0;
}

void CheckpointWriter::step(const physics::Simulation& sim) {
  seen_step_ = sim.step();
  // The first step seen (t = 0, or the restored step) always: a restart has a checkpoint from
  // the start on. Rank 0's clock decides for every rank: they must agree on a collective write.
  int due = written_step_ < 0 ||
            policy_.due(sim.step() - written_step_, now_seconds() - last_time_, last_cost_);
  if (core::PetscSession::size() > 1)
    core::check_mpi(MPI_Bcast(&due, 1, MPI_INT, 0, PETSC_COMM_WORLD), "MPI_Bcast");
  if (due) write(sim);
}

void CheckpointWriter::finish(const physics::Simulation& sim, const physics::RunStatus& status) {
  // At the end and after a stop signal the state is that of the last step whose output is
  // whole (seen by step()): it is saved, so the restart loses nothing. After a numerical or
  // output failure inside a step the state is part-way through the next one: the last
  // checkpoint stands, and a restart re-does the steps after it.
  if ((status.completed || status.between_steps) && seen_step_ == sim.step() &&
      written_step_ != sim.step())
    write(sim);
}

}  // namespace tc::io
