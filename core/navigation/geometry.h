// Plane geometry for the floor plan: points, poses, segments, boxes, polygons. Metres and
// radians; x east, y north, heading 0 = east, counter-clockwise positive.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

namespace marvin::navigation {

inline constexpr double kPi = 3.14159265358979323846;

struct Vec2 {
  double x = 0, y = 0;
};
inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(Vec2 a, double k) { return {a.x * k, a.y * k}; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double length(Vec2 a) { return std::hypot(a.x, a.y); }
inline double distance(Vec2 a, Vec2 b) { return length(a - b); }

struct Pose {
  double x = 0, y = 0, heading = 0;  // heading in radians
  Vec2 position() const { return {x, y}; }
};

// Wraps an angle into (-pi, pi].
inline double wrap_angle(double a) {
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}

struct Segment {
  Vec2 a, b;
  double height = 2.5;  // metres above the floor
};

// An axis-aligned box standing on the floor (furniture, clutter).
struct Box {
  Vec2 min, max;
  double height = 0.5;
  bool contains(Vec2 p) const {
    return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y;
  }
  // The four sides, counter-clockwise.
  void sides(Segment out[4]) const {
    out[0] = {{min.x, min.y}, {max.x, min.y}, height};
    out[1] = {{max.x, min.y}, {max.x, max.y}, height};
    out[2] = {{max.x, max.y}, {min.x, max.y}, height};
    out[3] = {{min.x, max.y}, {min.x, min.y}, height};
  }
};

// Distance from p to segment ab.
inline double point_segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  Vec2 e = b - a;
  double len2 = dot(e, e);
  double u = len2 > 0 ? dot(p - a, e) / len2 : 0;
  u = std::fmax(0.0, std::fmin(1.0, u));
  return distance(p, a + e * u);
}

// Distance along the ray o + t d (t >= 0, d a unit vector) to segment ab, or +inf.
inline double ray_segment(Vec2 o, Vec2 d, Vec2 a, Vec2 b) {
  Vec2 e = b - a;
  double denom = cross(d, e);
  if (std::fabs(denom) < 1e-12) return std::numeric_limits<double>::infinity();
  Vec2 w = a - o;
  double t = cross(w, e) / denom;
  double u = cross(w, d) / denom;
  if (t < 0 || u < 0 || u > 1) return std::numeric_limits<double>::infinity();
  return t;
}

// True when segments pq and ab cross or touch.
inline bool segments_intersect(Vec2 p, Vec2 q, Vec2 a, Vec2 b) {
  auto orient = [](Vec2 o, Vec2 s, Vec2 t) { return cross(s - o, t - o); };
  double d1 = orient(a, b, p), d2 = orient(a, b, q), d3 = orient(p, q, a), d4 = orient(p, q, b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  auto on = [](Vec2 o, Vec2 s, Vec2 t) {
    return std::fmin(o.x, s.x) - 1e-12 <= t.x && t.x <= std::fmax(o.x, s.x) + 1e-12 &&
           std::fmin(o.y, s.y) - 1e-12 <= t.y && t.y <= std::fmax(o.y, s.y) + 1e-12;
  };
  return (d1 == 0 && on(a, b, p)) || (d2 == 0 && on(a, b, q)) || (d3 == 0 && on(p, q, a)) ||
         (d4 == 0 && on(p, q, b));
}

// Even-odd point-in-polygon test.
inline bool polygon_contains(const std::vector<Vec2>& poly, Vec2 p) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
      inside = !inside;
  }
  return inside;
}

// Area-weighted centroid of a simple polygon.
inline Vec2 polygon_centroid(const std::vector<Vec2>& poly) {
  double area = 0, cx = 0, cy = 0;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    double c = cross(poly[j], poly[i]);
    area += c;
    cx += (poly[j].x + poly[i].x) * c;
    cy += (poly[j].y + poly[i].y) * c;
  }
  if (std::fabs(area) < 1e-12) return poly.empty() ? Vec2{} : poly[0];
  return {cx / (3 * area), cy / (3 * area)};
}

}  // namespace marvin::navigation
