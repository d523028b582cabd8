// Tables of rows written into a run's folder, for loop functions and for the
// run's own output (trajectories): one writer, three formats, chosen by the
// file name's ending:
//   NAME.csv      CSV, RFC 4180: a field holding a comma, a quote, CR or LF is
//                 quoted, its quotes doubled; numbers as the shortest text
//                 that reads back as the same double (or with fixed digits)
//   NAME.csv.gz   the same CSV, gzip-compressed (zlib), as a series of gzip
//                 members (gzip, Python's gzip module and pandas read them as
//                 one stream)
//   NAME.h5       HDF5 (the C API of libhdf5): one extendible, chunked
//                 dataset NAME of a compound type, one field per column
//                 (integers int64, numbers float64, text UTF-8 strings of
//                 variable or fixed length), optionally deflate-compressed
// What is on disk is whole rows only, written out at least once a second: a
// plain CSV keeps its rows across a crash of the process (the crash handler
// writes them); gzip members and HDF5 batches written before a crash are
// whole, the rows of the last second are lost with them. Every write is
// checked: a failure throws RuntimeFailure naming the file and the reason.
//
// Loop functions open their tables with Table::InRunFolder: the file goes
// into the run's folder (Simulation::run_folder()), so the runs of a sweep
// never share a file. A simulation without a run folder (colony_bench, a
// test or program that gives none) gets a table that writes nowhere: its
// calls do nothing and writing() is false. Nothing is ever written to the
// current directory.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace colony {

class Simulation;

// Appends `field` to `line` as one CSV field (RFC 4180): as it is, or in
// double quotes with each quote doubled when it holds a comma, a quote, CR
// or LF.
void AppendCsvField(std::string& line, std::string_view field);

// Appends `value` to `line`: the shortest text that reads back as the same
// double when `digits` is 0, else `digits` significant digits (%g style);
// "nan", "inf", "-inf" for those (pandas and Python's float() read them).
void AppendNumber(std::string& line, double value, int digits = 0);

enum class ColumnType {
  kInteger,  // int64
  kNumber,   // double
  kText,     // a string (a state name, a label...)
};

struct TableColumn {
  std::string name;
  ColumnType type = ColumnType::kNumber;
  // kNumber in CSV: significant digits; 0: the shortest text that reads
  // back as the same double. HDF5 stores the double itself.
  int digits = 0;
  // kText in HDF5: 0 stores variable-length strings; > 0 strings of
  // exactly `width` bytes, NUL-padded (smaller, faster to read; a longer
  // value throws RuntimeFailure). CSV ignores it.
  size_t width = 0;
};

struct TableOptions {
  // HDF5: chunks deflate-compressed (after the shuffle filter). CSV: name the file
  // .csv.gz instead.
  bool compress = false;
};

class Table {
 public:
  // A table that writes nowhere.
  Table();
  ~Table();
  Table(Table&&) noexcept;
  Table& operator=(Table&&) noexcept;

  // A table written to `path`, in the format its ending names (.csv,
  // .csv.gz, .h5 or .hdf5; anything else throws std::invalid_argument
  // naming what is accepted). Column names must be distinct and not empty
  // (std::invalid_argument). The file (and its folder) is created at the
  // first write, replacing any file of that name, so a run that fails to
  // load leaves nothing behind.
  static Table Create(const std::string& path, std::vector<TableColumn> columns,
                      const TableOptions& options = {});
  // A table named `name` relative to `sim`'s run folder ("pockets.csv",
  // "robots/tracks.h5"); a name that is absolute or climbs out of the
  // folder ("..") throws std::invalid_argument. No run folder: a table
  // that writes nowhere.
  static Table InRunFolder(const Simulation& sim, const std::string& name,
                           std::vector<TableColumn> columns, const TableOptions& options = {});

  // Whether rows go anywhere.
  bool writing() const { return sink_ != nullptr; }
  const std::string& path() const;
  const std::vector<TableColumn>& columns() const { return columns_; }

  // The cells of a row, in column order, then EndRow. A cell of the wrong
  // type, too many or too few cells, or Missing in an integer column throw
  // std::logic_error naming the table and the column.
  Table& Integer(int64_t value);
  Table& Number(double value);
  Table& Text(std::string_view value);
  // No value: an empty CSV field; in HDF5 NaN (number) or "" (text).
  Table& Missing();
  void EndRow();

  // Writes the buffered rows out now. Throws RuntimeFailure.
  void Flush();
  // Writes everything, syncs and closes (a table with no rows still gets
  // its header, or its empty dataset). Throws RuntimeFailure. The
  // destructor closes a table not closed, logging a failure.
  void Close();

  // The format behind a table (table_writer.cpp).
  class Sink;

 private:
  // The column of the next cell, checked to hold `type` (std::logic_error).
  const TableColumn& NextColumn(ColumnType type, const char* what) const;
  // "table 'PATH'" for messages.
  std::string Name() const;
  void CloseLogging() noexcept;

  std::unique_ptr<Sink> sink_;
  std::vector<TableColumn> columns_;
  size_t cell_ = 0;  // the next cell of the current row
};

}  // namespace colony
