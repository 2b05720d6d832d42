#include "tc/model/problem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "tc/core/error.hpp"

namespace tc::physics {

std::string combined_contact_dual_unavailable(const Problem& p) {
  if (p.contacts.empty()) return "the case has no [contact]";
  if (p.contacts.size() > 1)
    return fmt::format("the case has {} contact pairs (the combined dual takes one)",
                       p.contacts.size());
  if (p.time.scheme != Scheme::quasistatic)
    return "[time] scheme is \"dynamic\" (the combined dual is quasistatic only: the "
           "subdomains' rigid motions enter through Gλ = e)";
  for (const int b : {p.contacts.at(0).slave_body, p.contacts.at(0).master_body})
    if (p.bodies[static_cast<size_t>(b)].subdomains < 2)
      return "contact body \"" + p.bodies[static_cast<size_t>(b)].name +
             "\" is not decomposed (subdomains = 1; the combined dual needs TFETI on both)";
  return "";
}

bool heat_before_mechanics(CouplingOrder order, bool thermoelastic_heating) {
  switch (order) {
    case CouplingOrder::heat_first:
      return true;
    case CouplingOrder::mechanics_first:
      return false;
    case CouplingOrder::automatic:
      break;
  }
  return !thermoelastic_heating;
}

int TimeSettings::n_steps() const {
  // The case reader caps end/step far below this; a Problem built in code could still overflow
  // the int (it wrapped round to a few or negative steps).
  const double n = std::round(end / step);
  if (!(n >= 0 && n <= std::numeric_limits<int>::max()))
    throw Error(fmt::format("time: end / step = {:g} / {:g} = {:g} steps, expected 0 to {}", end,
                            step, n, std::numeric_limits<int>::max()));
  return static_cast<int>(n);
}

}  // namespace tc::physics
