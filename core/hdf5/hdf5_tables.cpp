// HDF5 tables (core/table_formats.h): the plugin colony_hdf5, which libcolony
// loads the first time something opens an HDF5 table, so that only the
// processes that write or read HDF5 load libhdf5 (the C API).
#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "core/run_files.h"
#include "core/table_formats.h"

namespace colony {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

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
      H5Pset_deflate(create, kTableGzipLevel);
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

// An HDF5 identifier closed when it goes.
class H5Handle {
 public:
  H5Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~H5Handle() {
    if (id_ >= 0) close_(id_);
  }
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// HDF5's own error printing, off while reading (its errors become ours).
class QuietHdf5 {
 public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
};

[[noreturn]] void Unreadable(const std::string& reason) { throw RuntimeFailure(reason); }

// The integer and number columns are read at once, as a compound of those
// fields, 8 bytes each, converted by HDF5; each text column on its own, in
// its own type (fixed width, or variable length).
size_t ReadColumns(const std::string& path, const std::string& dataset_name,
                   const std::vector<TableColumn>& wanted, std::vector<Hdf5Column>& out) {
  QuietHdf5 quiet;
  const H5Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.ok()) Unreadable("not a readable HDF5 file (damaged or cut short?)");
  const H5Handle dataset(H5Dopen2(file.get(), dataset_name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dataset.ok()) Unreadable("no dataset '" + dataset_name + "'");
  const H5Handle type(H5Dget_type(dataset.get()), H5Tclose);
  const H5Handle space(H5Dget_space(dataset.get()), H5Sclose);
  if (!type.ok() || !space.ok() || H5Tget_class(type.get()) != H5T_COMPOUND ||
      H5Sget_simple_extent_ndims(space.get()) != 1) {
    Unreadable("dataset '" + dataset_name + "' is not a one-dimensional table of a compound type");
  }
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  if (count < 0) Unreadable("cannot read the number of rows of dataset '" + dataset_name + "'");
  const size_t n = static_cast<size_t>(count);

  out.assign(wanted.size(), Hdf5Column{});
  std::vector<size_t> numeric;  // the wanted integer and number columns present
  std::string numeric_names;
  for (size_t c = 0; c < wanted.size(); ++c) {
    out[c].present = H5Tget_member_index(type.get(), wanted[c].name.c_str()) >= 0;
    if (!out[c].present || wanted[c].type == ColumnType::kText) continue;
    numeric.push_back(c);
    numeric_names += (numeric_names.empty() ? "" : ", ") + wanted[c].name;
  }

  if (!numeric.empty()) {
    const size_t row = 8 * numeric.size();
    const H5Handle memory(H5Tcreate(H5T_COMPOUND, row), H5Tclose);
    for (size_t k = 0; k < numeric.size(); ++k) {
      const TableColumn& column = wanted[numeric[k]];
      H5Tinsert(memory.get(), column.name.c_str(), 8 * k,
                column.type == ColumnType::kInteger ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE);
    }
    std::vector<unsigned char> cells(n * row);
    if (n > 0 &&
        H5Dread(dataset.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, cells.data()) < 0) {
      Unreadable("cannot read the rows' " + numeric_names + " (damaged or cut short?)");
    }
    // Field k of every record into its column's vector (int64 or double).
    auto scatter = [&](auto& to, size_t k) {
      to.resize(n);
      for (size_t r = 0; r < n; ++r) std::memcpy(&to[r], cells.data() + r * row + 8 * k, 8);
    };
    for (size_t k = 0; k < numeric.size(); ++k) {
      Hdf5Column& column = out[numeric[k]];
      if (wanted[numeric[k]].type == ColumnType::kInteger) {
        scatter(column.integers, k);
      } else {
        scatter(column.numbers, k);
      }
    }
  }

  for (size_t c = 0; c < wanted.size(); ++c) {
    if (!out[c].present || wanted[c].type != ColumnType::kText) continue;
    const std::string& name = wanted[c].name;
    const H5Handle text_type(
        H5Tget_member_type(type.get(), H5Tget_member_index(type.get(), name.c_str())), H5Tclose);
    if (H5Tget_class(text_type.get()) != H5T_STRING)
      Unreadable("column '" + name + "' is not text");
    const bool variable = H5Tis_variable_str(text_type.get()) > 0;
    const size_t width = variable ? sizeof(char*) : H5Tget_size(text_type.get());
    const H5Handle memory(H5Tcreate(H5T_COMPOUND, width), H5Tclose);
    H5Tinsert(memory.get(), name.c_str(), 0, text_type.get());
    std::vector<char> cells(n * width);
    if (n > 0 &&
        H5Dread(dataset.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, cells.data()) < 0) {
      Unreadable("cannot read the rows' " + name + " (damaged or cut short?)");
    }
    std::vector<std::string>& texts = out[c].texts;
    texts.resize(n);
    for (size_t r = 0; r < n; ++r) {
      const char* cell = cells.data() + r * width;
      if (variable) {
        const char* text = nullptr;
        std::memcpy(&text, cell, sizeof text);
        texts[r] = text ? text : "";
      } else {
        texts[r].assign(cell, strnlen(cell, width));
      }
    }
    if (variable && n > 0) H5Dvlen_reclaim(memory.get(), space.get(), H5P_DEFAULT, cells.data());
  }
  return n;
}

std::unique_ptr<Table::Sink> MakeSink(const std::string& path,
                                      const std::vector<TableColumn>& columns, bool compress) {
  return std::make_unique<Hdf5Sink>(path, columns, compress);
}

constexpr Hdf5Tables kTables{MakeSink, ReadColumns};

// Registered while libcolony loads the plugin.
const bool registered = (SetHdf5Tables(&kTables), true);

}  // namespace
}  // namespace colony
