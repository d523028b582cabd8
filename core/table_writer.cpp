#include "core/table_writer.h"

#include <zlib.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <stdexcept>

#include "core/error.h"
#include "core/log.h"
#include "core/plugin_loader.h"
#include "core/run_files.h"
#include "core/simulation.h"
#include "core/table_formats.h"

namespace colony {

namespace fs = std::filesystem;

void AppendCsvField(std::string& line, std::string_view field) {
  if (field.find_first_of(",\"\r\n") == std::string_view::npos) {
    line += field;
    return;
  }
  line += '"';
  for (char c : field) {
    if (c == '"') line += '"';
    line += c;
  }
  line += '"';
}

void AppendNumber(std::string& line, double value, int digits) {
  if (std::isnan(value)) {
    line += "nan";
    return;
  }
  char text[64];
  const auto result = digits > 0 ? std::to_chars(text, text + sizeof text, value,
                                                 std::chars_format::general, digits)
                                 : std::to_chars(text, text + sizeof text, value);
  line.append(text, result.ptr);
}

void CreateFolderOf(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) return;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec)
    throw RuntimeFailure("cannot create the folder '" + folder.string() + "': " + ec.message());
}

namespace {

// Whether `text` ends with `suffix`.
bool EndsWith(std::string_view text, std::string_view suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

using Clock = std::chrono::steady_clock;

// CSV, plain (a RowFile: whole rows, written out at least once a second,
// kept across a crash) or gzip'ed: rows gathered uncompressed, then
// compressed into one gzip member per write (at 1 MiB of rows, after a
// second, on Flush and Close).
class CsvSink : public Table::Sink {
 public:
  CsvSink(std::string path, const std::vector<TableColumn>& columns, bool gzip)
      : Sink(std::move(path)), columns_(columns), gzip_(gzip) {
    for (size_t i = 0; i < columns.size(); ++i) {
      if (i) header_ += ',';
      AppendCsvField(header_, columns[i].name);
    }
    header_ += '\n';
    row_.reserve(256);
  }

  void Integer(size_t column, int64_t value) override {
    Separate(column);
    char text[32];
    row_.append(text, std::to_chars(text, text + sizeof text, value).ptr);
  }
  void Number(size_t column, double value) override {
    Separate(column);
    AppendNumber(row_, value, columns_[column].digits);
  }
  void Text(size_t column, std::string_view value) override {
    Separate(column);
    AppendCsvField(row_, value);
  }
  void Missing(size_t column) override { Separate(column); }

  void EndRow() override {
    row_ += '\n';
    Open();
    if (!gzip_) {
      file_->Append(row_);
    } else {
      pending_ += row_;
      if (pending_.size() >= kMemberSize || Clock::now() - last_member_ >= std::chrono::seconds(1))
        WriteMember();
    }
    row_.clear();
  }

  void Flush() override {
    if (!file_) return;
    if (gzip_) WriteMember();
    file_->Flush();
  }

  void Close() override {
    Open();
    if (gzip_) WriteMember();
    file_->Close();
  }

 private:
  static constexpr size_t kMemberSize = 1 << 20;

  void Separate(size_t column) {
    if (column) row_ += ',';
  }

  // The file, created with its header at the first write.
  void Open() {
    if (file_) return;
    CreateFolderOf(path_);
    file_ = std::make_unique<RowFile>(path_);
    last_member_ = Clock::now();
    if (gzip_) {
      pending_ = header_;
    } else {
      file_->Append(header_);
    }
  }

  // Compresses the pending rows into one gzip member and writes it.
  void WriteMember() {
    last_member_ = Clock::now();
    if (pending_.empty()) return;
    z_stream z{};
    if (deflateInit2(&z, kTableGzipLevel, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
      throw RuntimeFailure("cannot write '" + path_ + "': zlib cannot start compressing");
    }
    member_.resize(deflateBound(&z, pending_.size()));
    z.next_in = reinterpret_cast<Bytef*>(pending_.data());
    z.avail_in = static_cast<uInt>(pending_.size());
    z.next_out = reinterpret_cast<Bytef*>(member_.data());
    z.avail_out = static_cast<uInt>(member_.size());
    const int status = deflate(&z, Z_FINISH);
    const size_t size = member_.size() - z.avail_out;
    deflateEnd(&z);
    if (status != Z_STREAM_END) {
      throw RuntimeFailure("cannot write '" + path_ + "': zlib failed to compress (status " +
                           std::to_string(status) + ")");
    }
    pending_.clear();
    file_->AppendBlock(std::string_view(member_.data(), size));
  }

  std::vector<TableColumn> columns_;
  bool gzip_;
  std::string header_, row_;
  std::unique_ptr<RowFile> file_;
  std::string pending_;  // gzip: rows not yet compressed
  std::string member_;   // gzip: the compressed member
  Clock::time_point last_member_;
};

// The HDF5 plugin (core/hdf5), loaded the first time an HDF5 table is
// opened; its registrar sets tables.
const Hdf5Tables* tables = nullptr;
std::string& Hdf5LoadFailure() {
  static std::string failure;
  return failure;
}

const char* TypeName(ColumnType type) {
  switch (type) {
    case ColumnType::kInteger:
      return "an integer";
    case ColumnType::kNumber:
      return "a number";
    case ColumnType::kText:
      return "a text";
  }
  return "";
}

}  // namespace

void SetHdf5Tables(const Hdf5Tables* hdf5) { tables = hdf5; }

const Hdf5Tables& Hdf5() {
  static std::once_flag once;
  std::call_once(once, [] {
    const std::string error = LoadPluginLibrary("colony_hdf5", "");
    if (tables == nullptr) {
      Hdf5LoadFailure() = error.empty() ? "it loaded but registered no HDF5 tables" : error;
    }
  });
  if (tables == nullptr) {
    throw RuntimeFailure(
        "HDF5 tables need the plugin colony_hdf5 (libcolony_hdf5.so, built with Colony and "
        "installed beside its other plugins), which could not be loaded: " +
        Hdf5LoadFailure());
  }
  return *tables;
}

Table::Table() = default;
Table::~Table() { CloseLogging(); }
Table::Table(Table&&) noexcept = default;

Table& Table::operator=(Table&& other) noexcept {
  if (this != &other) {
    CloseLogging();
    sink_ = std::move(other.sink_);
    columns_ = std::move(other.columns_);
    cell_ = other.cell_;
  }
  return *this;
}

void Table::CloseLogging() noexcept {
  if (!sink_) return;
  try {
    Close();
  } catch (const std::exception& e) {
    LogWarning(e.what());
  }
}

Table Table::Create(const std::string& path, std::vector<TableColumn> columns,
                    const TableOptions& options) {
  if (columns.empty()) throw std::invalid_argument("table '" + path + "': it has no columns");
  for (size_t i = 0; i < columns.size(); ++i) {
    if (columns[i].name.empty())
      throw std::invalid_argument("table '" + path + "': column " + std::to_string(i + 1) +
                                  " has no name");
    for (size_t j = 0; j < i; ++j) {
      if (columns[j].name == columns[i].name)
        throw std::invalid_argument("table '" + path + "': two columns are named '" +
                                    columns[i].name + "'");
    }
  }
  Table table;
  if (EndsWith(path, ".csv.gz")) {
    table.sink_ = std::make_unique<CsvSink>(path, columns, true);
  } else if (EndsWith(path, ".csv")) {
    if (options.compress)
      throw std::invalid_argument("table '" + path +
                                  "': a compressed CSV table is named NAME.csv.gz");
    table.sink_ = std::make_unique<CsvSink>(path, columns, false);
  } else if (EndsWith(path, ".h5") || EndsWith(path, ".hdf5")) {
    table.sink_ = Hdf5().make_sink(path, columns, options.compress);
  } else {
    throw std::invalid_argument("table '" + path +
                                "': unknown format; accepted endings: .csv, .csv.gz (gzip), .h5 "
                                "or .hdf5 (HDF5)");
  }
  table.columns_ = std::move(columns);
  return table;
}

Table Table::InRunFolder(const Simulation& sim, const std::string& name,
                         std::vector<TableColumn> columns, const TableOptions& options) {
  const fs::path relative(name);
  bool climbs = false;
  for (const auto& part : relative) climbs = climbs || part == "..";
  if (name.empty() || relative.is_absolute() || climbs) {
    throw std::invalid_argument("table '" + name +
                                "': expected a file name relative to the run folder, inside it "
                                "(e.g. 'pockets.csv' or 'tables/robots.h5')");
  }
  // The name and columns are checked the same with no run folder, so a
  // mistake shows in any run; the table made for that writes nothing (its
  // files are only ever created at the first write).
  Table table = Create(name, std::move(columns), options);
  table.sink_.reset();
  if (sim.run_folder().empty()) return table;
  return Create((fs::path(sim.run_folder()) / relative).string(), std::move(table.columns_),
                options);
}

const std::string& Table::path() const {
  static const std::string none;
  return sink_ ? sink_->path() : none;
}

std::string Table::Name() const {
  return sink_ ? "table '" + sink_->path() + "'" : std::string("a table");
}

const TableColumn& Table::NextColumn(ColumnType type, const char* what) const {
  if (cell_ >= columns_.size()) {
    throw std::logic_error(Name() + ": more cells in a row than its " +
                           std::to_string(columns_.size()) + " columns (EndRow missing?)");
  }
  const TableColumn& column = columns_[cell_];
  if (type != column.type) {
    throw std::logic_error(Name() + ": column '" + column.name + "' holds " +
                           TypeName(column.type) + ", not " + what);
  }
  return column;
}

Table& Table::Integer(int64_t value) {
  NextColumn(ColumnType::kInteger, "an integer");
  if (sink_) sink_->Integer(cell_, value);
  ++cell_;
  return *this;
}

Table& Table::Number(double value) {
  NextColumn(ColumnType::kNumber, "a number");
  if (sink_) sink_->Number(cell_, value);
  ++cell_;
  return *this;
}

Table& Table::Text(std::string_view value) {
  NextColumn(ColumnType::kText, "a text");
  if (sink_) sink_->Text(cell_, value);
  ++cell_;
  return *this;
}

Table& Table::Missing() {
  if (cell_ >= columns_.size()) NextColumn(ColumnType::kNumber, "a missing value");  // throws
  if (columns_[cell_].type == ColumnType::kInteger) {
    throw std::logic_error(Name() + ": column '" + columns_[cell_].name +
                           "' holds integers, which have no missing value");
  }
  if (sink_) sink_->Missing(cell_);
  ++cell_;
  return *this;
}

void Table::EndRow() {
  if (cell_ != columns_.size()) {
    throw std::logic_error(Name() + ": a row of " + std::to_string(cell_) + " cells; it has " +
                           std::to_string(columns_.size()) + " columns");
  }
  cell_ = 0;
  if (sink_) sink_->EndRow();
}

void Table::Flush() {
  if (sink_) sink_->Flush();
}

void Table::Close() {
  if (!sink_) return;
  const auto sink = std::move(sink_);
  sink->Close();
}

}  // namespace colony
