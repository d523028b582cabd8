// The two stochastic deposition rules of seed 004 (section 3.4.3, "Deploy")
// and the instantaneous coordinate system they are evaluated in, as pure
// functions of what the omnidirectional camera saw. Control-interface types
// only: they compile without the simulator, and tests call them directly.
//
// Units: metres, radians. "Body frame": x forwards, y to the robot's left.
#pragma once

#include <cmath>
#include <vector>

namespace colony::pocket_builder {

struct Point {
  double x = 0, y = 0;
};

// A blob seen at `distance` and `bearing` (camera), in the body frame.
inline Point FromPolar(double distance, double bearing) {
  return {distance * std::cos(bearing), distance * std::sin(bearing)};
}

// The instantaneous coordinate system (seed 004, 3.4.2, Fig. 3.4): its x axis
// points from the robot to the point p, the robot's projection on the closest
// boundary line; its y axis is x turned +90 degrees (along the boundary).
struct InstantFrame {
  double psi_p = 0;     // bearing of p in the body frame (rad)
  double distance = 0;  // from the robot to p: the robot's distance from the boundary line (m)
  // `q` (body frame) in this frame: C^{pb} q.
  Point ToInstant(const Point& q) const {
    const double c = std::cos(psi_p), s = std::sin(psi_p);
    return {c * q.x + s * q.y, -s * q.x + c * q.y};
  }
};

// The frame for the boundary line through landmarks `a` and `b` (body
// frame, distinct points).
inline InstantFrame FrameOfLine(const Point& a, const Point& b) {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const double ux = (b.x - a.x) / len, uy = (b.y - a.y) / len;
  const double t = -(a.x * ux + a.y * uy);
  const Point p{a.x + t * ux, a.y + t * uy};
  return {std::atan2(p.y, p.x), std::hypot(p.x, p.y)};
}

// n_f(delta), eq. 3.2: the visible pockets (instantaneous frame) whose
// y-component is within `delta` of the robot's.
inline int CountInfluential(const std::vector<Point>& pockets, double delta) {
  int n = 0;
  for (const Point& q : pockets) n += std::abs(q.y) <= delta ? 1 : 0;
  return n;
}

// Eq. 3.3: probability, per control step, of choosing the robot's current
// y-position along the boundary for the deposition, given n_f(delta_1).
inline double YDepositionProbability(int n_f, double k1, double alpha) {
  return k1 / (1.0 + alpha * alpha * static_cast<double>(n_f) * static_cast<double>(n_f));
}

// Eq. 3.4: mu_x(delta_2), the mean x-component (instantaneous frame) of the
// influential pockets, minus d_m, the distance from the robot's centre to the
// manipulator's. Sets `n_f` to n_f(delta_2); mu is 0 when it is 0.
inline double MeanInfluentialX(const std::vector<Point>& pockets, double delta2, double d_m,
                               int& n_f) {
  double sum = 0;
  n_f = 0;
  for (const Point& q : pockets) {
    if (std::abs(q.y) > delta2) continue;
    sum += q.x;
    ++n_f;
  }
  return n_f == 0 ? 0.0 : sum / n_f - d_m;
}

// Eq. 3.5: probability, per control step, of choosing the robot's current
// x-position (towards the boundary) for the deposition, given mu_x(delta_2).
inline double XDepositionProbability(double mu_x, double k2, double sigma) {
  return k2 * std::exp(-(mu_x * mu_x) / (sigma * sigma));
}

}  // namespace colony::pocket_builder
