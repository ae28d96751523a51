// SPDX-License-Identifier: LGPL-2.1-or-later
/// @file Vec.hpp
/// Small fixed-size vector types used everywhere in the core (no Eigen in hot paths).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>

namespace paramesh {

/// 2D point or vector, typically a (u,v) surface parameter.
struct Vec2 {
  double x = 0, y = 0;
  Vec2() = default;
  constexpr Vec2(double a, double b) : x(a), y(b) {}
  double& operator[](int i) { return i == 0 ? x : y; }
  double operator[](int i) const { return i == 0 ? x : y; }
};
inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline Vec2 operator*(Vec2 a, double s) { return {s * a.x, s * a.y}; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double norm(Vec2 a) { return std::sqrt(dot(a, a)); }

/// 3D point or vector.
struct Vec3 {
  double x = 0, y = 0, z = 0;
  Vec3() = default;
  constexpr Vec3(double a, double b, double c) : x(a), y(b), z(c) {}
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Vec3& operator+=(Vec3 o) { x += o.x; y += o.y; z += o.z; return *this; }
  Vec3& operator-=(Vec3 o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
};
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline Vec3 operator*(Vec3 a, double s) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm2(Vec3 a) { return dot(a, a); }
inline double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
inline double dist(Vec3 a, Vec3 b) { return norm(a - b); }
/// Distance from x to the segment (a, b).
inline double segmentDistance(Vec3 x, Vec3 a, Vec3 b) {
  const Vec3 e = b - a;
  const double l2 = dot(e, e);
  const double t = l2 > 0 ? std::clamp(dot(x - a, e) / l2, 0.0, 1.0) : 0.0;
  return norm(x - (a + t * e));
}
/// Unit vector along a; returns a unchanged when it is (numerically) zero.
inline Vec3 normalized(Vec3 a) {
  double n = norm(a);
  return n > 1e-300 ? a * (1.0 / n) : a;
}

/// Axis-aligned 3D box.
struct Box3 {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(Vec3 p) {
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::fmin(lo[i], p[i]);
      hi[i] = std::fmax(hi[i], p[i]);
    }
  }
  bool empty() const { return lo.x > hi.x; }
  double diagonal() const { return empty() ? 0.0 : norm(hi - lo); }
};

}  // namespace paramesh
