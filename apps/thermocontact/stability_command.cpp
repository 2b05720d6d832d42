#include "stability_command.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/io/files/files.hpp"
#include "tc/io/vtk/vtu.hpp"
#include "tc/stability/analysis.hpp"

namespace {

namespace fs = std::filesystem;
using tc::stability::Eigenpair;
using tc::stability::Linearisation;
using tc::stability::StabilityResult;

/// A number as JSON (null when not finite).
std::string json_number(double x) {
  return std::isfinite(x) ? fmt::format("{:.10g}", x) : std::string("null");
}

std::string json_eigenvalues(const std::vector<Eigenpair>& pairs) {
  std::string s = "[";
  for (size_t i = 0; i < pairs.size(); ++i)
    s += fmt::format("{}{{\"re\": {}, \"im\": {}, \"residual\": {}}}", i ? ", " : "",
                     json_number(pairs[i].re), json_number(pairs[i].im),
                     json_number(pairs[i].residual));
  return s + "]";
}

std::string json_text(const tc::physics::Problem& p, const StabilityResult& r, double total) {
  const auto& s = *p.stability;
  std::string j = "{\n";
  j += fmt::format("  \"case\": \"{}\",\n", tc::io::printable(p.case_file));
  j += fmt::format("  \"normal_control\": \"{}\",\n",
                   s.normal_control == tc::physics::StabilitySettings::NormalControl::force
                       ? "force"
                       : "displacement");
  j += fmt::format(
      "  \"state\": {{\"step\": {}, \"time\": {}, \"speed\": {}, \"pressed_nodes\": {}, "
      "\"open_nodes\": {}, \"unknowns\": {}}},\n",
      s.state_step, json_number(r.state_time), json_number(r.state_speed), r.active_nodes,
      r.open_nodes, r.unknowns);
  j += "  \"speeds\": [\n";
  for (size_t i = 0; i < r.speeds.size(); ++i) {
    const auto& v = r.speeds[i];
    j += fmt::format(
        "    {{\"speed\": {}, \"target\": {}, \"leading_growth_rate\": {}, \"eigenvalues\": {}, "
        "\"converged\": {}, \"iterations\": {}, \"seconds\": {}}}{}\n",
        json_number(v.speed), json_number(v.rates.target),
        v.rates.pairs.empty() ? "null" : json_number(v.rates.pairs.front().re),
        json_eigenvalues(v.rates.pairs), v.rates.converged, v.rates.iterations,
        json_number(v.seconds), i + 1 < r.speeds.size() ? "," : "");
  }
  j += "  ],\n";
  j += fmt::format("  \"critical_speed\": {},\n",
                   r.critical ? json_number(r.critical->re) : std::string("null"));
  j += fmt::format("  \"growth_rate_at_critical_speed\": {},\n",
                   r.growth_at_critical ? json_number(*r.growth_at_critical) : "null");
  j += fmt::format(
      "  \"seconds\": {{\"state\": {}, \"linearise\": {}, \"critical_speed\": {}, \"total\": "
      "{}}}\n",
      json_number(r.state_seconds), json_number(r.linearise_seconds),
      json_number(r.critical_seconds), json_number(total));
  return j + "}\n";
}

std::string csv_text(const StabilityResult& r) {
  std::string c = "speed,index,re,im,residual\n";
  for (const auto& v : r.speeds)
    for (size_t i = 0; i < v.rates.pairs.size(); ++i)
      c += fmt::format("{:.10g},{},{:.10g},{:.10g},{:.3g}\n", v.speed, i, v.rates.pairs[i].re,
                       v.rates.pairs[i].im, v.rates.pairs[i].residual);
  return c;
}

/// A mode's θ and u (real and imaginary parts) on the slave's mesh.
void write_mode(const fs::path& file, const tc::physics::Problem& p, const Linearisation& lin,
                const Eigenpair& e) {
  const auto& mesh = p.bodies.at(static_cast<size_t>(lin.body)).mesh;
  const int dim = p.dimension;
  const auto f = tc::stability::mode_fields(lin, e, dim, mesh.n_nodes());
  const auto vec3 = [&](const std::string& name, const std::vector<double>& u) {
    tc::io::Field out{name, 3, std::vector<double>(3 * static_cast<size_t>(mesh.n_nodes()), 0.0)};
    for (size_t a = 0; a < static_cast<size_t>(mesh.n_nodes()); ++a)
      for (int k = 0; k < dim; ++k) out.values[3 * a + k] = u[dim * a + k];
    return out;
  };
  tc::io::write_vtu(file, mesh,
                    {{"temperature_re", 1, f.theta_re},
                     {"temperature_im", 1, f.theta_im},
                     vec3("displacement_re", f.u_re),
                     vec3("displacement_im", f.u_im)},
                    {});
}

}  // namespace

int stability_command(const std::string& case_file, const std::vector<std::string>& overrides,
                      const std::string& output, const char* program) {
  int argc = 1;
  char* args[] = {const_cast<char*>(program), nullptr};
  char** argv = args;
  tc::core::PetscSession session(&argc, &argv);
  const auto start = std::chrono::steady_clock::now();
  try {
    if (tc::core::PetscSession::size() > 1)
      throw tc::Error("stability: runs on one rank (without mpirun)");
    auto problem = tc::io::read_case(case_file, overrides);
    if (!problem.stability) {  // its checks of the case (case_stability.cpp) come with it
      fmt::print(stderr,
                 "error: {}: no [stability] section, expected one (docs/case-format.md, "
                 "\"Stability analysis\"); nothing was run.\n",
                 case_file);
      return 2;
    }
    if (!output.empty()) problem.output.directory = output;
    Linearisation lin;
    const auto r = tc::stability::analyse(
        problem, [](const std::string& line) { fmt::print("stability: {}\n", line); }, &lin);
    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto& dir = problem.output.directory;
    fs::create_directories(dir);
    tc::io::replace_file(dir / "stability.json", json_text(problem, r, total));
    tc::io::replace_file(dir / "stability.csv", csv_text(r));
    if (problem.stability->modes) {
      for (size_t i = 0; i < r.speeds.size(); ++i)
        if (!r.speeds[i].rates.pairs.empty())
          write_mode(dir / fmt::format("mode_{}.vtu", i), problem, lin,
                     r.speeds[i].rates.pairs.front());
      if (r.critical) write_mode(dir / "mode_critical.vtu", problem, lin, *r.critical);
    }
    fmt::print("done: {} speed(s){}; output in {}\n", r.speeds.size(),
               r.critical ? fmt::format(", critical speed {:.6g} m/s", r.critical->re) : "",
               tc::io::printable(dir));
    std::fflush(stdout);
    return 0;
  } catch (const tc::InputError& e) {
    for (const auto& issue : e.issues()) fmt::print(stderr, "error: {}\n", issue.str());
    fmt::print(stderr, "{} error{} in the case file; nothing was run.\n", e.issues().size(),
               e.issues().size() == 1 ? "" : "s");
    return 2;
  } catch (const tc::MeshError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  } catch (const tc::Error& e) {
    fmt::print(stderr, "stopped: {}\n", e.what());
    return 1;
  }
}
