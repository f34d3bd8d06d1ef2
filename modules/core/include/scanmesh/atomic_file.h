#pragma once
// Outputs are written atomically: into a unique hidden temporary file beside the target, then renamed
// over it, so an interrupted or failed run never leaves a half-written file under the final name.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace scanmesh {

/// Where an encoder hands its bytes, a piece at a time.
using ByteSink = std::function<void(std::string_view)>;

/// The files of one run, made visible together. write() puts each into a hidden temporary beside its
/// target (".NAME.tmp.PID.XXXXXX", fsynced); commit() renames them all, the first written last (so a run
/// killed during the renames never leaves its main output beside an older sidecar), under a lock on each
/// target folder, so two runs writing the same outputs never mix their files. A
/// transaction destroyed without commit() removes its temporaries, and so does SIGINT, SIGTERM or SIGHUP
/// arriving meanwhile. Temporaries of a run killed outright (SIGKILL) are removed by the next write to
/// the same target once their process is gone.
class OutputTransaction {
 public:
  OutputTransaction();
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  /// Writes `bytes` for `path` (replacing an earlier write to the same path in this transaction).
  /// Throws OutputError naming the path if the folder is missing or the write fails.
  void write(const std::string& path, std::string_view bytes);
  /// The same, streamed: `produce` calls the sink with the file's bytes in as many pieces as it likes,
  /// each written as it comes (a large mesh is never held twice, once as a mesh and once as a file).
  /// An exception from `produce` removes the temporary and propagates.
  void write_with(const std::string& path, const std::function<void(const ByteSink&)>& produce);
  /// Renames every written file into place. Throws OutputError (and removes what is left) on failure.
  void commit();
  /// The targets written so far, in order.
  [[nodiscard]] std::vector<std::string> targets() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes `bytes` to `path` atomically (a transaction of one file). Throws OutputError naming the path.
void write_file_atomically(const std::string& path, std::string_view bytes);
/// Streams a file to `path` atomically (see OutputTransaction::write_with).
void write_file_atomically(const std::string& path, const std::function<void(const ByteSink&)>& produce);

/// Throws OutputError naming `path` unless its folder exists and this process may create files in it.
void check_writable(const std::string& path);

/// Reads a whole file. Throws InputError naming the path if it cannot be opened or read.
std::string read_file(const std::string& path);

/// Reads at most the first `max_bytes` of a file (e.g. to look at a header). Throws InputError like read_file.
std::string read_file_head(const std::string& path, std::size_t max_bytes);

/// True if both paths name the same existing file (so an output would overwrite its input).
bool same_file(const std::string& a, const std::string& b);

}  // namespace scanmesh
