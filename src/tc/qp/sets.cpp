#include "tc/qp/sets.hpp"

#include <mpi.h>

#include <algorithm>

#include "tc/core/verify.hpp"

namespace tc::qp {

namespace {
double all_min(double local, MPI_Comm comm) {
  double global = local;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MIN, comm);
  return global;
}
double all_max(double local, MPI_Comm comm) {
  double global = local;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, comm);
  return global;
}
std::array<double, 2> pair(std::span<const double> v, const DiscBlock& b) {
  return {v[b.first], v[b.second]};
}
/// The outward unit normal at a point on a circle of radius r > 0.
std::array<double, 2> unit(std::array<double, 2> x) {
  const double n = std::hypot(x[0], x[1]);
  return {x[0] / n, x[1] / n};
}
}  // namespace

FeasibleSet::FeasibleSet(const Vector& layout)
    : intervals_(static_cast<size_t>(layout.local_size())),
      in_disc_(static_cast<size_t>(layout.local_size()), 0) {}

void FeasibleSet::set_interval(PetscInt i, Interval iv) {
  // Written so that a NaN bound passes: it is reported by the finite checks with its step.
  TC_VERIFY(!(iv.lo > iv.hi), "an interval's lower bound is not above its upper one");
  intervals_.at(static_cast<size_t>(i)) = iv;
}

void FeasibleSet::add_disc(DiscBlock block) {
  TC_VERIFY(!(block.disc.r < 0) && block.first != block.second,
            "a friction disc has a radius and two distinct components");
  in_disc_.at(static_cast<size_t>(block.first)) = 1;
  in_disc_.at(static_cast<size_t>(block.second)) = 1;
  discs_.push_back(block);
}

bool FeasibleSet::chopped_step_may_leave() const {
  if (!discs_.empty()) return true;
  for (size_t i = 0; i < intervals_.size(); ++i)
    if (!in_disc_[i] && intervals_[i].hi < infinity) return true;
  return false;
}

void FeasibleSet::project(Vector& x) const {
  auto v = x.view();
  for (size_t i = 0; i < intervals_.size(); ++i)
    if (!in_disc_[i]) v[i] = intervals_[i].project(v[i]);
  for (const auto& b : discs_) {
    const auto p = b.disc.project({v[b.first], v[b.second]});
    v[b.first] = p[0];
    v[b.second] = p[1];
  }
}

double FeasibleSet::violation(const Vector& x) const {
  const auto r = x.read();
  const auto v = r.span();
  double worst = 0;
  for (size_t i = 0; i < intervals_.size(); ++i)
    if (!in_disc_[i]) worst = std::max({worst, intervals_[i].lo - v[i], v[i] - intervals_[i].hi});
  for (const auto& b : discs_) {
    const auto p = pair(v, b);
    worst = std::max(worst, std::hypot(p[0], p[1]) - b.disc.r);
  }
  return all_max(worst, x.comm());
}

void FeasibleSet::zero_fixed(Vector& v) const {
  auto vv = v.view();
  for (size_t i = 0; i < intervals_.size(); ++i)
    if (!in_disc_[i] && intervals_[i].lo == intervals_[i].hi) vv[i] = 0.0;
  for (const auto& b : discs_)
    if (b.disc.r == 0) vv[b.first] = vv[b.second] = 0.0;
}

void FeasibleSet::split_gradient(const Vector& x, const Vector& g, Vector& free, Vector& chopped,
                                 Vector& projected, bool slide) const {
  const auto rx = x.read();
  const auto rg = g.read();
  const auto xv = rx.span(), gv = rg.span();
  auto fv = free.view();
  auto cv = chopped.view();
  auto pv = projected.view();
  for (size_t i = 0; i < intervals_.size(); ++i) {
    if (in_disc_[i]) continue;
    const auto& iv = intervals_[i];
    const bool act = iv.active(xv[i]);
    fv[i] = act ? 0.0 : gv[i];
    cv[i] = act ? iv.chopped(xv[i], gv[i]) : 0.0;
    pv[i] = fv[i] + cv[i];
  }
  for (const auto& b : discs_) {
    const auto xp = pair(xv, b), gp = pair(gv, b);
    const bool act = b.disc.active(xp);
    auto c = act ? b.disc.chopped(xp, gp) : std::array<double, 2>{0.0, 0.0};
    fv[b.first] = act ? 0.0 : gp[0];
    fv[b.second] = act ? 0.0 : gp[1];
    if (slide && act && b.disc.r > 0) {
      // g^P = t + (g·n)⁺n with t the tangential part: t is free (the face is the circle),
      // only the inward normal part releases the node into the disc.
      const auto n = unit(xp);
      const double gn = gp[0] * n[0] + gp[1] * n[1];
      fv[b.first] = gp[0] - gn * n[0];
      fv[b.second] = gp[1] - gn * n[1];
      c = {std::max(gn, 0.0) * n[0], std::max(gn, 0.0) * n[1]};
    }
    cv[b.first] = c[0];
    cv[b.second] = c[1];
    pv[b.first] = fv[b.first] + c[0];
    pv[b.second] = fv[b.second] + c[1];
  }
}

double FeasibleSet::max_step(const Vector& x, const Vector& p, bool slide) const {
  const auto rx = x.read();
  const auto rp = p.read();
  const auto xv = rx.span(), pv = rp.span();
  double alpha = infinity;
  for (size_t i = 0; i < intervals_.size(); ++i)
    if (!in_disc_[i]) alpha = std::min(alpha, intervals_[i].max_step(xv[i], pv[i]));
  for (const auto& b : discs_) {
    if (slide && b.disc.r > 0 && b.disc.active(pair(xv, b))) continue;
    alpha = std::min(alpha, b.disc.max_step(pair(xv, b), pair(pv, b)));
  }
  return std::max(all_min(alpha, x.comm()), 0.0);
}

void FeasibleSet::add_circle_curvature(const Vector& x, const Vector& g, const Vector& p,
                                       Vector& y) const {
  const auto rx = x.read();
  const auto rg = g.read();
  const auto rp = p.read();
  const auto xv = rx.span(), gv = rg.span(), pv = rp.span();
  auto yv = y.view();
  for (const auto& b : discs_) {
    if (!(b.disc.r > 0) || !b.disc.active(pair(xv, b))) continue;
    const auto n = unit(pair(xv, b));
    const double mu = std::max(-(gv[b.first] * n[0] + gv[b.second] * n[1]), 0.0);
    yv[b.first] += mu / b.disc.r * pv[b.first];
    yv[b.second] += mu / b.disc.r * pv[b.second];
  }
}

bool FeasibleSet::moves_on_circles(const Vector& x, const Vector& p) const {
  const auto rx = x.read();
  const auto rp = p.read();
  const auto xv = rx.span(), pv = rp.span();
  double moves = 0;
  for (const auto& b : discs_)
    if (b.disc.r > 0 && (pv[b.first] != 0 || pv[b.second] != 0) && b.disc.active(pair(xv, b)))
      moves = 1;
  return all_max(moves, x.comm()) > 0;
}

void FeasibleSet::advance(Vector& x, const Vector& p, double alpha) const {
  const auto rp = p.read();
  const auto pv = rp.span();
  auto xv = x.view();
  // A component whose own maximal step is α (to round-off) is the one that blocked: it
  // lands on the boundary exactly instead of 1 ulp inside or outside it.
  const double reach = alpha * (1 + 1e-12);
  for (size_t i = 0; i < intervals_.size(); ++i) {
    if (in_disc_[i] || pv[i] == 0) continue;
    const auto& iv = intervals_[i];
    const double own = iv.max_step(xv[i], pv[i]);
    xv[i] = own <= reach ? (pv[i] > 0 ? iv.lo : iv.hi) : iv.project(xv[i] - alpha * pv[i]);
  }
  for (const auto& b : discs_) {
    const std::array<double, 2> xp{xv[b.first], xv[b.second]};
    const auto pp = pair(pv, b);
    if (pp[0] == 0 && pp[1] == 0) continue;
    std::array<double, 2> y{xp[0] - alpha * pp[0], xp[1] - alpha * pp[1]};
    if (b.disc.max_step(xp, pp) <= reach) {
      const double n = std::hypot(y[0], y[1]);
      if (n > 0) y = {y[0] * b.disc.r / n, y[1] * b.disc.r / n};
    }
    y = b.disc.project(y);
    xv[b.first] = y[0];
    xv[b.second] = y[1];
  }
}

void FeasibleSet::restrict_to_free(const Vector& x, Vector& v, bool slide) const {
  const auto rx = x.read();
  const auto xv = rx.span();
  auto vv = v.view();
  for (size_t i = 0; i < intervals_.size(); ++i)
    if (!in_disc_[i] && intervals_[i].active(xv[i])) vv[i] = 0;
  for (const auto& b : discs_) {
    if (!b.disc.active(pair(xv, b))) continue;
    if (slide && b.disc.r > 0) {
      const auto n = unit(pair(xv, b));
      const double vn = vv[b.first] * n[0] + vv[b.second] * n[1];
      vv[b.first] -= vn * n[0];
      vv[b.second] -= vn * n[1];
    } else {
      vv[b.first] = vv[b.second] = 0;
    }
  }
}

PetscInt FeasibleSet::count_active(const Vector& x) const {
  const auto rx = x.read();
  const auto xv = rx.span();
  PetscInt n = 0;
  for (size_t i = 0; i < intervals_.size(); ++i)
    if (!in_disc_[i] && intervals_[i].active(xv[i])) ++n;
  for (const auto& b : discs_)
    if (b.disc.active(pair(xv, b))) n += 2;
  PetscInt total = n;
  MPI_Allreduce(&n, &total, 1, MPIU_INT, MPI_SUM, x.comm());
  return total;
}

FeasibleSet FeasibleSet::scaled(const Vector& s) const {
  const auto rs = s.read();
  const auto sv = rs.span();
  if (sv.size() != intervals_.size())
    throw std::invalid_argument("FeasibleSet::scaled: the scaling has another layout");
  FeasibleSet out(s);
  for (size_t i = 0; i < intervals_.size(); ++i) {
    if (!(sv[i] > 0)) throw std::invalid_argument("FeasibleSet::scaled: a factor is not > 0");
    // ±∞ and 0 stay what they are; a finite bound moves with its component.
    out.intervals_[i] = {intervals_[i].lo / sv[i], intervals_[i].hi / sv[i]};
  }
  for (const auto& b : discs_) {
    const double sa = sv[b.first], sb = sv[b.second];
    if (std::abs(sa - sb) > 1e-12 * std::max(sa, sb))
      throw std::invalid_argument(
          "FeasibleSet::scaled: the two components of a disc need one factor");
    out.add_disc({b.first, b.second, {b.disc.r / sa}});
  }
  return out;
}

Vector FeasibleSet::jacobi_scaling(const Vector& diagonal) const {
  Vector s = diagonal.duplicate();
  {
    const auto rd = diagonal.read();
    const auto dv = rd.span();
    auto sv = s.view();
    for (size_t i = 0; i < intervals_.size(); ++i) {
      if (!(dv[i] > 0))
        throw std::invalid_argument("FeasibleSet::jacobi_scaling: a diagonal entry is not > 0");
      sv[i] = 1 / std::sqrt(dv[i]);
    }
    for (const auto& b : discs_)
      sv[b.first] = sv[b.second] = 1 / std::sqrt(std::sqrt(dv[b.first] * dv[b.second]));
  }
  return s;
}

}  // namespace tc::qp
