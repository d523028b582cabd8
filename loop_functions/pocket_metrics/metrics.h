// The performance criteria of seed 004 (4.2: equations 4.5-4.8) and its
// swarm figures (5.2-5.3: equations 5.1-5.4), as pure functions on pocket
// centres in the structure's frame, so they can be checked by hand. Used by
// the pocket_metrics loop functions (pocket_metrics.cpp); see README.md.
//
// The structure's frame: `along` is the position along the boundary (the
// seed's x in 4.2), from 0 at one end of the template to `length` at the
// other; `across` is the signed distance from the boundary line (the seed's
// y in 4.2). Metres and seconds throughout.
#pragma once

#include <cstddef>
#include <optional>
#include <span>

#include "core/math.h"

namespace colony::pockets {

// The boundary as the template landmarks give it: the straight line through
// them (least squares when there are more than two) and their extent on it.
struct StructureFrame {
  Vec2 origin = Vec2::Zero();  // the end of the template where along = 0
  Vec2 axis = Vec2::UnitX();   // unit vector along the boundary
  double length = 0;           // extent of the landmarks along the axis (m)
  // (along, across) of the world point `p` (x, y).
  Vec2 ToFrame(const Vec2& p) const;
  // Distance (m) from `p` to the boundary segment [0, length] on the axis.
  double DistanceToSegment(const Vec2& p) const;
};

// The frame of the landmarks at `points` (x, y), or nothing when they do not
// span a line (fewer than two, or all within 1 mm of each other). The axis
// points from the first landmark's end to the other's.
std::optional<StructureFrame> FrameThrough(std::span<const Vec2> points);

// The default kernel bandwidth (m): the standard deviation along the length
// of a pocket's own footprint, 12 cm / sqrt(12) = 3.46 cm (README.md says
// why; the seed gives no value).
double DefaultBandwidth();

// Uniformity deviation u_d(n), equations 4.5-4.6: (1 / 2A) times the
// integral over [a, b] of |f_h(x) - f_u(x)|, where f_h is the univariate
// kernel density of `along` with a normal kernel (4.4) of bandwidth `h`
// (4.1-4.2 with d = 1, H = h^2), A its integral over [a, b], and f_u the
// uniform density A / (b - a). In [0, 1]; 0 is perfectly uniform. Needs at
// least one pocket, b > a and h > 0.
double UniformityDeviation(std::span<const double> along, double a, double b, double h);

// Integrity deviation i_d(n), equation 4.7: the sample standard deviation
// (n - 1 in the denominator) of `across` (m). 0 for fewer than two pockets.
double IntegrityDeviation(std::span<const double> across);

// Maximum gap d_m(n), equation 4.8: the largest distance along the length
// between two adjacent pockets (centre to centre, m). The ends of the
// structure are not pockets and do not count. 0 for fewer than two pockets.
double MaximumGap(std::span<const double> along);

// Average iteration time xi_c(m) (5.2): construction time t_c(n) over the
// n pockets deposited (s).
double AverageIterationTime(double construction_time, size_t deposited);
// Ideal average iteration time xi_d(m) = xi_c(1) / m, equation 5.1 (s).
double IdealIterationTime(double single_robot_iteration_time, size_t robots);
// Swarm density rho_s = pi R^2 m / A_a, equation 5.2.
double SwarmDensity(double robot_radius, size_t robots, double arena_area);
// Efficiency eta_s = 1 - (xi_c(m) / xi_d(1) - xi_d(m) / xi_d(1)), equations
// 5.3-5.4, with xi_d(1) = xi_c(1) = `single_robot_iteration_time`.
double Efficiency(double iteration_time, double single_robot_iteration_time, size_t robots);

}  // namespace colony::pockets
