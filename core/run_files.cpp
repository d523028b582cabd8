#include "core/run_files.h"

#include <fcntl.h>
#include <nettle/sha2.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "core/log.h"

namespace colony {

namespace {

namespace fs = std::filesystem;

// Writes all of [data, data + size) to `fd`; returns the bytes written and
// sets `error` (0 when all were written).
size_t WriteAll(int fd, const char* data, size_t size, int& error) {
  size_t done = 0;
  error = 0;
  while (done < size) {
    const ssize_t n = ::write(fd, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : ENOSPC;
      break;
    }
    done += static_cast<size_t>(n);
  }
  return done;
}

// Open row files, for the crash handler. A fixed table: the handler may not
// allocate or lock.
constexpr size_t kMaxOpenRowFiles = 32;
std::atomic<RowFile*> open_row_files[kMaxOpenRowFiles];

void SyncFolderOf(const std::string& path) {
  const std::string dir =
      fs::path(path).parent_path().empty() ? "." : fs::path(path).parent_path().string();
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

std::string WriteErrorMessage(const std::string& path, int error_number) {
  return "cannot write '" + path + "': " + std::strerror(error_number);
}

void WriteFileAtomically(const std::string& path, std::string_view text, bool sync,
                         const std::string& tmp_name) {
  const std::string tmp = tmp_name.empty() ? path + ".tmp" : tmp_name;
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw RuntimeFailure(WriteErrorMessage(tmp, errno));
  int error = 0;
  WriteAll(fd, text.data(), text.size(), error);
  if (!error && sync && ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && !error) error = errno;
  if (error) {
    ::unlink(tmp.c_str());
    throw RuntimeFailure(WriteErrorMessage(path, error));
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    error = errno;
    ::unlink(tmp.c_str());
    throw RuntimeFailure(WriteErrorMessage(path, error));
  }
  if (sync) SyncFolderOf(path);
}

std::string FileSha256(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  sha256_ctx context;
  sha256_init(&context);
  bool ok = true;
  uint8_t buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ok = n == 0;
      break;
    }
    sha256_update(&context, static_cast<size_t>(n), buffer);
  }
  ::close(fd);
  if (!ok) return "";
  uint8_t digest[SHA256_DIGEST_SIZE];
  sha256_digest(&context, sizeof digest, digest);
  static const char kHex[] = "0123456789abcdef";
  std::string hex;
  for (const uint8_t byte : digest) {
    hex += kHex[byte >> 4];
    hex += kHex[byte & 15];
  }
  return hex;
}

RowFile::RowFile(std::string path)
    : path_(std::move(path)),
      buffer_(new char[kCapacity]),
      last_write_(std::chrono::steady_clock::now()) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw RuntimeFailure(WriteErrorMessage(path_, errno));
  for (auto& slot : open_row_files) {
    RowFile* expected = nullptr;
    if (slot.compare_exchange_strong(expected, this)) break;
  }
}

RowFile::~RowFile() {
  for (auto& slot : open_row_files) {
    RowFile* expected = this;
    if (slot.compare_exchange_strong(expected, nullptr)) break;
  }
  if (fd_ < 0) return;
  if (const int error = WriteBuffered()) LogWarning(WriteErrorMessage(path_, error));
  ::close(fd_);
}

int RowFile::WriteRows(const char* rows, size_t size, bool block) {
  writing_.store(true);
  int error = 0;
  const size_t done = WriteAll(fd_, rows, size, error);
  size_t whole = done;
  if (error) {
    // Keep the rows that went out whole; cut the rest off the file.
    if (block) whole = 0;
    while (whole > 0 && rows[whole - 1] != '\n') --whole;
    if (::ftruncate(fd_, static_cast<off_t>(file_size_ + whole)) == 0) ::lseek(fd_, 0, SEEK_END);
  }
  file_size_ += whole;
  writing_.store(false);
  last_write_ = std::chrono::steady_clock::now();
  return error;
}

int RowFile::WriteBuffered() {
  const size_t used = used_.load();
  if (used == 0) return 0;
  const int error = WriteRows(buffer_.get(), used);
  used_.store(0);
  return error;
}

void RowFile::Append(std::string_view row) {
  if (fd_ < 0) throw RuntimeFailure(WriteErrorMessage(path_, EBADF));
  if (used_.load() + row.size() > kCapacity) Flush();
  if (row.size() > kCapacity) {
    // Larger than the buffer: straight out.
    if (const int error = WriteRows(row.data(), row.size()))
      throw RuntimeFailure(WriteErrorMessage(path_, error));
    return;
  }
  const size_t used = used_.load();
  std::memcpy(buffer_.get() + used, row.data(), row.size());
  used_.store(used + row.size());  // the row is now whole in the buffer
  if (std::chrono::steady_clock::now() - last_write_ >= std::chrono::seconds(1)) Flush();
}

void RowFile::AppendBlock(std::string_view block) {
  Flush();
  if (fd_ < 0) throw RuntimeFailure(WriteErrorMessage(path_, EBADF));
  if (const int error = WriteRows(block.data(), block.size(), true))
    throw RuntimeFailure(WriteErrorMessage(path_, error));
}

void RowFile::Flush() {
  if (fd_ < 0) return;
  if (const int error = WriteBuffered()) throw RuntimeFailure(WriteErrorMessage(path_, error));
}

void RowFile::Close() {
  if (fd_ < 0) return;
  int error = WriteBuffered();
  if (!error && ::fsync(fd_) != 0) error = errno;
  if (::close(fd_) != 0 && !error) error = errno;
  fd_ = -1;
  if (error) throw RuntimeFailure(WriteErrorMessage(path_, error));
}

void RowFile::FlushAllAfterCrash() {
  for (auto& slot : open_row_files) {
    RowFile* f = slot.load();
    if (!f || f->fd_ < 0 || f->writing_.load()) continue;
    int error = 0;
    WriteAll(f->fd_, f->buffer_.get(), f->used_.load(), error);
    f->used_.store(0);
  }
}

}  // namespace colony
