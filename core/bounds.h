// Upper bounds on what an experiment file may ask for. A typo such as
// size="1e9,1e9,1e9" or quantity="1e9" must be refused at load, naming the
// attribute and the bound, instead of exhausting the machine's memory or
// overflowing an integer. The bounds are far above what an experiment of 1 to
// 1,000,000 robots needs; docs/experiment-files.md lists them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

namespace colony {

// Largest arena side, and largest distance of the arena's centre from the
// origin, along each axis (m). 100 km: far beyond any swarm's arena, and
// positions keep sub-micrometre resolution in double precision.
constexpr double kMaxArenaExtent = 1e5;
// Most entities one <distribute> may create.
constexpr int64_t kMaxDistributeQuantity = 10'000'000;
// Most <ditch> elements in the floor (dynamics3d cuts the ground along
// every ditch edge: its work grows with the cube of the count).
constexpr int64_t kMaxDitches = 256;
// Most pixels of a floor image (16384 x 16384; 4 bytes each once decoded).
constexpr uint64_t kMaxFloorImagePixels = uint64_t{1} << 28;

// The space's index, a uniform grid over the arena, holds at most
// max(kMinGridCells, 4 x entities) cells, and never more than kMaxGridCells:
// past that its cells grow, so that a huge, nearly empty arena costs memory
// for its entities, not for its empty area. Up to the cap the cells keep
// their size, and so every result its neighbour queries give.
constexpr double kMinGridCells = 1 << 20;
constexpr double kMaxGridCells = 1 << 28;
inline double GridCellCap(size_t entities) {
  return std::clamp(4.0 * static_cast<double>(entities), kMinGridCells, kMaxGridCells);
}

// The cell size of a grid over a `wx` x `wy` rectangle: `cell` itself when
// it needs at most `max_cells` cells, else a larger size that does (grown
// by 1/16 at a time from an estimate). Either way the grid has at most
// max(max_cells, 1) cells, so nx and ny fit an int.
inline double CappedCellSize(double wx, double wy, double cell, double max_cells) {
  auto cells = [&](double c) { return std::ceil(wx / c) * std::ceil(wy / c); };
  if (cells(cell) <= max_cells) return cell;
  double c = std::max({cell, std::sqrt(wx * wy / max_cells), std::max(wx, wy) / max_cells});
  while (cells(c) > max_cells) c *= 1.0625;
  return c;
}

// Rough memory the simulation holds per entity once loaded (bytes): the
// space's arrays, the engine's and the spatial indexes' entries, and for a
// robot its controller and its devices' ordinary state (docs/benchmarks.md
// measures 1.5 to 4.6 kB per marXbot with kinematics2d). Devices holding
// more per robot (a camera's image) add their own figure: BytesPerRobot in
// core/device.h.
constexpr uint64_t kEstimatedBytesPerRobot = 4096;
constexpr uint64_t kEstimatedBytesPerEntity = 1024;

// The memory this process may use: the machine's physical memory, or the
// control group's limit when that is lower (bytes).
uint64_t AvailableMemoryBytes();

// "12.3 GB".
std::string FormatBytes(double bytes);

}  // namespace colony
