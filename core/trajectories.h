// The trajectories table of a run (<output trajectories_every="K"
// format="csv|hdf5" compress="gzip|none">): every K ticks, from tick 0, one
// row per robot alive, in slot order:
//   tick, time (s), id, type, x, y, z (m), yaw (rad)
//   pitch, roll (rad): in runs whose physics engines are 3D
//   led_r, led_g, led_b (0..255): with <output leds="true">, the colour it
//   shows (its first LED's, else its body colour)
//   then the robots' named values (core/control_interface.h, RobotValues):
//   those its controller gives (Controller::RecordValues), then those the
//   loop functions give (LoopFunctions::RecordRobotValues), in the order
//   they first appear. The columns are fixed at the first record; a robot
//   without a value in a column gets an empty cell (NaN or "" in HDF5).
// Written with core/table_writer.h to trajectories.csv, trajectories.csv.gz
// or trajectories.h5 (dataset "trajectories"; ids and types in fixed-width
// strings, the id's the longest id of the first record plus 8 bytes) in the
// run folder; layouts in docs/data-output.md. Reading the space and asking for values changes
// nothing, so the state hash is the same with trajectories on or off; with
// them off nothing of this runs.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/experiment_spec.h"
#include "core/table_writer.h"

namespace colony {

class Simulation;

class Trajectories {
 public:
  // The table's file name: trajectories.csv, trajectories.csv.gz or
  // trajectories.h5.
  static std::string FileName(const OutputConfig& output);

  // The table in folder `dir`, for `sim`'s <output>; nothing is written
  // before the first Record.
  Trajectories(const std::string& dir, const Simulation& sim);
  ~Trajectories();

  // One row per robot for the current tick. At the first record, a value
  // name that is one of the table's own columns, given twice for one robot,
  // or as a number by one and a label by another throws ConfigError naming
  // it and who gave it; later, such a name or one that is not a column
  // throws RuntimeFailure, as does a RecordValues that throws.
  void Record(Simulation& sim);
  // Writes everything out and closes. Throws RuntimeFailure.
  void Close();
  const std::string& path() const { return path_; }

  class Values;  // the RobotValues a robot's row is collected in

 private:
  // Asks `slot`'s controller, then the loop functions, for its values.
  void Ask(Simulation& sim, uint32_t slot);
  void WriteRow(const Simulation& sim, uint32_t slot);
  // Fixes the columns from the first record's values and opens the table.
  void Open(const Simulation& sim, size_t longest_id);

  std::string path_;
  OutputConfig output_;
  bool three_d_ = false;  // pitch and roll columns
  // HDF5: the widths of the id and type columns (0: CSV).
  size_t id_width_ = 0, type_width_ = 0;
  Table table_;
  std::unique_ptr<Values> values_;
  // Who gives values, as messages name them: per controller label
  // ("controller 'x'"), per loop functions ("loop functions 'y'").
  std::vector<std::pair<const std::string*, std::string>> controller_sources_;
  std::vector<std::string> loop_sources_;
};

}  // namespace colony
