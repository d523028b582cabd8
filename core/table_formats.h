// The formats behind core/table_writer.h's tables: what a table writes to
// (Table::Sink; the CSV sinks are in table_writer.cpp), and HDF5, written and
// read by the plugin colony_hdf5 (core/hdf5/), which libcolony loads the
// first time something opens an HDF5 table. A process that writes and reads
// no HDF5 (a run with CSV output, `colony version`, a sweep's workers) then
// never loads libhdf5 and the 29 other libraries it brings, which cost some 5 ms
// at every start-up.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/table_writer.h"

namespace colony {

// What a table writes to: cells in column order, then EndRow. Every write
// is checked: a failure throws RuntimeFailure naming the file.
class Table::Sink {
 public:
  virtual ~Sink() = default;
  virtual void Integer(size_t column, int64_t value) = 0;
  virtual void Number(size_t column, double value) = 0;
  virtual void Text(size_t column, std::string_view value) = 0;
  virtual void Missing(size_t column) = 0;
  virtual void EndRow() = 0;
  virtual void Flush() = 0;
  virtual void Close() = 0;
  const std::string& path() const { return path_; }

 protected:
  explicit Sink(std::string path) : path_(std::move(path)) {}
  std::string path_;
};

// gzip and HDF5 deflate level: the fastest. The simulation waits while a
// table is compressed; level 6 makes a trajectories CSV 8% smaller in 6
// times the time.
constexpr int kTableGzipLevel = 1;

// Creates the folder `path` goes in. Throws RuntimeFailure.
void CreateFolderOf(const std::string& path);

// One column of an HDF5 table as read: whether the dataset has it, and its
// cells in the vector of its type (the others stay empty).
struct Hdf5Column {
  bool present = false;
  std::vector<int64_t> integers;
  std::vector<double> numbers;
  std::vector<std::string> texts;
};

// HDF5 tables (the plugin's side).
struct Hdf5Tables {
  // A sink writing the table `path` (one dataset named as the file without
  // its ending, of a compound type), deflate-compressed when `compress`.
  std::unique_ptr<Table::Sink> (*make_sink)(const std::string& path,
                                            const std::vector<TableColumn>& columns, bool compress);
  // Reads the columns `wanted` (by name; integers, numbers or text) of the
  // one-dimensional dataset of a compound type `dataset` in the file
  // `path`, converting what HDF5 can convert; one Hdf5Column per wanted
  // column into `out`, not present when the dataset has none of that name.
  // Returns the number of rows. A file that cannot be read, a dataset that
  // is missing or not such a table, a text column that is not text or a
  // cell that cannot be converted throw RuntimeFailure saying which (not
  // naming the file: the caller does).
  size_t (*read_columns)(const std::string& path, const std::string& dataset,
                         const std::vector<TableColumn>& wanted, std::vector<Hdf5Column>& out);
};

// The plugin's registrar: called while libcolony loads it.
void SetHdf5Tables(const Hdf5Tables* tables);

// HDF5 tables, the plugin loaded on the first call (thread-safe). Throws
// RuntimeFailure when it is not there or fails to load, saying where it was
// looked for and why.
const Hdf5Tables& Hdf5();

}  // namespace colony
