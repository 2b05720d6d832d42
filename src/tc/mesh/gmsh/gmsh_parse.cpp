// The .msh file into a RawMesh (gmsh_reader.hpp, detail): the header checked at once, then
// libgmsh, loaded with dlopen, parses it in a forked child that sends the RawMesh back through
// a pipe, so that neither a crash nor the state of libgmsh reaches the caller. gmsh_reader.cpp
// builds the Mesh from what comes back.
#include <dlfcn.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <gmshc.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <type_traits>

#include "tc/core/bytes.hpp"
#include "tc/core/error.hpp"
#include "tc/core/stop.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"

#define TC_STRINGIFY_(x) #x
#define TC_STRINGIFY(x) TC_STRINGIFY_(x)

namespace tc::mesh {
namespace {

// ---- Raw data copied out of gmsh (gmsh_reader.hpp, detail) --------------------------------

using detail::RawBlock;
using detail::RawGroup;
using detail::RawMesh;

/// libgmsh through its C API (gmshc.h), loaded with dlopen when a mesh file is first read (in
/// the reader's child process, below) instead of linked: linked, its OpenCASCADE, FLTK …
/// libraries loaded and initialised in every run, 0.1 s of a 0.17 s start-up
/// (bench/RESULTS.md). Each call's error code becomes an exception with gmsh's last error
/// message, as its C++ API throws.
class Gmsh {
 public:
  static const Gmsh& api() {
    static const Gmsh g;
    return g;
  }

  template <class F, class... A>
  void call(F* f, const char* what, A... args) const {
    int ierr = 0;
    f(args..., &ierr);
    if (ierr != 0) throw std::runtime_error(last_error(what));
  }
  /// A gmsh-allocated array as a vector (and freed).
  template <class T>
  std::vector<T> take(T* data, std::size_t n) const {
    std::vector<T> out(data, data + n);
    free(data);
    return out;
  }
  std::string take_string(char* text) const {
    std::string out = text ? text : "";
    free(text);
    return out;
  }

  // Each function resolved as the object is built (after handle_, declared first): one line
  // names the C function, its type and its member.
#define TC_GMSH_FUNCTION(member, symbol) \
  const decltype(&::symbol) member = resolve<decltype(&::symbol)>(#symbol)

 private:
  void* const handle_ = open_library();

 public:
  TC_GMSH_FUNCTION(initialize, gmshInitialize);
  TC_GMSH_FUNCTION(finalize, gmshFinalize);
  TC_GMSH_FUNCTION(set_number, gmshOptionSetNumber);
  TC_GMSH_FUNCTION(open, gmshOpen);
  TC_GMSH_FUNCTION(get_nodes, gmshModelMeshGetNodes);
  TC_GMSH_FUNCTION(get_elements, gmshModelMeshGetElements);
  TC_GMSH_FUNCTION(get_element_properties, gmshModelMeshGetElementProperties);
  TC_GMSH_FUNCTION(get_physical_groups, gmshModelGetPhysicalGroups);
  TC_GMSH_FUNCTION(get_physical_name, gmshModelGetPhysicalName);
  TC_GMSH_FUNCTION(get_entities_for_physical_group, gmshModelGetEntitiesForPhysicalGroup);
  TC_GMSH_FUNCTION(get_last_error, gmshLoggerGetLastError);
  TC_GMSH_FUNCTION(free, gmshFree);
#undef TC_GMSH_FUNCTION

 private:
  Gmsh() = default;
  /// The library the build found, else the installed one of the same API version. In a link
  /// namespace of its own (dlmopen) where it can: loaded beside PETSc, MPI and the BLAS, each of
  /// libgmsh's many symbols was looked up through those hundred libraries first, which tripled
  /// the CPU time of loading it (bench/RESULTS.md, "Start-up of a case with Gmsh meshes"). The
  /// child that loads it exits after the parse, so the namespace's own C library is harmless.
  static void* open_library() {
    for (const char* name :
         {TC_GMSH_LIBRARY, "libgmsh.so." TC_STRINGIFY(GMSH_API_VERSION_MAJOR) "." TC_STRINGIFY(
                               GMSH_API_VERSION_MINOR)}) {
      if (void* handle = ::dlmopen(LM_ID_NEWLM, name, RTLD_NOW | RTLD_LOCAL)) return handle;
      if (void* handle = ::dlopen(name, RTLD_NOW | RTLD_LOCAL)) return handle;
    }
    const char* why = ::dlerror();
    throw MeshError(std::string("cannot load libgmsh (" TC_GMSH_LIBRARY "): ") +
                    (why ? why : "unknown error"));
  }
  template <class F>
  F resolve(const char* symbol) const {
    auto* f = reinterpret_cast<F>(::dlsym(handle_, symbol));
    if (!f) throw MeshError(std::string("libgmsh has no ") + symbol);
    return f;
  }
  std::string last_error(const char* what) const {
    char* text = nullptr;
    int ierr = 0;
    get_last_error(&text, &ierr);
    std::string message = ierr == 0 && text && *text ? text : std::string(what) + " failed";
    if (text) free(text);
    return message;
  }
};

/// One gmsh session: libgmsh is a global singleton, so read_gmsh must not be called while the
/// caller holds a gmsh session of its own (this one would finalize it).
class GmshSession {
 public:
  GmshSession() {
    const auto& g = Gmsh::api();
    // No configuration files: the user's ~/.gmshrc must not change how a mesh is read.
    g.call(g.initialize, "gmshInitialize", 0, static_cast<char**>(nullptr), 0);
    g.call(g.set_number, "gmshOptionSetNumber", "General.Terminal", 0.0);
  }
  ~GmshSession() {
    int ierr = 0;
    Gmsh::api().finalize(&ierr);  // a destructor must not throw; nothing useful to do
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

std::string type_name(int type) {
  const auto& g = Gmsh::api();
  char* name = nullptr;
  int dim = 0, order = 0, n = 0, n_primary = 0;
  double* local = nullptr;
  std::size_t n_local = 0;
  g.call(g.get_element_properties, "gmshModelMeshGetElementProperties", type, &name, &dim, &order,
         &n, &local, &n_local, &n_primary);
  g.free(local);
  return g.take_string(name);
}

/// gmshModelMeshGetElements of (dim, tag): the element types and each type's node tags.
void get_elements(int dim, int tag, std::vector<int>& types,
                  std::vector<std::vector<std::size_t>>& nodes) {
  const auto& g = Gmsh::api();
  int* t = nullptr;
  std::size_t nt = 0, n_tags_nn = 0, n_nodes_nn = 0;
  std::size_t **tags = nullptr, **node_tags = nullptr;
  std::size_t *tags_n = nullptr, *node_tags_n = nullptr;
  g.call(g.get_elements, "gmshModelMeshGetElements", &t, &nt, &tags, &tags_n, &n_tags_nn,
         &node_tags, &node_tags_n, &n_nodes_nn, dim, tag);
  types = g.take(t, nt);
  nodes.clear();
  for (std::size_t b = 0; b < n_tags_nn; ++b) g.free(tags[b]);
  for (std::size_t b = 0; b < n_nodes_nn; ++b)
    nodes.push_back(g.take(node_tags[b], node_tags_n[b]));
  g.free(tags);
  g.free(tags_n);
  g.free(node_tags);
  g.free(node_tags_n);
}

RawBlock to_block(int type, std::vector<std::size_t>&& nodes, RawMesh& raw) {
  if (!raw.type_names.count(type)) raw.type_names[type] = type_name(type);
  return {type, std::move(nodes)};
}

RawMesh read_raw(const std::filesystem::path& file, int dim) {
  const auto& g = Gmsh::api();
  RawMesh raw;
  g.call(g.open, "gmshOpen", file.c_str());
  {
    std::size_t *tags = nullptr, n_tags = 0, n_coords = 0, n_param = 0;
    double *coords = nullptr, *param = nullptr;
    g.call(g.get_nodes, "gmshModelMeshGetNodes", &tags, &n_tags, &coords, &n_coords, &param,
           &n_param, -1, -1, 0, 0);
    raw.node_tags = g.take(tags, n_tags);
    raw.coords = g.take(coords, n_coords);
    g.free(param);
  }
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> nodes;
  get_elements(dim, -1, types, nodes);
  for (std::size_t b = 0; b < types.size(); ++b)
    raw.cells.push_back(to_block(types[b], std::move(nodes[b]), raw));

  int* dim_tags = nullptr;
  std::size_t n_dim_tags = 0;
  g.call(g.get_physical_groups, "gmshModelGetPhysicalGroups", &dim_tags, &n_dim_tags, dim - 1);
  const auto groups = g.take(dim_tags, n_dim_tags);
  for (std::size_t i = 0; i + 1 < groups.size(); i += 2) {
    const int gdim = groups[i], gtag = groups[i + 1];
    RawGroup group;
    char* name = nullptr;
    g.call(g.get_physical_name, "gmshModelGetPhysicalName", gdim, gtag, &name);
    group.name = g.take_string(name);
    if (group.name.empty()) continue;  // unnamed groups cannot be referred to by a case file
    int* entities = nullptr;
    std::size_t n_entities = 0;
    g.call(g.get_entities_for_physical_group, "gmshModelGetEntitiesForPhysicalGroup", gdim, gtag,
           &entities, &n_entities);
    for (const int e : g.take(entities, n_entities)) {
      get_elements(gdim, e, types, nodes);
      for (std::size_t b = 0; b < types.size(); ++b)
        group.blocks.push_back(to_block(types[b], std::move(nodes[b]), raw));
    }
    raw.groups.push_back(std::move(group));
  }
  // The physical groups of the cells (Mesh::cell_group, the .vtu's physical_group).
  g.call(g.get_physical_groups, "gmshModelGetPhysicalGroups", &dim_tags, &n_dim_tags, dim);
  const auto cell_groups = g.take(dim_tags, n_dim_tags);
  for (std::size_t i = 0; i + 1 < cell_groups.size(); i += 2) {
    RawGroup group;
    group.tag = cell_groups[i + 1];
    int* entities = nullptr;
    std::size_t n_entities = 0;
    g.call(g.get_entities_for_physical_group, "gmshModelGetEntitiesForPhysicalGroup",
           cell_groups[i], group.tag, &entities, &n_entities);
    for (const int e : g.take(entities, n_entities)) {
      get_elements(dim, e, types, nodes);
      for (std::size_t b = 0; b < types.size(); ++b)
        group.blocks.push_back(to_block(types[b], std::move(nodes[b]), raw));
    }
    raw.cell_groups.push_back(std::move(group));
  }
  return raw;
}

/// Runs read_raw in its own gmsh session and turns whatever gmsh throws into a MeshError.
RawMesh read_raw_safely(const std::filesystem::path& file, int dim) {
  const std::string where = "mesh file '" + file.string() + "'";
  try {
    const GmshSession session;
    return read_raw(file, dim);
  } catch (const tc::Error&) {
    throw;
  } catch (const std::string& s) {
    throw MeshError("cannot read " + where + ": " + s);
  } catch (const char* s) {
    throw MeshError("cannot read " + where + ": " + s);
  } catch (const std::exception& e) {
    throw MeshError("cannot read " + where + ": " + e.what());
  } catch (...) {
    throw MeshError("cannot read " + where + ": unknown gmsh error");
  }
}

// ---- libgmsh in a child process ---------------------------------------------------------
//
// libgmsh 4.8 is not memory-safe on malformed files: tests/fuzz/fuzz_gmsh_reader found files
// on which it frees an invalid pointer in gmsh::finalize (glibc aborts the process) or
// corrupts its heap (docs/robustness.md). So the file is parsed by a forked child that sends
// the RawMesh back through a pipe and exits; a crash of libgmsh kills only the child and
// becomes a MeshError here. Forking an MPI process is safe for this: the child touches no
// MPI state and leaves by _exit (no atexit handlers, no MPI_Finalize).

using Bytes = core::ByteWriter;

/// The child's record read back; a short record is a MeshError.
class Reader : public core::ByteReader {
 public:
  explicit Reader(const std::string& s)
      : core::ByteReader(
            s, [](const std::string& what) { throw MeshError("mesh reader: " + what); }) {}
};

void put_block(Bytes& b, const RawBlock& block) {
  b.put(static_cast<std::int32_t>(block.type));
  b.put_vector(block.nodes);
}

RawBlock get_block(Reader& r) {
  RawBlock block;
  block.type = r.get<std::int32_t>();
  block.nodes = r.get_vector<std::size_t>();
  return block;
}

std::string encode(const RawMesh& raw) {
  Bytes b;
  b.put_vector(raw.node_tags);
  b.put_vector(raw.coords);
  b.put(static_cast<std::uint64_t>(raw.cells.size()));
  for (const auto& c : raw.cells) put_block(b, c);
  b.put(static_cast<std::uint64_t>(raw.groups.size()));
  for (const auto& g : raw.groups) {
    b.put_string(g.name);
    b.put(static_cast<std::uint64_t>(g.blocks.size()));
    for (const auto& c : g.blocks) put_block(b, c);
  }
  b.put(static_cast<std::uint64_t>(raw.cell_groups.size()));
  for (const auto& g : raw.cell_groups) {
    b.put(static_cast<std::int32_t>(g.tag));
    b.put(static_cast<std::uint64_t>(g.blocks.size()));
    for (const auto& c : g.blocks) put_block(b, c);
  }
  b.put(static_cast<std::uint64_t>(raw.type_names.size()));
  for (const auto& [type, name] : raw.type_names) {
    b.put(static_cast<std::int32_t>(type));
    b.put_string(name);
  }
  return std::move(b.str());
}

RawMesh decode(const std::string& bytes) {
  Reader r(bytes);
  RawMesh raw;
  raw.node_tags = r.get_vector<std::size_t>();
  raw.coords = r.get_vector<double>();
  for (auto n = r.get<std::uint64_t>(); n > 0; --n) raw.cells.push_back(get_block(r));
  for (auto n = r.get<std::uint64_t>(); n > 0; --n) {
    RawGroup g;
    g.name = r.get_string();
    for (auto m = r.get<std::uint64_t>(); m > 0; --m) g.blocks.push_back(get_block(r));
    raw.groups.push_back(std::move(g));
  }
  for (auto n = r.get<std::uint64_t>(); n > 0; --n) {
    RawGroup g;
    g.tag = r.get<std::int32_t>();
    for (auto m = r.get<std::uint64_t>(); m > 0; --m) g.blocks.push_back(get_block(r));
    raw.cell_groups.push_back(std::move(g));
  }
  for (auto n = r.get<std::uint64_t>(); n > 0; --n) {
    const int type = r.get<std::int32_t>();
    raw.type_names[type] = r.get_string();
  }
  return raw;
}

void write_all(int fd, const std::string& s) {
  std::size_t done = 0;
  while (done < s.size()) {
    const auto n = ::write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent sees a short message and reports it
    done += static_cast<std::size_t>(n);
  }
}

/// The signals that ask thermocontact to stop (apps/thermocontact): the child must not inherit
/// the parent's handler for them, which only sets a flag the child never reads.
constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGUSR2, SIGXCPU};

/// Ends the child at once and reaps it (it may hold gigabytes and a core at 100 %).
void kill_child(pid_t pid) {
  ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
}

/// Collects the child's reply until it closes the pipe. Waits in slices of 50 ms so that a
/// stop signal (core::stop_signal, set by the app's handler; the poll also returns early with
/// EINTR) ends the wait promptly: libgmsh may take minutes on a large malformed file, and the
/// parent ignored SIGTERM and SIGINT all that time (issue 42, D8).
std::string read_reply(int fd, pid_t pid, const std::string& where) {
  std::string in;
  char buf[65536];
  for (;;) {
    if (const int sig = core::stop_signal.load(); sig != 0) {
      kill_child(pid);
      throw Interrupted("interrupted by signal " + std::to_string(sig) + " while reading " + where);
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, 50);
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    const auto n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    in.append(buf, static_cast<std::size_t>(n));
  }
  return in;
}

RawMesh read_raw_isolated(const std::filesystem::path& file, int dim) {
  const std::string where = "mesh file '" + file.string() + "'";
  int fds[2];
  if (::pipe(fds) != 0) return read_raw_safely(file, dim);  // no pipe: parse in-process
  std::fflush(nullptr);                                     // nothing buffered is written twice
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return read_raw_safely(file, dim);
  }
  if (pid == 0) {  // the child: parse, send 'R' + data or 'E' + message, leave without cleanup
    ::close(fds[0]);
    // The child dies with its parent, however the parent dies (SIGKILL included): it kept
    // parsing at 100 % CPU after its parent was killed (issue 42, D8). The parent may have died
    // before prctl took effect: then the child is an orphan already and leaves.
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(1);
    // A stop signal ends the child (Ctrl-C reaches the whole process group); the parent then
    // reports the stop. A crash is reported by the parent: not by the handlers MPI/PETSc
    // installed, nor by glibc's heap messages on stderr.
    for (const int sig : kStopSignals) std::signal(sig, SIG_DFL);
    for (const int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, SIG_DFL);
    if (const int null = ::open("/dev/null", O_WRONLY); null >= 0) ::dup2(null, STDERR_FILENO);
    std::string out;
    try {
      out = 'R' + encode(read_raw_safely(file, dim));
    } catch (const std::exception& e) {
      out = std::string("E") + e.what();
    } catch (...) {
      out = "Eunknown error";
    }
    write_all(fds[1], out);
    ::close(fds[1]);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string in;
  try {
    in = read_reply(fds[0], pid, where);
  } catch (...) {
    ::close(fds[0]);
    throw;
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // A stop signal sent to the process group ends the child too: that is the stop, not a crash.
  if (const int sig = core::stop_signal.load(); sig != 0)
    throw Interrupted("interrupted by signal " + std::to_string(sig) + " while reading " + where);
  if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGKILL || WTERMSIG(status) == SIGTERM))
    throw Interrupted("cannot read " + where + ": the Gmsh reader (a child process) was killed " +
                      "by signal " + std::to_string(WTERMSIG(status)) +
                      " (out of memory, or stopped from outside)");
  if (WIFSIGNALED(status))
    throw MeshError("cannot read " + where + ": the Gmsh library crashed on it (signal " +
                    std::to_string(WTERMSIG(status)) + "); the file is malformed");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || in.empty())
    throw MeshError("cannot read " + where + ": the Gmsh library failed on it (exit status " +
                    std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                    "); the file is malformed");
  if (in[0] == 'E') throw MeshError(in.substr(1));
  if (in[0] != 'R') throw MeshError("cannot read " + where + ": garbled reply from the reader");
  return decode(in.substr(1));
}

/// Gmsh's own first line of every .msh file, ASCII or binary, versions 2 and 4.
constexpr std::string_view kMeshFormat = "$MeshFormat";

/// `bytes` shown on one line: printable ASCII as is, anything else as \xNN.
std::string printable(std::string_view bytes) {
  std::string out;
  for (const char c : bytes) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", u);
      out += hex;
    }
  }
  return out;
}

/// Refuses at once a file whose first line is not `$MeshFormat`: libgmsh read 300 MB of NUL
/// bytes for 72 s (3 GB: 14 min) before it found no mesh in them (issue 42, D8). Only the first
/// 4 KiB are read. The line must be the very first and exactly that, as libgmsh itself
/// requires (a blank line before it gave "line 3: syntax error ($)", trailing blanks or a
/// '\r' "no cells").
void check_header(const std::filesystem::path& file, const std::string& where) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw MeshError("cannot read " + where + ": it cannot be opened");
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  std::string_view line(head);
  line = line.substr(0, line.find('\n'));
  if (line == kMeshFormat) return;
  constexpr std::size_t shown = 24;
  // fmt rather than operator+: g++ 12 takes the concatenation for an overlapping memcpy
  // (a -Wrestrict false alarm) once this function sits in its own translation unit.
  const std::string found =
      head.empty()   ? std::string("an empty file")
      : line.empty() ? std::string("a blank first line")
                     : fmt::format("'{}{}' as its first line", printable(line.substr(0, shown)),
                                   line.size() > shown ? "..." : "");
  throw MeshError(
      fmt::format("cannot read {}: found {}, expected {} (the first line of a Gmsh "
                  ".msh file)",
                  where, found, kMeshFormat));
}

}  // namespace

RawMesh detail::read_raw_isolated(const std::filesystem::path& file, int dim) {
  return mesh::read_raw_isolated(file, dim);
}

void detail::check_header(const std::filesystem::path& file, const std::string& where) {
  mesh::check_header(file, where);
}

}  // namespace tc::mesh
