#include "tc/model/rigid_tool.hpp"

#include <algorithm>
#include <cmath>

#include "tc/core/error.hpp"
#include "tc/mesh/box.hpp"

namespace tc::physics {

namespace {

using Vec = std::array<double, 3>;

double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double norm(const Vec& a) {
  return std::sqrt(dot(a, a));
}

/// The largest |d(t)| of a displacement given per component: piecewise linear, so at the
/// tables' points (and t = 0, where a constant component has its value).
double largest_travel(const std::array<TimeTable, 3>& d) {
  std::vector<double> times{0.0};
  for (const auto& c : d) times.insert(times.end(), c.times().begin(), c.times().end());
  double most = 0;
  for (const double t : times) most = std::max(most, norm({d[0](t), d[1](t), d[2](t)}));
  return most;
}

/// The largest travel any displacement support of body b prescribes (free components 0).
double largest_support_travel(const Problem& p, int b) {
  double most = 0;
  for (const auto& bc : p.boundaries) {
    if (bc.body != b) continue;
    std::array<TimeTable, 3> d{};
    for (int k = 0; k < 3; ++k)
      if (bc.displacement[k]) d[k] = *bc.displacement[k];
    most = std::max(most, largest_travel(d));
  }
  return most;
}

/// The rotation whose last column (3D) or second column (2D) is n: the box's face (zmax, ymax)
/// is carried into the plane, keeping its outward normal and the cells' orientation
/// (det = +1).
std::array<std::array<double, 3>, 3> rotation_onto(const Vec& n, int dim) {
  if (dim == 2) {
    const Vec t{n[1], -n[0], 0};  // t × n = +1
    return {{{t[0], n[0], 0}, {t[1], n[1], 0}, {0, 0, 1}}};
  }
  const Vec seed = std::abs(n[0]) < 0.9 ? Vec{1, 0, 0} : Vec{0, 1, 0};
  Vec t1 = cross(seed, n);
  const double l = norm(t1);
  for (auto& x : t1) x /= l;
  const Vec t2 = cross(n, t1);  // (t1, t2, n) right-handed
  return {{{t1[0], t2[0], n[0]}, {t1[1], t2[1], n[1]}, {t1[2], t2[2], n[2]}}};
}

/// The tool's body for pair c: one cell behind the plane, its face around the slave's shadow.
Body tool_body(const Problem& p, const ContactSettings& c, const RigidTool& tool) {
  const int dim = p.dimension;
  const auto& slave = p.bodies.at(static_cast<size_t>(c.slave_body));
  const Vec n = unit_normal(tool.normal, dim);
  // The slave surface's shadow on the plane: its centre and radius.
  const auto nodes = slave.mesh.boundary_nodes(c.slave_where);
  if (nodes.empty())
    throw Error("rigid tool: the slave surface \"" + c.slave_where + "\" is empty");
  std::vector<Vec> shadow;
  for (const int a : nodes) {
    Vec x = slave.mesh.point(a);
    Vec r{x[0] - tool.point[0], x[1] - tool.point[1], x[2] - tool.point[2]};
    const double h = dot(r, n);
    for (int i = 0; i < 3; ++i) x[i] -= h * n[i];
    shadow.push_back(x);
  }
  Vec centre{0, 0, 0};
  for (const auto& x : shadow)
    for (int i = 0; i < 3; ++i) centre[i] += x[i] / static_cast<double>(shadow.size());
  double radius = 0;
  for (const auto& x : shadow)
    radius = std::max(radius, norm({x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]}));
  const double travel = largest_travel(tool.motion) + largest_support_travel(p, c.slave_body);
  const double a = 4 * (radius + travel) + (radius + travel == 0 ? 1.0 : 0.0);
  Body b;
  b.name = rigid_tool_name(c);
  b.rigid_tool = true;
  b.material_name = slave.material_name;
  b.material = slave.material;
  b.material.density = 0;  // no kinetic energy, no heat capacity: nothing in the energies
  // Local frame: the face at z = 0 (y = 0 in 2D), the cell behind it.
  b.mesh = dim == 2 ? mesh::make_box(2, {-a, -a, 0}, {a, 0, 0}, {1, 1, 1})
                    : mesh::make_box(3, {-a, -a, -a}, {a, a, 0}, {1, 1, 1});
  const char* face = dim == 2 ? "ymax" : "zmax";
  const char* back = dim == 2 ? "ymin" : "zmin";
  for (const auto& f : b.mesh.boundary(face)) {
    b.mesh.add_facet(kRigidToolFace, f);
    b.mesh.add_facet(kRigidToolHeld, f);
  }
  for (const auto& f : b.mesh.boundary(back)) b.mesh.add_facet(kRigidToolHeld, f);
  b.mesh.transform(rotation_onto(n, dim), centre);
  b.initial_temperature =
      tool.temperature ? (*tool.temperature)(0.0) : p.physics.reference_temperature;
  return b;
}

}  // namespace

std::string rigid_tool_name(const ContactSettings& c) {
  // A lone pair is named "contact" by default: its tool is plainly "tool".
  return c.name.empty() || c.name == "contact" ? "tool" : "tool_" + c.name;
}

std::array<double, 3> unit_normal(const std::array<double, 3>& normal, int dim) {
  Vec n = normal;
  if (dim == 2) n[2] = 0;
  const double l = norm(n);
  if (!(l > 0) || !std::isfinite(l)) throw Error("rigid tool: the plane's normal is zero");
  for (auto& x : n) x /= l;
  return n;
}

void place_rigid_tools(Problem& p) {
  for (auto& c : p.contacts) {
    if (!c.rigid_master || c.master_body >= 0) continue;
    const auto& tool = *c.rigid_master;
    p.bodies.push_back(tool_body(p, c, tool));
    c.master_body = static_cast<int>(p.bodies.size()) - 1;
    c.master_where = kRigidToolFace;
    BoundaryCondition held;
    held.body = c.master_body;
    held.where = kRigidToolHeld;
    for (int k = 0; k < p.dimension; ++k) held.displacement[k] = tool.motion[k];
    held.temperature = tool.temperature.value_or(TimeTable(p.physics.reference_temperature));
    p.boundaries.push_back(std::move(held));
    if (!tool.temperature) {  // adiabatic: every joule of frictional heat into the slave
      c.conductance_slave = 1.0;
      c.conductance_master = 0.0;
      c.heat_conduction = false;
    }
  }
}

namespace {

double slope_after(const core::TimeTable& table, double t) {
  const auto& x = table.times();
  const auto& v = table.values();
  for (size_t i = 0; i + 1 < x.size(); ++i)
    if (x[i] <= t && t < x[i + 1]) return (v[i + 1] - v[i]) / (x[i + 1] - x[i]);
  return 0.0;
}

}  // namespace

std::array<double, 3> sliding_velocity(const RigidTool& tool, int dim, double t) {
  const auto n = unit_normal(tool.normal, dim);
  std::array<double, 3> v{};
  for (int c = 0; c < dim; ++c) v[c] = slope_after(tool.motion[c], t);
  double vn = 0;
  for (int c = 0; c < dim; ++c) vn += v[c] * n[c];
  for (int c = 0; c < dim; ++c) v[c] -= vn * n[c];  // the motion along the plane only
  return v;
}

}  // namespace tc::physics
