// Exact geometry of the 2-D world: ray/box by the slab method, ray/disc by the quadratic,
// body/box overlap by the separating-axis test, and body/box distance from vertices (the nearest
// points of two disjoint convex polygons include a vertex of one of them).
#include "robot/world/world.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace keel::robot {
namespace {

struct Vec {
  double x;
  double y;
};

/// Distance along the unit ray (o, d) to box b, or max_m if it misses within max_m.
double rayBox(Vec o, Vec d, const Box& b, double max_m) {
  double t_in = 0.0, t_out = max_m;
  const auto slab = [&](double origin, double dir, double lo, double hi) {
    if (dir == 0.0) return origin >= lo && origin <= hi;  // parallel to this slab
    double ta = (lo - origin) / dir, tb = (hi - origin) / dir;
    if (ta > tb) std::swap(ta, tb);
    t_in = std::max(t_in, ta);
    t_out = std::min(t_out, tb);
    return t_in <= t_out;
  };
  if (!slab(o.x, d.x, b.min_x, b.max_x) || !slab(o.y, d.y, b.min_y, b.max_y)) return max_m;
  return t_in;
}

/// Distance along the unit ray (o, d) to the target disc, or max_m if it misses within max_m.
double rayDisc(Vec o, Vec d, const Target& t, double max_m) {
  const Vec p{o.x - t.x_m, o.y - t.y_m};
  const double c = p.x * p.x + p.y * p.y - t.radius_m * t.radius_m;
  if (c <= 0.0) return 0.0;  // inside
  const double b = p.x * d.x + p.y * d.y;
  const double disc = b * b - c;
  if (disc < 0.0) return max_m;
  const double hit = -b - std::sqrt(disc);
  return hit < 0.0 ? max_m : std::min(hit, max_m);
}

/// The robot body as an oriented rectangle.
struct Body {
  Vec centre;
  Vec u;  // unit, along heading
  Vec v;  // unit, to the left
  double half_length;
  double half_width;

  [[nodiscard]] std::array<Vec, 4> corners() const {
    std::array<Vec, 4> out{};
    const double sl[4] = {1, 1, -1, -1}, sw[4] = {1, -1, -1, 1};
    for (std::size_t i = 0; i < 4; ++i) {
      out[i] = {centre.x + sl[i] * half_length * u.x + sw[i] * half_width * v.x,
                centre.y + sl[i] * half_length * u.y + sw[i] * half_width * v.y};
    }
    return out;
  }
};

Body makeBody(double x, double y, double heading, double length, double width) {
  const double c = std::cos(heading), s = std::sin(heading);
  return Body{{x, y}, {c, s}, {-s, c}, length / 2, width / 2};
}

/// Separating-axis test: true when the body and the box share interior (touching is not).
bool overlaps(const Body& body, const Box& b) {
  const double hx = (b.max_x - b.min_x) / 2, hy = (b.max_y - b.min_y) / 2;
  const Vec gap{(b.min_x + b.max_x) / 2 - body.centre.x, (b.min_y + b.max_y) / 2 - body.centre.y};
  const std::array<Vec, 4> axes{Vec{1, 0}, Vec{0, 1}, body.u, body.v};
  for (const Vec& n : axes) {
    const double r_body = body.half_length * std::abs(body.u.x * n.x + body.u.y * n.y) +
                          body.half_width * std::abs(body.v.x * n.x + body.v.y * n.y);
    const double r_box = hx * std::abs(n.x) + hy * std::abs(n.y);
    if (std::abs(gap.x * n.x + gap.y * n.y) >= r_body + r_box) return false;
  }
  return true;
}

/// Distance from point p to the solid axis-aligned rectangle [lo_x, hi_x] × [lo_y, hi_y].
double pointToRect(Vec p, double lo_x, double lo_y, double hi_x, double hi_y) {
  const double dx = std::max({lo_x - p.x, 0.0, p.x - hi_x});
  const double dy = std::max({lo_y - p.y, 0.0, p.y - hi_y});
  return std::hypot(dx, dy);
}

double distance(const Body& body, const Box& b) {
  if (overlaps(body, b)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (const Vec& c : body.corners()) {
    best = std::min(best, pointToRect(c, b.min_x, b.min_y, b.max_x, b.max_y));
  }
  const std::array<Vec, 4> box_corners{Vec{b.min_x, b.min_y}, Vec{b.max_x, b.min_y}, Vec{b.max_x, b.max_y},
                                       Vec{b.min_x, b.max_y}};
  for (const Vec& c : box_corners) {  // in the body's frame the body is axis-aligned
    const Vec rel{c.x - body.centre.x, c.y - body.centre.y};
    const Vec local{rel.x * body.u.x + rel.y * body.u.y, rel.x * body.v.x + rel.y * body.v.y};
    best = std::min(best, pointToRect(local, -body.half_length, -body.half_width, body.half_length, body.half_width));
  }
  return best;
}

}  // namespace

World::World(std::vector<Box> boxes, Target target, Pose start)
    : boxes_(std::move(boxes)), target_(target), start_(start) {}

World World::paperArena() {
  constexpr double kWall = 0.1;  // walls lie outside the 4 × 3 m interior
  std::vector<Box> boxes{
      {-kWall, -kWall, 4.0 + kWall, 0.0},       // south
      {-kWall, 3.0, 4.0 + kWall, 3.0 + kWall},  // north
      {-kWall, 0.0, 0.0, 3.0},                  // west
      {4.0, 0.0, 4.0 + kWall, 3.0},             // east
      {1.4, 1.55, 1.7, 2.1},                    // A: clips the straight drive's left side, target still visible
      {2.4, 0.3, 2.7, 0.8},                     // B: well below the line of sight
      {2.6, 2.3, 2.9, 2.8},                     // C: well above it, near the target
  };
  return World(std::move(boxes), Target{3.5, 1.5, 0.12, Rgb{220, 30, 30}}, Pose{0.4, 1.5, 0.0});
}

RayHits World::castRay(double x_m, double y_m, double heading_rad, double max_m) const {
  const Vec o{x_m, y_m}, d{std::cos(heading_rad), std::sin(heading_rad)};
  RayHits hits{max_m, rayDisc(o, d, target_, max_m)};
  for (const Box& b : boxes_) hits.box_m = std::min(hits.box_m, rayBox(o, d, b, hits.box_m));
  return hits;
}

double World::rayCast(double x_m, double y_m, double heading_rad, double max_m) const {
  return castRay(x_m, y_m, heading_rad, max_m).nearest();
}

bool World::collides(double x_m, double y_m, double heading_rad, double length_m, double width_m) const {
  const Body body = makeBody(x_m, y_m, heading_rad, length_m, width_m);
  return std::any_of(boxes_.begin(), boxes_.end(), [&](const Box& b) { return overlaps(body, b); });
}

double World::clearance(double x_m, double y_m, double heading_rad, double length_m, double width_m) const {
  const Body body = makeBody(x_m, y_m, heading_rad, length_m, width_m);
  double best = std::numeric_limits<double>::infinity();
  for (const Box& b : boxes_) best = std::min(best, distance(body, b));
  return best;
}

RayCast sonarRayCast(const World& world) {
  return [world](double x_m, double y_m, double heading_rad) {
    return 100.0 * world.rayCast(x_m, y_m, heading_rad, kMaxRangeCm / 100.0);
  };
}

}  // namespace keel::robot
