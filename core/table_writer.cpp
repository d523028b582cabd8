#include "core/table_writer.h"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "core/error.h"
#include "core/log.h"
#include "core/run_files.h"
#include "core/simulation.h"

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

namespace {

// Whether `text` ends with `suffix`.
bool EndsWith(std::string_view text, std::string_view suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Creates the folder `path` goes in. Throws RuntimeFailure.
void CreateFolderOf(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) return;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec)
    throw RuntimeFailure("cannot create the folder '" + folder.string() + "': " + ec.message());
}

}  // namespace

// What a table writes to: cells in column order, then EndRow.
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

namespace {

using Clock = std::chrono::steady_clock;

// gzip and HDF5 deflate level: the fastest. The simulation waits while a
// table is compressed; level 6 makes a trajectories CSV 8% smaller in 6
// times the time.
constexpr int kGzipLevel = 1;

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
    if (deflateInit2(&z, kGzipLevel, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
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

// The message of the error HDF5 just reported (its stack), cleared: the
// system's reason ("No space left on device") when the stack holds one,
// else the innermost description.
std::string Hdf5Error() {
  std::vector<std::string> descriptions;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        if (e->desc && *e->desc) static_cast<std::vector<std::string>*>(data)->push_back(e->desc);
        return 0;
      },
      &descriptions);
  H5Eclear2(H5E_DEFAULT);
  for (const auto& d : descriptions) {
    const std::string key = "error message = '";
    const size_t at = d.find(key);
    if (at == std::string::npos) continue;
    const size_t end = d.find('\'', at + key.size());
    if (end != std::string::npos) return d.substr(at + key.size(), end - at - key.size());
  }
  return descriptions.empty() ? "an HDF5 error" : descriptions.back();
}

// HDF5: rows gathered in memory as the compound type's records (int64,
// double, a fixed-width string's bytes, or a variable-length string's
// offset in text_, turned into a pointer just before writing), then
// appended to the dataset in one write per batch (a chunk's worth of rows,
// a second, Flush, Close), each followed by a flush of the file.
class Hdf5Sink : public Table::Sink {
 public:
  Hdf5Sink(std::string path, const std::vector<TableColumn>& columns, bool compress)
      : Sink(std::move(path)), columns_(columns), compress_(compress) {
    for (const TableColumn& c : columns) {
      offsets_.push_back(row_size_);
      row_size_ += c.type == ColumnType::kText && c.width > 0 ? c.width : 8;
    }
    chunk_rows_ = std::max<size_t>(64, (size_t{256} << 10) / row_size_);
    rows_.reserve(chunk_rows_ * row_size_);
    dataset_name_ = fs::path(path_).filename().string();
    dataset_name_ = dataset_name_.substr(0, dataset_name_.rfind('.'));
  }

  ~Hdf5Sink() override { Release(); }

  void Integer(size_t column, int64_t value) override { Put(column, &value, 8); }
  void Number(size_t column, double value) override { Put(column, &value, 8); }
  void Text(size_t column, std::string_view value) override {
    if (const size_t width = columns_[column].width) {
      if (value.size() > width) {
        Fail("'" + std::string(value) + "' (" + std::to_string(value.size()) +
             " bytes) does not fit column '" + columns_[column].name + "', of " +
             std::to_string(width) + " bytes");
      }
      unsigned char* cell = Cell(column);
      std::memcpy(cell, value.data(), value.size());
      std::memset(cell + value.size(), 0, width - value.size());
      return;
    }
    const uint64_t offset = text_.size();
    text_.append(value);
    text_ += '\0';
    Put(column, &offset, 8);
  }
  void Missing(size_t column) override {
    if (columns_[column].type == ColumnType::kText) {
      Text(column, "");
    } else {
      Number(column, std::nan(""));
    }
  }

  void EndRow() override {
    ++rows_buffered_;
    if (rows_buffered_ >= chunk_rows_ || Clock::now() - last_write_ >= std::chrono::seconds(1))
      WriteRows();
  }

  void Flush() override { WriteRows(); }

  void Close() override {
    WriteRows();
    if (file_ < 0) return;
    const bool ok = H5Fflush(file_, H5F_SCOPE_LOCAL) >= 0;
    const std::string error = ok ? "" : Hdf5Error();
    Release();
    if (!ok) Fail(error);
    // Synced to disk, as the other files of a run.
    const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
      const int failed = ::fsync(fd) != 0 ? errno : 0;
      ::close(fd);
      if (failed) throw RuntimeFailure(WriteErrorMessage(path_, failed));
    }
  }

 private:
  // Where cell `column` of the row being filled is.
  unsigned char* Cell(size_t column) {
    const size_t row = rows_buffered_ * row_size_;
    if (rows_.size() < row + row_size_) rows_.resize(row + row_size_);
    return rows_.data() + row + offsets_[column];
  }
  void Put(size_t column, const void* value, size_t size) {
    std::memcpy(Cell(column), value, size);
  }

  [[noreturn]] void Fail(const std::string& reason) {
    throw RuntimeFailure("cannot write '" + path_ + "': " + reason);
  }

  // A string type of `width` bytes (0: variable length), UTF-8.
  static hid_t StringType(size_t width) {
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, width > 0 ? width : H5T_VARIABLE);
    if (width > 0) H5Tset_strpad(t, H5T_STR_NULLPAD);
    H5Tset_cset(t, H5T_CSET_UTF8);
    return t;
  }

  // Creates the file and its empty dataset.
  void Open() {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors come back as messages
    CreateFolderOf(path_);
    const hid_t access = H5Pcreate(H5P_FILE_ACCESS);
    // No file locks: they fail on some cluster file systems, and no other
    // process writes a run's files.
    H5Pset_file_locking(access, false, true);
    file_ = H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access);
    H5Pclose(access);
    if (file_ < 0) Fail(Hdf5Error());
    type_ = H5Tcreate(H5T_COMPOUND, row_size_);
    for (size_t i = 0; i < columns_.size(); ++i) {
      const TableColumn& c = columns_[i];
      if (c.type == ColumnType::kText) {
        const hid_t t = StringType(c.width);
        H5Tinsert(type_, c.name.c_str(), offsets_[i], t);
        H5Tclose(t);
      } else {
        H5Tinsert(type_, c.name.c_str(), offsets_[i],
                  c.type == ColumnType::kInteger ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE);
      }
    }
    const hsize_t size = 0, max_size = H5S_UNLIMITED, chunk = chunk_rows_;
    const hid_t space = H5Screate_simple(1, &size, &max_size);
    const hid_t create = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(create, 1, &chunk);
    if (compress_) {
      H5Pset_shuffle(create);
      H5Pset_deflate(create, kGzipLevel);
    }
    dataset_ =
        H5Dcreate2(file_, dataset_name_.c_str(), type_, space, H5P_DEFAULT, create, H5P_DEFAULT);
    H5Pclose(create);
    H5Sclose(space);
    if (dataset_ < 0) Fail(Hdf5Error());
  }

  void WriteRows() {
    last_write_ = Clock::now();
    if (file_ < 0) Open();
    if (rows_buffered_ == 0) return;
    // Variable-length text cells: offsets into text_ become pointers, as
    // HDF5 reads such strings.
    for (size_t c = 0; c < columns_.size(); ++c) {
      if (columns_[c].type != ColumnType::kText || columns_[c].width > 0) continue;
      for (size_t r = 0; r < rows_buffered_; ++r) {
        unsigned char* cell = rows_.data() + r * row_size_ + offsets_[c];
        uint64_t offset;
        std::memcpy(&offset, cell, 8);
        const char* text = text_.data() + offset;
        std::memcpy(cell, &text, 8);
      }
    }
    const hsize_t start = rows_written_, count = rows_buffered_, size = start + count;
    bool ok = H5Dset_extent(dataset_, &size) >= 0;
    const hid_t file_space = H5Dget_space(dataset_);
    const hid_t memory_space = H5Screate_simple(1, &count, nullptr);
    ok = ok &&
         H5Sselect_hyperslab(file_space, H5S_SELECT_SET, &start, nullptr, &count, nullptr) >= 0;
    ok = ok && H5Dwrite(dataset_, type_, memory_space, file_space, H5P_DEFAULT, rows_.data()) >= 0;
    H5Sclose(memory_space);
    H5Sclose(file_space);
    ok = ok && H5Fflush(file_, H5F_SCOPE_LOCAL) >= 0;
    if (!ok) Fail(Hdf5Error());
    rows_written_ += rows_buffered_;
    rows_buffered_ = 0;
    text_.clear();
  }

  void Release() {
    if (dataset_ >= 0) H5Dclose(dataset_);
    if (type_ >= 0) H5Tclose(type_);
    if (file_ >= 0) H5Fclose(file_);
    dataset_ = type_ = file_ = -1;
  }

  std::vector<TableColumn> columns_;
  bool compress_;
  std::string dataset_name_;
  std::vector<size_t> offsets_;  // of each column's cell in a row
  size_t row_size_ = 0, chunk_rows_ = 0;
  std::vector<unsigned char> rows_;  // rows_buffered_ records of row_size_ bytes
  std::string text_;  // the buffered rows' variable-length strings, each ended by '\0'
  size_t rows_buffered_ = 0;
  uint64_t rows_written_ = 0;
  Clock::time_point last_write_ = Clock::now();
  hid_t file_ = -1, dataset_ = -1, type_ = -1;
};

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
    table.sink_ = std::make_unique<Hdf5Sink>(path, columns, options.compress);
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
