// [stability]: the settings of `thermocontact stability` and what the analysis needs of the
// case (src/tc/stability/analysis.hpp): the quasistatic scheme, one contact pair whose master
// is a rigid tool that slides after the state's step, an adiabatic tool (a conducting tool's
// terms are not linearised). Each
// refusal names the [stability] table's line.
#include <fmt/format.h>

#include <cmath>

#include "tc/io/case/case_reader_detail.hpp"
#include "tc/model/rigid_tool.hpp"

namespace tc::io::detail {

void CaseReader::read_stability(const TableReader& root) {
  const auto t = root.sub_table("stability");
  if (!t) return;
  physics::StabilitySettings s;
  if (const auto* n = t->get("speeds")) {
    const auto* a = n->as_array();
    if (!a || a->empty()) {
      t->issue("speeds", fmt::format("found {}, expected a non-empty array of speeds > 0 (m/s)",
                                     describe(*n)));
    } else {
      const Range speed{[](double v) { return v > 0; }, "a speed > 0 (m/s)"};
      for (size_t i = 0; i < a->size(); ++i)
        if (const auto v = read_number(*a->get(i), at(t->key("speeds"), i), issues_, speed))
          s.speeds.push_back(*v);
    }
  }
  if (const auto e = t->integer("eigenvalues")) s.eigenvalues = *e;
  if (const auto c = t->boolean("critical_speed")) s.critical_speed = *c;
  if (const auto m = t->boolean("modes")) s.modes = *m;
  if (const auto c = t->choice("normal_control"))
    s.normal_control = *c == "force" ? physics::StabilitySettings::NormalControl::force
                                     : physics::StabilitySettings::NormalControl::displacement;
  if (const auto f = t->boolean("friction_shear")) s.friction_shear = *f;
  if (const auto x = t->number("target")) s.target = *x;
  if (const auto k = t->integer("state_step")) s.state_step = *k;
  p_.stability = s;

  // What the analysis needs of the case.
  // At the [stability] table's line, but for the key it names.
  const auto refuse = [&](std::string_view key, const std::string& why) {
    if (key.empty())
      root.issue("stability", why);
    else
      t->issue(key, why);
  };
  if (p_.time.scheme != physics::Scheme::quasistatic)
    refuse("",
           "found time.scheme = \"dynamic\", expected \"quasistatic\": the stability "
           "analysis linearises the quasistatic problem (inertia matters near the wave "
           "speeds only)");
  const int steps = p_.time.step > 0 ? static_cast<int>(std::round(p_.time.end / p_.time.step)) : 0;
  if (steps > 0 && s.state_step > steps)
    refuse("state_step", fmt::format("found {}, expected a step of the case, at most its {} "
                                     "steps",
                                     s.state_step, steps));
  if (p_.contacts.size() != 1) {
    refuse("", fmt::format("found {} contact pairs, expected one [contact] pair whose master is a "
                           "rigid tool",
                           p_.contacts.size()));
    return;
  }
  const auto& c = p_.contacts.front();
  if (!c.rigid_master) {
    refuse("",
           "found a contact pair of two bodies, expected a rigid tool as the master "
           "(contact.master = { rigid = \"plane\", … }): a body pair's contact pattern "
           "moves over both meshes, so its linearisation is not autonomous");
    return;
  }
  if (c.rigid_master->temperature && c.heat_conduction)
    refuse("",
           "found a rigid tool with a temperature and heat_conduction = true, expected an "
           "adiabatic tool (no contact.master.temperature) or heat_conduction = false: the "
           "conductance across the interface is not linearised");
  const double at = s.state_step * p_.time.step;
  const auto v = physics::sliding_velocity(*c.rigid_master, p_.dimension, at);
  if (!(std::hypot(v[0], v[1], v[2]) > 0))
    refuse("", fmt::format("found no sliding: the rigid tool of contact '{}' does not move along "
                           "its plane after the state's step {} (t = {:g} s), expected a "
                           "contact.master.velocity (or displacement) with a component along "
                           "the plane",
                           c.name, s.state_step, at));
}

}  // namespace tc::io::detail
