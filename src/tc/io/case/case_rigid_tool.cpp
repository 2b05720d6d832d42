// CaseReader: a contact pair's master as an analytic rigid tool (`master = { rigid = "plane",
// … }`), read into physics::RigidTool; the reader places its body once the case is valid
// (physics::place_rigid_tools).
#include <fmt/format.h>

#include <cmath>

#include "tc/io/case/case_reader_detail.hpp"
#include "tc/model/rigid_tool.hpp"

namespace tc::io::detail {

namespace {

constexpr std::string_view kToolKeys[] = {"rigid",    "point",        "normal",
                                          "velocity", "displacement", "temperature"};

}  // namespace

void CaseReader::refuse_tool_keys(const TableReader& s, std::string_view side) {
  for (const auto k : kToolKeys)
    if (s.has(k))
      s.issue(k, side == "slave"
                     ? fmt::format("found a rigid tool's key on the slave side; expected the "
                                   "slave to be a body's surface {{ body, where }} (a rigid "
                                   "tool can only be the master)")
                     : fmt::format("found a rigid tool's key without rigid = \"plane\"; "
                                   "expected {{ body, where }} for a body's surface, or "
                                   "rigid = \"plane\" with point and normal for a rigid tool"));
}

bool CaseReader::read_rigid_tool(const TableReader& s, physics::ContactSettings& c) {
  const size_t before = issues_.size();
  c.master_body = -1;
  c.master_where.clear();
  for (const auto* k : {"body", "where"})
    if (s.has(k))
      s.issue(k,
              "found a body's surface and rigid = \"plane\"; expected one of them (a rigid "
              "tool has no body)");
  (void)s.choice("rigid");  // "plane", the only shape yet
  physics::RigidTool tool;
  const auto read_vec = [&](std::string_view k) -> std::optional<std::array<double, 3>> {
    const auto* n = s.get(k);
    return n ? read_vector(*n, s.key(k), issues_, dim_) : std::nullopt;
  };
  if (const auto x = read_vec("point"))
    tool.point = *x;
  else if (!s.has("point"))
    s.issue("point", "missing; expected a point of the tool's plane at t = 0 [m]");
  if (const auto n = read_vec("normal")) {
    const int d = dim_ == 2 ? 2 : 3;
    double l2 = 0;
    for (int k = 0; k < d; ++k) l2 += (*n)[k] * (*n)[k];
    if (l2 > 0 && std::isfinite(l2))
      tool.normal = physics::unit_normal(*n, d);
    else
      s.issue("normal",
              "found a zero vector, expected the plane's normal out of the tool, "
              "towards the slave (any length > 0)");
  } else if (!s.has("normal")) {
    s.issue("normal", "missing; expected the plane's normal out of the tool, towards the slave");
  }
  if (s.has("velocity") && s.has("displacement"))
    s.issue("displacement", "found both a velocity and a displacement, expected one of them");
  else if (const auto v = read_vec("velocity")) {
    // d(t) = v t: linear through the run's end (the table is constant beyond its last time).
    const double end = p_.time.end > 0 ? p_.time.end : 1.0;
    for (int k = 0; k < 3; ++k)
      if ((*v)[k] != 0) tool.motion[k] = core::TimeTable({0.0, end}, {0.0, (*v)[k] * end});
  } else if (const auto* n = s.get("displacement")) {
    if (const auto d = read_components(*n, s.key("displacement"), issues_, dim_, false))
      for (int k = 0; k < 3; ++k)
        if ((*d)[k]) tool.motion[k] = *(*d)[k];
  }
  if (const auto* n = s.get("temperature"))
    tool.temperature = read_time_table(*n, s.key("temperature"), issues_, temperature());
  const auto name = physics::rigid_tool_name(c);
  for (const auto& b : p_.bodies)
    if (b.name == name)
      s.issue("rigid", fmt::format("found a body named \"{}\", the name the rigid tool's body "
                                   "takes; expected another name for that body (or another "
                                   "pair name)",
                                   name));
  c.rigid_master = tool;
  return issues_.size() == before;
}

void CaseReader::check_adiabatic_tool(const TableReader& contact) {
  for (const auto* k : {"conductance", "gap_conductance"})
    if (contact.has(k))
      contact.issue(
          k, fmt::format("found a {} for an adiabatic rigid tool (no temperature); "
                         "expected none (it takes no heat: all frictional heat goes "
                         "into the slave) or a temperature for the tool",
                         k == std::string_view("conductance") ? "conductance" : "gap conductance"));
}

}  // namespace tc::io::detail
