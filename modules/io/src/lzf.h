#pragma once
// LZF, the byte-oriented LZ77 variant PCD's binary_compressed blocks use (M. Lehmann's liblzf format):
// a control byte below 32 starts a run of ctrl+1 literal bytes; otherwise its top three bits give a
// match length (7 = "read one more length byte") and, with the next byte, a distance back into the
// output of up to 8192 bytes.
#include <cstdint>
#include <string>
#include <string_view>

namespace scanmesh::detail {

/// Decompresses `in`, which must expand to exactly `expected` bytes. Returns false for a corrupt block
/// (a reference before the start, a run past either end, or a different size); never reads or writes
/// out of bounds. The output grows as data is produced, so a false size claim allocates nothing.
bool lzf_decompress(std::string_view in, std::size_t expected, std::string& out);

/// Compresses `in` (greedy matching through a hash of three-byte prefixes).
std::string lzf_compress(std::string_view in);

}  // namespace scanmesh::detail
