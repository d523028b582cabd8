#include "loop_functions/pocket_metrics/metrics.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "entities/objects/pocket.h"

namespace colony::pockets {

Vec2 StructureFrame::ToFrame(const Vec2& p) const {
  const Vec2 d = p - origin;
  return Vec2(d.dot(axis), axis.x() * d.y() - axis.y() * d.x());
}

double StructureFrame::DistanceToSegment(const Vec2& p) const {
  const Vec2 f = ToFrame(p);
  const double beyond = f.x() < 0 ? -f.x() : std::max(0.0, f.x() - length);
  return std::hypot(beyond, f.y());
}

std::optional<StructureFrame> FrameThrough(std::span<const Vec2> points) {
  if (points.size() < 2) return std::nullopt;
  Vec2 mean = Vec2::Zero();
  for (const Vec2& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  // The principal axis of the points: the least-squares line through them.
  double sxx = 0, syy = 0, sxy = 0;
  for (const Vec2& p : points) {
    const Vec2 d = p - mean;
    sxx += d.x() * d.x();
    syy += d.y() * d.y();
    sxy += d.x() * d.y();
  }
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  Vec2 axis(std::cos(angle), std::sin(angle));
  if ((points.back() - points.front()).dot(axis) < 0) axis = -axis;
  double lo = 0, hi = 0;
  for (const Vec2& p : points) {
    const double t = (p - mean).dot(axis);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  if (hi - lo < 1e-3) return std::nullopt;
  return StructureFrame{mean + lo * axis, axis, hi - lo};
}

double DefaultBandwidth() { return pocket::kLength / std::sqrt(12.0); }

double UniformityDeviation(std::span<const double> along, double a, double b, double h) {
  const double n = static_cast<double>(along.size());
  // f_h at x (4.1, 4.2 and 4.4 with d = 1).
  const auto density = [&](double x) {
    double sum = 0;
    for (double xi : along) {
      const double u = (x - xi) / h;
      sum += std::exp(-0.5 * u * u);
    }
    return sum / (n * h * std::sqrt(2 * M_PI));
  };
  // A, the integral of f_h over [a, b], exactly (4.6).
  double mass = 0;
  for (double xi : along) {
    mass += 0.5 * (std::erf((b - xi) / (h * M_SQRT2)) - std::erf((a - xi) / (h * M_SQRT2)));
  }
  mass /= n;
  if (mass <= 0) return 1;
  const double uniform = mass / (b - a);
  // The integral of |f_h - f_u| by Simpson's rule on a grid much finer than
  // h (at least 64 steps per bandwidth, at least 4096 steps in all).
  const int steps = 2 * std::max(2048, static_cast<int>(std::ceil(32 * (b - a) / h)));
  const double dx = (b - a) / steps;
  double sum = 0;
  for (int k = 0; k <= steps; ++k) {
    const double w = (k == 0 || k == steps) ? 1 : (k % 2 ? 4 : 2);
    sum += w * std::abs(density(a + k * dx) - uniform);
  }
  return std::min(1.0, sum * dx / 3 / (2 * mass));
}

double IntegrityDeviation(std::span<const double> across) {
  if (across.size() < 2) return 0;
  double mean = 0;
  for (double y : across) mean += y;
  mean /= static_cast<double>(across.size());
  double sum = 0;
  for (double y : across) sum += (y - mean) * (y - mean);
  return std::sqrt(sum / static_cast<double>(across.size() - 1));
}

double MaximumGap(std::span<const double> along) {
  std::vector<double> sorted(along.begin(), along.end());
  std::sort(sorted.begin(), sorted.end());
  double gap = 0;
  for (size_t k = 1; k < sorted.size(); ++k) gap = std::max(gap, sorted[k] - sorted[k - 1]);
  return gap;
}

double AverageIterationTime(double construction_time, size_t deposited) {
  return construction_time / static_cast<double>(deposited);
}

double IdealIterationTime(double single_robot_iteration_time, size_t robots) {
  return single_robot_iteration_time / static_cast<double>(robots);
}

double SwarmDensity(double robot_radius, size_t robots, double arena_area) {
  return M_PI * robot_radius * robot_radius * static_cast<double>(robots) / arena_area;
}

double Efficiency(double iteration_time, double single_robot_iteration_time, size_t robots) {
  const double ideal = IdealIterationTime(single_robot_iteration_time, robots);
  return 1 - (iteration_time - ideal) / single_robot_iteration_time;
}

}  // namespace colony::pockets
