#pragma once
// Outputs are written atomically: into a temporary file beside the target, then renamed over it, so an
// interrupted or failed run never leaves a half-written file under the final name.
#include <string>
#include <string_view>

namespace scanmesh {

/// Writes `bytes` to `path` atomically. Throws OutputError naming the path on failure.
void write_file_atomically(const std::string& path, std::string_view bytes);

/// Reads a whole file. Throws InputError naming the path if it cannot be opened or read.
std::string read_file(const std::string& path);

/// Reads at most the first `max_bytes` of a file (e.g. to look at a header). Throws InputError like read_file.
std::string read_file_head(const std::string& path, std::size_t max_bytes);

/// True if both paths name the same existing file (so an output would overwrite its input).
bool same_file(const std::string& a, const std::string& b);

}  // namespace scanmesh
