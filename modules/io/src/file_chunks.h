#pragma once
// A file read a chunk at a time through one buffer, for the readers that stream big files (PLY bodies,
// OBJ lines) instead of holding them whole.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>

#include "scanmesh/errors.h"

namespace scanmesh::detail {

class FileChunks {
 public:
  /// Opens `path` (InputError naming it if that fails); `chunk` bytes are read per call of next().
  FileChunks(const std::string& path, std::size_t chunk)
      : f_(std::fopen(path.c_str(), "rb"), &std::fclose), path_(path), chunk_(std::max<std::size_t>(chunk, 16)) {
    if (!f_) throw InputError("cannot open '" + path + "': " + std::strerror(errno));
  }

  /// The next window: the last `keep` bytes of the previous window (moved to the front; none of the
  /// first window), then up to `chunk` bytes more from the file (none once it is exhausted). Earlier
  /// windows are no longer valid.
  std::string_view next(std::size_t keep) {
    buffer_.erase(0, buffer_.size() - std::min(keep, buffer_.size()));
    const std::size_t kept = buffer_.size();
    buffer_.resize(kept + chunk_);
    fresh_ = std::fread(buffer_.data() + kept, 1, chunk_, f_.get());
    if (std::ferror(f_.get()) != 0) throw InputError("cannot read '" + path_ + "': read error");
    buffer_.resize(kept + fresh_);
    return buffer_;
  }
  /// How many bytes at the end of the last window are new (0: the file had no more).
  [[nodiscard]] std::size_t fresh() const { return fresh_; }

 private:
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f_;
  std::string path_;
  std::size_t chunk_;
  std::string buffer_;
  std::size_t fresh_ = 0;
};

/// Hands `parse(block, line, last)` the file in blocks of whole lines (about `chunk` bytes each; a line
/// longer than that makes a longer block), `line` being the file's line number of the block's first line;
/// `parse` returns the line after the block. The last block (`last` true) holds what follows the last
/// newline, possibly nothing.
template <class Parse>
void for_each_line_block(const std::string& path, std::size_t chunk, Parse&& parse) {
  FileChunks chunks(path, chunk);
  std::size_t line = 1, carried = 0;  // bytes of an unfinished line at the end of the window
  for (;;) {
    const std::string_view window = chunks.next(carried);
    if (chunks.fresh() == 0) {  // end of file: the last line has no newline
      parse(window, line, true);
      return;
    }
    // Only the new bytes can hold a newline (the carried ones are one unfinished line), so a file of one
    // endless line is scanned once, not once per chunk.
    const std::size_t found = window.substr(carried).rfind('\n');
    if (found == std::string_view::npos) {  // one line longer than the chunk: read on
      carried = window.size();
      continue;
    }
    const std::size_t end = carried + found + 1;
    line = parse(window.substr(0, end), line, false);
    carried = window.size() - end;
  }
}

}  // namespace scanmesh::detail
