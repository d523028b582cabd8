// Files a run writes, written so that what is on disk is always either
// complete or clearly incomplete: every write is checked (a failure names the
// file and the reason, e.g. "No space left on device"), whole files are
// written to a temporary name, synced and renamed, and row files (CSV) only
// ever hold whole rows.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace colony {

// Writes `text` to `path` through a temporary file (`tmp`, default
// `path`.tmp; writers on several hosts sharing a folder give each their
// own): written, fsync'ed (when `sync`), renamed over `path`, then the folder
// synced. On any failure the temporary file is removed and RuntimeFailure
// names the file and the reason; `path` is left as it was. Without `sync` a
// crash of the process still never leaves a partial `path`; a crash of the
// machine might.
void WriteFileAtomically(const std::string& path, std::string_view text, bool sync = true,
                         const std::string& tmp = "");

// Where a write of `path` failed, as a message: "cannot write 'PATH': REASON".
std::string WriteErrorMessage(const std::string& path, int error_number);

// The SHA-256 of the file's content, as 64 lowercase hex digits (what
// sha256sum prints), or "" when it cannot be read.
std::string FileSha256(const std::string& path);

// An append-only file of text rows (CSV). Rows are kept in a fixed buffer
// and written out whole: when the buffer fills, when a second of wall time
// has passed since the last write, on Flush and on Close. A write that fails
// part-way is cut back to the last whole row before the error is reported,
// so a reader never sees half a row written by this process. A crash handler
// can call FlushAfterCrash (async-signal-safe) to write what is buffered.
class RowFile {
 public:
  // Creates (truncates) `path`. Throws RuntimeFailure naming it and why.
  explicit RowFile(std::string path);
  // Flushes what is buffered; errors here are only logged.
  ~RowFile();
  RowFile(const RowFile&) = delete;
  RowFile& operator=(const RowFile&) = delete;

  // Appends one row; `row` must end with '\n'. Throws RuntimeFailure when a
  // write it triggers fails.
  void Append(std::string_view row);
  // Writes `block` out now, after the buffered rows: a unit of binary data
  // (a gzip member) that the file holds whole or not at all; a write that
  // fails part-way is cut back to the end of the previous block. Throws
  // RuntimeFailure.
  void AppendBlock(std::string_view block);
  // Writes every buffered row. Throws RuntimeFailure on failure.
  void Flush();
  // Flushes, syncs to disk and closes. Throws RuntimeFailure on failure.
  void Close();
  const std::string& path() const { return path_; }

  // Writes the buffered rows of every open RowFile with write(2) alone. For
  // signal handlers: the rows were completed before the signal, so they are
  // whole; a file being written by its owner at that moment is skipped.
  static void FlushAllAfterCrash();

 private:
  static constexpr size_t kCapacity = 64 * 1024;
  // Writes `size` bytes of whole rows; when a write fails part-way, cuts the
  // file back to its last whole row (`block`: to where the write began).
  // Returns 0 or the errno of the failure.
  int WriteRows(const char* rows, size_t size, bool block = false);
  // WriteRows of the buffer, which it then empties.
  int WriteBuffered();

  std::string path_;
  int fd_ = -1;
  std::unique_ptr<char[]> buffer_;
  std::atomic<size_t> used_{0};       // whole rows waiting in buffer_
  std::atomic<bool> writing_{false};  // the owner is inside WriteBuffered
  size_t file_size_ = 0;              // bytes of whole rows in the file
  std::chrono::steady_clock::time_point last_write_;
};

}  // namespace colony
