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

}  // namespace scanmesh::detail
