#include "lzf.h"

#include <algorithm>
#include <vector>

namespace scanmesh::detail {

bool lzf_decompress(std::string_view in, std::size_t expected, std::string& out) {
  out.clear();
  // Reserve what the input can produce at most (a 3-byte match yields 264 bytes), never more.
  out.reserve(std::min<std::size_t>(expected, in.size() * 88 + 64));
  std::size_t i = 0;
  while (i < in.size()) {
    const unsigned ctrl = static_cast<unsigned char>(in[i++]);
    if (ctrl < 32) {
      const std::size_t run = ctrl + 1;
      if (run > in.size() - i || run > expected - out.size()) return false;
      out.append(in.data() + i, run);
      i += run;
      continue;
    }
    std::size_t len = ctrl >> 5;
    if (len == 7) {
      if (i >= in.size()) return false;
      len += static_cast<unsigned char>(in[i++]);
    }
    if (i >= in.size()) return false;
    const std::size_t distance = ((static_cast<std::size_t>(ctrl & 31) << 8) | static_cast<unsigned char>(in[i++])) + 1;
    len += 2;
    if (distance > out.size() || len > expected - out.size()) return false;
    // The source may overlap what is being written (a run of a repeated pattern): copy byte by byte.
    std::size_t from = out.size() - distance;
    for (std::size_t k = 0; k < len; ++k) out.push_back(out[from++]);
  }
  return out.size() == expected;
}

std::string lzf_compress(std::string_view in) {
  constexpr std::size_t kMaxDistance = 8192, kMaxMatch = 264, kMaxLiteral = 32;
  constexpr int kHashBits = 14;
  std::vector<long> last(std::size_t{1} << kHashBits, -1);
  std::string out;
  out.reserve(in.size() + in.size() / 32 + 16);
  std::size_t literal_start = 0;  // first byte not yet emitted
  auto flush_literals = [&](std::size_t end) {
    while (literal_start < end) {
      const std::size_t run = std::min(kMaxLiteral, end - literal_start);
      out.push_back(static_cast<char>(run - 1));
      out.append(in.data() + literal_start, run);
      literal_start += run;
    }
  };
  auto hash = [&](std::size_t p) {
    const unsigned v = (static_cast<unsigned char>(in[p]) << 16) | (static_cast<unsigned char>(in[p + 1]) << 8) |
                       static_cast<unsigned char>(in[p + 2]);
    return (v * 2654435761u) >> (32 - kHashBits);
  };
  std::size_t p = 0;
  while (p + 2 < in.size()) {
    const unsigned h = hash(p);
    const long candidate = last[h];
    last[h] = static_cast<long>(p);
    if (candidate >= 0 && p - static_cast<std::size_t>(candidate) <= kMaxDistance) {
      const std::size_t c = static_cast<std::size_t>(candidate);
      std::size_t len = 0;
      const std::size_t limit = std::min(kMaxMatch, in.size() - p);
      while (len < limit && in[c + len] == in[p + len]) ++len;
      if (len >= 3) {
        flush_literals(p);
        const std::size_t distance = p - c - 1;
        const std::size_t code = len - 2;
        if (code < 7) {
          out.push_back(static_cast<char>((code << 5) | (distance >> 8)));
        } else {
          out.push_back(static_cast<char>((7u << 5) | (distance >> 8)));
          out.push_back(static_cast<char>(code - 7));
        }
        out.push_back(static_cast<char>(distance & 0xff));
        for (std::size_t k = 1; k < len && p + k + 2 < in.size(); ++k) last[hash(p + k)] = static_cast<long>(p + k);
        p += len;
        literal_start = p;
        continue;
      }
    }
    ++p;
  }
  flush_literals(in.size());
  return out;
}

}  // namespace scanmesh::detail
