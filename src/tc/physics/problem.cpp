#include "tc/physics/problem.hpp"

#include <cmath>

namespace tc::physics {

std::string combined_contact_dual_unavailable(const Problem& p) {
  if (!p.contact) return "the case has no [contact]";
  if (p.time.scheme != Scheme::Quasistatic)
    return "[time] scheme is \"dynamic\" (the combined dual is quasistatic only: the "
           "subdomains' rigid motions enter through Gλ = e)";
  for (const int b : {p.contact->slave_body, p.contact->master_body})
    if (p.bodies[static_cast<size_t>(b)].subdomains < 2)
      return "contact body \"" + p.bodies[static_cast<size_t>(b)].name +
             "\" is not decomposed (subdomains = 1; the combined dual needs TFETI on both)";
  return "";
}

int TimeSettings::n_steps() const {
  return static_cast<int>(std::lround(end / step));
}

}  // namespace tc::physics
