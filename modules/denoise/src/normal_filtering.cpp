#include "scanmesh/normal_filtering.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include <immintrin.h>

#include "scanmesh/memory.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/vertex_update.h"

namespace scanmesh {

double robust_weight(RobustEstimator estimator, double x, double s) {
  switch (estimator) {
    case RobustEstimator::tukey: {
      if (x > s) return 0.0;
      const double u = 1.0 - (x * x) / (s * s);
      return 0.5 * u * u;
    }
    case RobustEstimator::gaussian: return std::exp(-(x * x) / (2.0 * s * s));
    case RobustEstimator::huber: return x <= s ? 1.0 : s / x;
    case RobustEstimator::lorentzian: return 1.0 / (1.0 + (x * x) / (2.0 * s * s));
  }
  return 0.0;
}

namespace {

// e^x for x <= 0, inline: the closeness weight is evaluated for every pair of faces in every iteration,
// and libm's exp took a third of the denoiser's time. x = (256 m + j) ln2 / 256 + r with |r| <= ln2/512:
// e^x = 2^m * 2^(j/256) * e^r, the middle factor from a table, e^r from its Taylor polynomial to degree 4
// (relative error below 1e-16), 2^m from the exponent bits. Deterministic: the table is filled once and
// the same x gives the same bits on every thread.
struct ExpTable {
  double v[256];
  ExpTable() {
    for (int j = 0; j < 256; ++j) v[j] = std::exp2(j / 256.0);
  }
};
const ExpTable kExpTable;

inline double exp_nonpositive(double x) {
  if (!(x >= -700.0)) return 0.0;  // also NaN
  constexpr double kScale = 256.0 * 1.4426950408889634;  // 256 / ln2
  // ln2 / 256 in two parts (ln2's high part has its low 32 bits zero, so k * kStepHi is exact).
  constexpr double kStepHi = 6.93147180369123816490e-01 / 256.0, kStepLo = 1.90821492927058770002e-10 / 256.0;
  // Round to nearest by adding and removing 1.5 * 2^52 (no call to floor, which needs SSE4.1 to be inline).
  constexpr double kRound = 6755399441055744.0;
  const double k = (x * kScale + kRound) - kRound;
  const double r = (x - k * kStepHi) - k * kStepLo;
  const double p = 1.0 + r * (1.0 + r * (0.5 + r * (1.0 / 6.0 + r * (1.0 / 24.0))));
  const auto ki = static_cast<std::int64_t>(k);
  const std::int64_t m = ki >> 8;  // floor division (arithmetic shift), j = ki - 256 m in [0, 255]
  const auto bits = static_cast<std::uint64_t>(m + 1023) << 52;
  double scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * kExpTable.v[ki - 256 * m] * scale;
}

// A face's neighbourhood as a pointer and a length: an Adjacency's row in place, a PackedRows' row unpacked
// into a per-thread buffer (grown once, never inside the iterations after the first).
struct PlainRows {
  const Adjacency& a;
  [[gnu::always_inline]] static const std::uint16_t* differences(long, int&) { return nullptr; }
  [[gnu::always_inline]] const int* row(long i, int& count) const {
    count = a.size(static_cast<std::size_t>(i));
    return a.begin(static_cast<std::size_t>(i));
  }
};
struct UnpackedRows {
  const PackedRows& p;
  int* buffer;
  [[gnu::always_inline]] const std::uint16_t* differences(long i, int& count) const { return p.differences(static_cast<std::size_t>(i), count); }
  [[gnu::always_inline]] const int* row(long i, int& count) const {
    count = p.unpack(static_cast<std::size_t>(i), static_cast<int>(i), buffer);
    return buffer;
  }
};
int* row_buffer(const PackedRows& p) {
  thread_local std::vector<int> buffer;
  if (buffer.size() < static_cast<std::size_t>(p.max_row())) buffer.resize(static_cast<std::size_t>(p.max_row()));
  return buffer.data();
}

// The Tukey kernel works in single precision on eight neighbours at a time: each face's normal, area
// and centroid packed into 32 bytes, read into one AVX2 register of eight lanes, or into
// two SSE registers of four lanes on a machine without AVX2. Either way each lane does the same IEEE
// operations in the same order, -ffp-contract=off keeps a*b+c from becoming an FMA in one and not the
// other, and the lanes are added up in one fixed order, so the result depends neither on the thread count
// nor on the instruction set. Single precision is enough: a weight's relative error is about 1e-7, the
// filtered normal's about 1e-6 radians, and the vertex update that uses it runs in double precision.
// GCC notes that passing 32-byte vectors changes the ABI without AVX; these helpers are always inlined,
// so no such vector crosses a call.
#pragma GCC diagnostic ignored "-Wpsabi"
template <int W>
struct Lanes;
template <>
struct Lanes<4> {
  typedef float F __attribute__((vector_size(16)));
  typedef std::int32_t I __attribute__((vector_size(16)));
};
template <>
struct Lanes<8> {
  typedef float F __attribute__((vector_size(32)));
  typedef std::int32_t I __attribute__((vector_size(32)));
};
template <int W>
using Vf = typename Lanes<W>::F;
template <int W>
using Vi = typename Lanes<W>::I;

template <int W>
[[gnu::always_inline]] inline Vf<W> splat(float x) {
  Vf<W> v;
  for (int l = 0; l < W; ++l) v[l] = x;
  return v;
}

// e^x for x <= 0, W at a time and without a table: x = k ln2 + r with |r| <= ln2/2, e^r from its Taylor
// polynomial to degree 6 (relative error below 2e-7, single precision's own), in Estrin's scheme; 2^k from
// the exponent bits. Below -87 (and for NaN) the result is e^-87, which no sum of weights can tell from zero.
template <int W>
[[gnu::always_inline]] inline Vf<W> exp_nonpositive(Vf<W> x) {
  using V = Vf<W>;
  x = x >= splat<W>(-87.0f) ? x : splat<W>(-87.0f);
  constexpr float kInvLn2 = 1.44269504f;
  constexpr float kLn2Hi = 0.693359375f, kLn2Lo = -2.12194440e-4f;  // kLn2Hi has 9 significant bits: k * kLn2Hi is exact
  constexpr float kRound = 12582912.0f;                             // 1.5 * 2^23: adding it rounds to an integer
  const V shifted = x * splat<W>(kInvLn2) + splat<W>(kRound);
  const V k = shifted - splat<W>(kRound);
  const V r = (x - k * splat<W>(kLn2Hi)) - k * splat<W>(kLn2Lo);
  const V r2 = r * r, r4 = r2 * r2;
  const V q01 = splat<W>(1.0f) + r;
  const V q23 = splat<W>(1.0f / 2) + splat<W>(1.0f / 6) * r;
  const V q456 = splat<W>(1.0f / 24) + splat<W>(1.0f / 120) * r + splat<W>(1.0f / 720) * r2;
  const V p = (q01 + q23 * r2) + q456 * r4;
  // The low bits of `shifted` hold k as a two's-complement integer.
  Vi<W> ki, round_bits;
  std::memcpy(&ki, &shifted, sizeof ki);
  const V round = splat<W>(kRound);
  std::memcpy(&round_bits, &round, sizeof round_bits);
  const Vi<W> bits = ((ki - round_bits) + 127) << 23;
  V scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

using PackedFace = FilterWork::Record;
static_assert(sizeof(PackedFace) == 32);

void size_records(std::vector<PackedFace>& out, std::size_t n) {
  if (out.capacity() < n) {  // the neighbours' records are read at random: huge pages
    std::vector<PackedFace>().swap(out);
    out.reserve(n);
    advise_huge_pages(out.data(), n * sizeof(PackedFace));
  }
  out.resize(n);
}

// Centroids are stored relative to face 0's, so a mesh far from the origin keeps its precision (any
// fixed origin gives the same weights up to rounding; this one depends on nothing but the input).
void pack_faces(const FaceGeometry& g, const FilterWork* work, std::vector<PackedFace>& out) {
  const auto nf = static_cast<long>(g.normals.size());
  const bool stored = !g.centroids.empty();
  if (!stored && (work == nullptr || work->positions == nullptr || work->faces == nullptr))
    throw std::logic_error("filter_face_normals: geometry without centroids and no positions to compute them from");
  auto centroid = [&](long f) -> Vec3 { return stored ? g.centroids[f] : face_centroid(*work->positions, (*work->faces)[f]); };
  const Vec3 mid = nf > 0 ? centroid(0) : Vec3::Zero();
  size_records(out, g.normals.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nf; ++i) out[i] = FilterWork::record(g.normals[i], g.areas[i], centroid(i), mid);
}

// The eight neighbours' fields, lanes 0-7 (as one eight-lane vector or two four-lane halves).
template <int W>
struct Group {
  static constexpr int kParts = 8 / W;
  Vf<W> nx[kParts], ny[kParts], nz[kParts], a[kParts], cx[kParts], cy[kParts], cz[kParts], live[kParts];
};

// The kernel widths as the lanes use them.
struct Widths {
  float ss2, inv_ss2, inv_two_sc2;
  Widths(double sigma_c, double sigma_s)
      : ss2(static_cast<float>(sigma_s * sigma_s)), inv_ss2(static_cast<float>(1.0 / (sigma_s * sigma_s))),
        inv_two_sc2(static_cast<float>(1.0 / (2.0 * sigma_c * sigma_c))) {}
};

// Tukey's estimator, the default and the one --auto uses, for one face: neighbours k..k+7 go to lanes 0-7
// (lanes past the end of a neighbourhood, and neighbours the estimator rejects, get weight 0), each lane
// sums its own, and the eight lane sums are added as ((0+1)+(2+3))+((4+5)+(6+7)). The two kernels below
// differ only in how they fill a Group (AVX2 loads and shuffles cannot sit in code compiled for SSE2).
template <int W>
struct FaceTerms {
  static constexpr int kParts = 8 / W;
  Vf<W> nx, ny, nz, cx, cy, cz, ss2, inv_ss2, inv_two_sc2;
  Vf<W> sx[kParts], sy[kParts], sz[kParts];
  FaceTerms(const PackedFace& f, const Widths& w)
      : nx(splat<W>(f.nx)), ny(splat<W>(f.ny)), nz(splat<W>(f.nz)), cx(splat<W>(f.cx)), cy(splat<W>(f.cy)), cz(splat<W>(f.cz)),
        ss2(splat<W>(w.ss2)), inv_ss2(splat<W>(w.inv_ss2)), inv_two_sc2(splat<W>(w.inv_two_sc2)) {
    for (int p = 0; p < kParts; ++p) sx[p] = sy[p] = sz[p] = splat<W>(0.0f);
  }
  // Adds the eight neighbours' terms to the lane sums: the same operations for every lane width.
  [[gnu::always_inline]] void add(const Group<W>& q) {
    using V = Vf<W>;
    for (int p = 0; p < kParts; ++p) {
      const V dx = nx - q.nx[p], dy = ny - q.ny[p], dz = nz - q.nz[p];
      const V x2 = dx * dx + dy * dy + dz * dz;
      const V ex = cx - q.cx[p], ey = cy - q.cy[p], ez = cz - q.cz[p];
      const V d2 = ex * ex + ey * ey + ez * ez;
      const V u = splat<W>(1.0f) - x2 * inv_ss2;
      const V w = splat<W>(0.5f) * u * u;
      V f = (q.a[p] * exp_nonpositive<W>(-d2 * inv_two_sc2) * w) * q.live[p];
      f = x2 <= ss2 ? f : splat<W>(0.0f);
      sx[p] += f * q.nx[p];
      sy[p] += f * q.ny[p];
      sz[p] += f * q.nz[p];
    }
  }
  // The three lane sums, each added in the fixed order.
  [[gnu::always_inline]] void sums(float s[3]) const {
    if constexpr (W == 8) {
      // The same sums by shuffles: lane 0 gets (0+1), then (0+1)+(2+3), then that plus (4+5)+(6+7).
      const Vf<8>* v[3] = {&sx[0], &sy[0], &sz[0]};
      for (int c = 0; c < 3; ++c) {
        Vf<8> x = *v[c] + __builtin_shufflevector(*v[c], *v[c], 1, 0, 3, 2, 5, 4, 7, 6);
        x = x + __builtin_shufflevector(x, x, 2, 3, 0, 1, 6, 7, 4, 5);
        x = x + __builtin_shufflevector(x, x, 4, 5, 6, 7, 0, 1, 2, 3);
        s[c] = x[0];
      }
    } else {
      float lane[3][8];
      for (int p = 0; p < kParts; ++p)
        for (int l = 0; l < W; ++l) lane[0][p * W + l] = sx[p][l], lane[1][p * W + l] = sy[p][l], lane[2][p * W + l] = sz[p][l];
      for (int c = 0; c < 3; ++c) {
        const float* v = lane[c];
        s[c] = ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
      }
    }
  }
  // The normalized sum, or `own` if every weight vanished.
  [[gnu::always_inline]] Vec3 result(const Vec3& own) const {
    float s[3];
    sums(s);
    const Vec3 sum(s[0], s[1], s[2]);
    const double len = sum.norm();
    return len > 0.0 ? Vec3(sum / len) : own;
  }
};

// Lane l of neighbours k.. of face i: the neighbour's index, or i itself past the end of the row (its
// `live` lane is 0 then).
[[gnu::always_inline]] inline int lane_index(int i, const int* row, int at, int count) { return at < count ? row[at] : i; }

struct KernelArgs {
  const PackedFace* faces;
  const FaceGeometry& g;
  double sigma_c;
  const std::vector<double>* face_sigma;
  std::vector<Vec3>& out;
  Widths global;  // every face's, unless face_sigma
  [[nodiscard]] Widths widths(long i) const { return face_sigma != nullptr ? Widths(sigma_c, (*face_sigma)[i]) : global; }
};

// Adds neighbours index[0..7] (the first `live` of them real) to face terms `t`, reading each
// neighbour's 32 bytes as two 16-byte halves (normal and area; centroid), neighbours l and l+4 into the
// low and high half of one register, transposed 4x4 within the halves: plain loads and in-lane shuffles
// (AVX2 gathers are microcoded and slow on many processors).
__attribute__((target("avx2"), always_inline)) inline void add_group_avx2(const float* base, const int* index, int live, Group<8>& q,
                                                                          FaceTerms<8>& t) {
  __m256 na[4], cc[4];
  for (int l = 0; l < 4; ++l) {
    const float* lo = base + 8 * static_cast<std::ptrdiff_t>(index[l]);
    const float* hi = base + 8 * static_cast<std::ptrdiff_t>(index[l + 4]);
    na[l] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(lo)), _mm_load_ps(hi), 1);
    cc[l] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(lo + 4)), _mm_load_ps(hi + 4), 1);
  }
  const __m256 t0 = _mm256_unpacklo_ps(na[0], na[1]), t1 = _mm256_unpackhi_ps(na[0], na[1]);
  const __m256 t2 = _mm256_unpacklo_ps(na[2], na[3]), t3 = _mm256_unpackhi_ps(na[2], na[3]);
  q.nx[0] = _mm256_shuffle_ps(t0, t2, 0x44);
  q.ny[0] = _mm256_shuffle_ps(t0, t2, 0xEE);
  q.nz[0] = _mm256_shuffle_ps(t1, t3, 0x44);
  q.a[0] = _mm256_shuffle_ps(t1, t3, 0xEE);
  const __m256 u0 = _mm256_unpacklo_ps(cc[0], cc[1]), u1 = _mm256_unpackhi_ps(cc[0], cc[1]);
  const __m256 u2 = _mm256_unpacklo_ps(cc[2], cc[3]), u3 = _mm256_unpackhi_ps(cc[2], cc[3]);
  q.cx[0] = _mm256_shuffle_ps(u0, u2, 0x44);
  q.cy[0] = _mm256_shuffle_ps(u0, u2, 0xEE);
  q.cz[0] = _mm256_shuffle_ps(u1, u3, 0x44);
  const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  q.live[0] = _mm256_and_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(live), lanes)), _mm256_set1_ps(1.0f));
  t.add(q);
}

// Faces b..b+n-1 (n <= kTail) of the AVX2 kernel: their sums (x, y, z, a face per lane) normalized four at
// a time, `own` where every weight vanished. The same IEEE operations as FaceTerms::result on one face
// (the squared length summed as (x^2 + y^2) + z^2, as Eigen's norm() does; a square root; three
// divisions), so the bits do not depend on the kernel. Done per face, each face's tail waited on its
// square root and divisions (a third of the kernel's samples on fandisk); here they overlap.
constexpr int kTail = 16;
__attribute__((target("avx2"), always_inline)) inline void normalize_tail_avx2(const float* sx, const float* sy, const float* sz, int n,
                                                                               Vec3* out, const Vec3* own) {
  for (int j = 0; j < n; j += 4) {
    const __m256d x = _mm256_cvtps_pd(_mm_load_ps(sx + j)), y = _mm256_cvtps_pd(_mm_load_ps(sy + j)),
                  z = _mm256_cvtps_pd(_mm_load_ps(sz + j));
    const __m256d len = _mm256_sqrt_pd(_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)), _mm256_mul_pd(z, z)));
    alignas(32) double l[4], qx[4], qy[4], qz[4];
    _mm256_store_pd(l, len);
    _mm256_store_pd(qx, _mm256_div_pd(x, len));
    _mm256_store_pd(qy, _mm256_div_pd(y, len));
    _mm256_store_pd(qz, _mm256_div_pd(z, len));
    for (int m = 0; m < 4 && j + m < n; ++m) out[j + m] = l[m] > 0.0 ? Vec3(qx[m], qy[m], qz[m]) : own[j + m];
  }
}

template <class Rows>
__attribute__((target("avx2"))) void filter_tukey_avx2(const KernelArgs& k, const Rows& nbh, long first, long last) {
  const auto* base = reinterpret_cast<const float*>(k.faces);
  Group<8> q{};
  alignas(16) float tail[3][kTail] = {};
  long tail_first = first;
  for (long i = first; i < last; ++i) {
    // The records of the neighbours of the face eight ahead are asked for now: on meshes whose records
    // outgrow the caches the kernel waited on those loads (the Morton order keeps most neighbours near,
    // not all of them).
    if (i + 8 < last) {
      int ahead = 0;
      if (const std::uint16_t* d = nbh.differences(i + 8, ahead))
        for (int l = 0; l < ahead; ++l) __builtin_prefetch(base + 8 * static_cast<std::ptrdiff_t>(i + 8 + static_cast<std::int16_t>(d[l])));
    }
    FaceTerms<8> t(k.faces[i], k.widths(i));
    const auto self = static_cast<int>(i);
    alignas(32) int index[8];
    int count = 0;
    // A packed row's 16-bit differences become indices eight at a time; the last group of a row pads
    // with face i itself.
    if (const std::uint16_t* d = nbh.differences(i, count)) {
      int at = 0;
      for (; at + 8 <= count; at += 8) {
        const __m256i v = _mm256_add_epi32(_mm256_cvtepi16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(d + at))),
                                           _mm256_set1_epi32(self));
        _mm256_store_si256(reinterpret_cast<__m256i*>(index), v);
        add_group_avx2(base, index, 8, q, t);
      }
      if (at < count) {
        for (int l = 0; l < 8; ++l) index[l] = at + l < count ? self + static_cast<std::int16_t>(d[at + l]) : self;
        add_group_avx2(base, index, count - at, q, t);
      }
    } else {
      const int* row = nbh.row(i, count);
      for (int at = 0; at < count; at += 8) {
        const int* group = row + at;
        if (at + 8 > count) {
          for (int l = 0; l < 8; ++l) index[l] = lane_index(self, row, at + l, count);
          group = index;
        }
        add_group_avx2(base, group, count - at, q, t);
      }
    }
    float sum[3];
    t.sums(sum);
    const auto at = static_cast<int>(i - tail_first);
    tail[0][at] = sum[0], tail[1][at] = sum[1], tail[2][at] = sum[2];
    if (at + 1 == kTail || i + 1 == last) {
      normalize_tail_avx2(tail[0], tail[1], tail[2], at + 1, k.out.data() + tail_first, k.g.normals.data() + tail_first);
      tail_first = i + 1;
    }
  }
}

template <class Rows>
void filter_tukey_sse2(const KernelArgs& k, const Rows& nbh, long first, long last) {
  Group<4> q{};
  for (long i = first; i < last; ++i) {
    FaceTerms<4> t(k.faces[i], k.widths(i));
    int count = 0;
    const int* row = nbh.row(i, count);
    for (int at = 0; at < count; at += 8) {
      for (int p = 0; p < 2; ++p)
        for (int l = 0; l < 4; ++l) {
          const int lane = at + 4 * p + l;
          const PackedFace& f = k.faces[lane_index(static_cast<int>(i), row, lane, count)];
          q.nx[p][l] = f.nx, q.ny[p][l] = f.ny, q.nz[p][l] = f.nz, q.a[p][l] = f.area;
          q.cx[p][l] = f.cx, q.cy[p][l] = f.cy, q.cz[p][l] = f.cz;
          q.live[p][l] = lane < count ? 1.0f : 0.0f;
        }
      t.add(q);
    }
    k.out[i] = t.result(k.g.normals[i]);
  }
}

// The other estimators, one neighbour at a time; the estimator is a template parameter so the hot loop
// has no switch in it.
template <RobustEstimator E, class MakeRows>
void filter_impl(const FaceGeometry& g, MakeRows make_rows, double sigma_c, double global_sigma_s,
                 const std::vector<double>* face_sigma, std::vector<Vec3>& out) {
  const auto nf = static_cast<long>(g.normals.size());
  const double inv_two_sc2 = 1.0 / (2.0 * sigma_c * sigma_c);
#pragma omp parallel
  {
    const auto nbh = make_rows();
#pragma omp for schedule(dynamic, 512)
    for (long i = 0; i < nf; ++i) {
      const double sigma_s = face_sigma != nullptr ? (*face_sigma)[i] : global_sigma_s;
      const double ss2 = sigma_s * sigma_s;
      const double inv_two_ss2 = 1.0 / (2.0 * sigma_s * sigma_s);
      const Vec3& ni = g.normals[i];
      const Vec3& ci = g.centroids[i];
      Vec3 sum = Vec3::Zero();
      int count = 0;
      const int* row = nbh.row(i, count);
      for (const int* j = row; j != row + count; ++j) {
        const double aj = g.areas[*j];
        if (aj == 0.0) continue;
        const Vec3& nj = g.normals[*j];
        const double x2 = (ni - nj).squaredNorm();
        double w;
        if constexpr (E == RobustEstimator::gaussian) {
          w = std::exp(-x2 * inv_two_ss2);
        } else if constexpr (E == RobustEstimator::huber) {
          w = x2 <= ss2 ? 1.0 : sigma_s / std::sqrt(x2);
        } else {
          w = 1.0 / (1.0 + x2 * inv_two_ss2);
        }
        const double d2 = (ci - g.centroids[*j]).squaredNorm();
        sum += (aj * exp_nonpositive(-d2 * inv_two_sc2) * w) * nj;
      }
      const double len = sum.norm();
      out[i] = len > 0.0 ? Vec3(sum / len) : ni;
    }
  }
}

FilterIsa g_isa = FilterIsa::best;

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2") != 0;
  return has;
}

}  // namespace

void set_filter_isa(FilterIsa isa) { g_isa = isa; }

void FilterWork::size_records(std::size_t n) { scanmesh::size_records(records, n); }

std::size_t refresh_faces(const std::vector<Vec3>& positions, const std::vector<Vec3>& input, const std::vector<Face>& faces,
                          double sliver_limit, FaceGeometry& geometry, FilterWork& work, std::vector<std::uint8_t>& slivers) {
  const auto nf = static_cast<long>(faces.size());
  geometry.normals.resize(faces.size());
  geometry.areas.resize(faces.size());
  std::vector<Vec3>().swap(geometry.centroids);
  work.size_records(faces.size());
  const bool guard = sliver_limit > 0.0;
  if (guard) slivers.resize(faces.size());
  const Vec3 origin = nf > 0 ? face_centroid(positions, faces[0]) : Vec3::Zero();
  Vec3* const normal = geometry.normals.data();
  double* const area = geometry.areas.data();
  FilterWork::Record* const record = work.records.data();
  std::size_t count = 0;
#pragma omp parallel for schedule(static) reduction(+ : count)
  for (long f = 0; f < nf; ++f) {
    const Face& t = faces[f];
    const Vec3& a = positions[t[0]];
    const Vec3& b = positions[t[1]];
    const Vec3& c = positions[t[2]];
    // triangle_normal's operations, from the cross product the sliver test shares.
    const TriangleTerms terms(a, b, c);
    const double len = std::sqrt(terms.cross2());
    area[f] = len > 1e-300 ? 0.5 * len : 0.0;
    normal[f] = len > 1e-300 ? Vec3(terms.cx / len, terms.cy / len, terms.cz / len) : Vec3::Zero();
    record[f] = FilterWork::record(normal[f], area[f], face_centroid(positions, t), origin);
    if (guard) {
      const bool sliver = terms.sliver(sliver_limit) && triangle_shape(a, b, c) > triangle_shape(input[t[0]], input[t[1]], input[t[2]]);
      slivers[f] = sliver ? 1 : 0;
      count += sliver ? 1 : 0;
    }
  }
  work.records_ready = true;
  return count;
}

namespace {

// `make_rows()` gives each thread its view of the neighbourhood table.
template <class MakeRows>
void filter_with(const FaceGeometry& g, MakeRows make_rows, double sigma_c, double sigma_s, RobustEstimator estimator,
                 std::vector<Vec3>& filtered, const std::vector<double>* face_sigma, FilterWork* work) {
  if (estimator != RobustEstimator::tukey && g.centroids.empty() && !g.normals.empty())
    throw std::logic_error("filter_face_normals: the robust estimators other than Tukey's need the geometry's centroids");
  if (&filtered == &g.normals && estimator != RobustEstimator::tukey) {
    // In place: the estimators below read the neighbours' normals from `g` as they write.
    std::vector<Vec3> out;
    filter_with(g, make_rows, sigma_c, sigma_s, estimator, out, face_sigma, work);
    filtered.swap(out);
    return;
  }
  filtered.resize(g.normals.size());
  using Rows = decltype(make_rows());
  switch (estimator) {
    case RobustEstimator::tukey: {
      const auto nf = static_cast<long>(g.normals.size());
      constexpr long kBlock = 512;
      std::vector<PackedFace> local;
      std::vector<PackedFace>& packed = work != nullptr ? work->records : local;
      if (work == nullptr || !work->records_ready || packed.size() != g.normals.size()) pack_faces(g, work, packed);
      if (work != nullptr) work->records_ready = false;
      const KernelArgs args{packed.data(), g, sigma_c, face_sigma, filtered, Widths(sigma_c, sigma_s)};
      const auto kernel = g_isa == FilterIsa::best && cpu_has_avx2() ? filter_tukey_avx2<Rows> : filter_tukey_sse2<Rows>;
#pragma omp parallel
      {
        const Rows rows = make_rows();
#pragma omp for schedule(dynamic, 1)
        for (long b = 0; b < (nf + kBlock - 1) / kBlock; ++b) kernel(args, rows, b * kBlock, std::min(nf, (b + 1) * kBlock));
      }
      break;
    }
    case RobustEstimator::gaussian: filter_impl<RobustEstimator::gaussian>(g, make_rows, sigma_c, sigma_s, face_sigma, filtered); break;
    case RobustEstimator::huber: filter_impl<RobustEstimator::huber>(g, make_rows, sigma_c, sigma_s, face_sigma, filtered); break;
    case RobustEstimator::lorentzian: filter_impl<RobustEstimator::lorentzian>(g, make_rows, sigma_c, sigma_s, face_sigma, filtered); break;
  }
}

}  // namespace

void filter_face_normals(const FaceGeometry& geometry, const Adjacency& neighbourhoods, double sigma_c,
                         double sigma_s, RobustEstimator estimator, std::vector<Vec3>& filtered,
                         const std::vector<double>* face_sigma, FilterWork* work) {
  filter_with(geometry, [&] { return PlainRows{neighbourhoods}; }, sigma_c, sigma_s, estimator, filtered, face_sigma, work);
}

void filter_face_normals(const FaceGeometry& geometry, const PackedRows& neighbourhoods, double sigma_c,
                         double sigma_s, RobustEstimator estimator, std::vector<Vec3>& filtered,
                         const std::vector<double>* face_sigma, FilterWork* work) {
  filter_with(geometry, [&] { return UnpackedRows{neighbourhoods, row_buffer(neighbourhoods)}; }, sigma_c, sigma_s, estimator,
              filtered, face_sigma, work);
}

double mean_centroid_distance(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry) {
  // Over manifold edges; only if there are none, consecutive faces of non-manifold edges (all pairs of a
  // fan of k faces would cost k^2).
  double sum = 0.0;
  std::size_t n = 0;
  for (int pass = 0; pass < 2 && n == 0; ++pass)
    for (std::size_t e = 0; e < topology.edges.size(); ++e) {
      const int* f = topology.edge_faces.begin(e);
      const int count = topology.edge_faces.size(e);
      if (count < 2 || (pass == 0 && count != 2)) continue;
      for (int a = 0; a + 1 < count; ++a) {
        sum += (geometry.centroids[f[a]] - geometry.centroids[f[a + 1]]).norm();
        ++n;
      }
    }
  if (n > 0) return sum / static_cast<double>(n);
  return mean_edge_length(mesh, topology);
}

int max_neighbourhood_size(double radius_factor) {
  return static_cast<int>(std::max(128.0, std::ceil(32.0 * radius_factor * radius_factor)));
}

Adjacency face_neighbourhoods(const Topology& topology, const FaceGeometry& geometry, double radius,
                              NeighbourhoodKind kind, int max_size, std::size_t* capped, bool spatially_ordered) {
  if (kind == NeighbourhoodKind::ball) return radius_neighbourhoods(geometry.centroids, radius, max_size, capped, spatially_ordered);

  // Connected ball: grow from face i through edge-adjacent faces whose centroids are within the radius.
  const auto nf = static_cast<long>(geometry.centroids.size());
  std::vector<std::vector<int>> rows(geometry.centroids.size());
  const double r2 = radius * radius;
  std::size_t cut = 0;
#pragma omp parallel reduction(+ : cut)
  {
    std::vector<int> stack, seen;
    std::vector<long> stamp(geometry.centroids.size(), -1);  // stamp[f] == i: f already in face i's region
#pragma omp for schedule(dynamic, 256)
    for (long i = 0; i < nf; ++i) {
      seen.assign(1, static_cast<int>(i));
      stack.assign(1, static_cast<int>(i));
      stamp[i] = i;
      bool full = false;
      while (!stack.empty() && !full) {
        const int f = stack.back();
        stack.pop_back();
        for (const int* g = topology.face_faces.begin(f); g != topology.face_faces.end(f); ++g) {
          if (stamp[*g] == i) continue;
          if ((geometry.centroids[*g] - geometry.centroids[i]).squaredNorm() > r2) continue;
          stamp[*g] = i;
          seen.push_back(*g);
          stack.push_back(*g);
          if (seen.size() >= static_cast<std::size_t>(max_size)) {
            full = true;
            ++cut;
            break;
          }
        }
      }
      std::sort(seen.begin(), seen.end());
      rows[i] = seen;
    }
  }
  if (capped != nullptr) *capped = cut;
  Adjacency a;
  a.offsets.assign(rows.size() + 1, 0);
  for (std::size_t i = 0; i < rows.size(); ++i) a.offsets[i + 1] = a.offsets[i] + static_cast<int>(rows[i].size());
  a.indices.reserve(static_cast<std::size_t>(a.offsets.back()));
  for (const auto& r : rows) a.indices.insert(a.indices.end(), r.begin(), r.end());
  return a;
}

PackedRows packed_face_neighbourhoods(const Topology& topology, const FaceGeometry& geometry, double radius,
                                      NeighbourhoodKind kind, int max_size, std::size_t* capped, bool spatially_ordered) {
  if (kind == NeighbourhoodKind::ball)
    return packed_radius_neighbourhoods(geometry.centroids, radius, max_size, capped, spatially_ordered);
  return PackedRows::from(face_neighbourhoods(topology, geometry, radius, kind, max_size, capped, spatially_ordered));
}

}  // namespace scanmesh
