#include "tc/stability/analysis.hpp"

#include <fmt/format.h>

#include <chrono>

#include "tc/core/error.hpp"
#include "tc/run/simulation.hpp"

namespace tc::stability {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

ModeFields mode_fields(const Linearisation& lin, const Eigenpair& e, int dim, PetscInt n_nodes) {
  ModeFields f;
  f.theta_re.assign(static_cast<size_t>(n_nodes), 0.0);
  f.theta_im = f.theta_re;
  f.u_re.assign(static_cast<size_t>(dim * n_nodes), 0.0);
  f.u_im = f.u_re;
  for (size_t i = 0; i < lin.x.u.size(); ++i) {
    f.u_re[static_cast<size_t>(lin.x.u[i])] = e.x_re[i];
    f.u_im[static_cast<size_t>(lin.x.u[i])] = e.x_im[i];
  }
  const auto ot = static_cast<size_t>(lin.x.theta_offset());
  for (size_t i = 0; i < lin.x.theta.size(); ++i) {
    f.theta_re[static_cast<size_t>(lin.x.theta[i])] = e.x_re[ot + i];
    f.theta_im[static_cast<size_t>(lin.x.theta[i])] = e.x_im[ot + i];
  }
  return f;
}

StabilityResult analyse(const physics::Problem& p,
                        const std::function<void(const std::string&)>& progress,
                        Linearisation* keep) {
  const auto settings = p.stability.value_or(physics::StabilitySettings{});
  const auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  StabilityResult out;
  auto clock = std::chrono::steady_clock::now();
  // The state: the case's first steps, each body solved directly (one rank).
  physics::Problem state = p;
  for (auto& b : state.bodies) b.subdomains = 1;
  physics::Simulation sim(state);
  sim.enable_mortar_contact();
  for (int s = 0; s < settings.state_step; ++s) sim.advance();
  out.state_seconds = seconds_since(clock);
  out.state_time = sim.time();
  say(fmt::format("state: {} step(s) to t = {:g} s in {:.2f} s", settings.state_step, sim.time(),
                  out.state_seconds));

  clock = std::chrono::steady_clock::now();
  Linearisation lin = linearise(sim, settings.normal_control, settings.friction_shear);
  out.linearise_seconds = seconds_since(clock);
  out.body = lin.body;
  out.state_speed = lin.speed;
  out.active_nodes = static_cast<int>(lin.x.contact.size());
  out.open_nodes = lin.open_nodes;
  out.unknowns = static_cast<int>(lin.x.size());
  say(fmt::format("linearised: {} unknowns, {} contact nodes pressed, {} open, V = {:g} m/s",
                  out.unknowns, out.active_nodes, out.open_nodes, lin.speed));

  SlepcSession slepc;
  auto speeds = settings.speeds;
  if (speeds.empty()) speeds.push_back(lin.speed);
  for (const double v : speeds) {
    clock = std::chrono::steady_clock::now();
    SpeedResult r;
    r.speed = v;
    r.rates = growth_rates(lin, v, settings.eigenvalues,
                           settings.target.value_or(default_target(lin, v)));
    r.seconds = seconds_since(clock);
    say(fmt::format("V = {:g} m/s: leading b = {} 1/s ({} converged, {:.2f} s)", v,
                    r.rates.pairs.empty() ? std::string("none")
                                          : fmt::format("{:.6g}", r.rates.pairs.front().re),
                    r.rates.converged, r.seconds));
    out.speeds.push_back(std::move(r));
  }
  if (settings.critical_speed) {
    clock = std::chrono::steady_clock::now();
    out.critical = critical_speed(lin, settings.eigenvalues, &out.critical_iterations);
    if (out.critical) {
      const auto at = growth_rates(lin, out.critical->re, 1,
                                   settings.target.value_or(default_target(lin, out.critical->re)));
      if (!at.pairs.empty()) out.growth_at_critical = at.pairs.front().re;
    }
    out.critical_seconds = seconds_since(clock);
    say(out.critical
            ? fmt::format("critical speed {:.6g} m/s (leading b there {:.3g} 1/s; {:.2f} s)",
                          out.critical->re, out.growth_at_critical.value_or(0.0),
                          out.critical_seconds)
            : std::string("critical speed: none found (no real crossing b = 0)"));
  }
  if (keep) *keep = std::move(lin);
  return out;
}

}  // namespace tc::stability
