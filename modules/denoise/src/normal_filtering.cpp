#include "scanmesh/normal_filtering.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "scanmesh/neighbourhoods.h"

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
  [[gnu::always_inline]] const int* row(long i, int& count) const {
    count = a.size(static_cast<std::size_t>(i));
    return a.begin(static_cast<std::size_t>(i));
  }
};
struct UnpackedRows {
  const PackedRows& p;
  int* buffer;
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

// The Tukey kernel works on four neighbours at a time, as four lanes of doubles. On a machine with AVX2
// the four lanes are one register; otherwise they are two SSE2 registers of two lanes, processed one after
// the other (letting GCC split four-lane vectors itself spills them to the stack and ran 1.7x slower than
// scalar code). Either way each lane does the same IEEE operations in the same order, -ffp-contract=off
// keeps a*b+c from becoming an FMA in one and not the other, and the lanes are added up in one fixed
// order, so the result depends neither on the thread count nor on the instruction set.
// GCC notes that passing 32-byte vectors changes the ABI without AVX; these helpers are always inlined,
// so no such vector crosses a call.
#pragma GCC diagnostic ignored "-Wpsabi"
template <int W>
struct Lanes;
template <>
struct Lanes<2> {
  typedef double D __attribute__((vector_size(16)));
  typedef std::int64_t I __attribute__((vector_size(16)));
};
template <>
struct Lanes<4> {
  typedef double D __attribute__((vector_size(32)));
  typedef std::int64_t I __attribute__((vector_size(32)));
};
template <int W>
using Vd = typename Lanes<W>::D;
template <int W>
using Vi = typename Lanes<W>::I;

template <int W>
[[gnu::always_inline]] inline Vd<W> splat(double x) {
  Vd<W> v;
  for (int l = 0; l < W; ++l) v[l] = x;
  return v;
}

// e^x for x <= 0, W at a time and without a table: x = k ln2 + r with |r| <= ln2/2, e^r from its Taylor
// polynomial to degree 10 (relative error below 3e-13, far below anything a weight can show), evaluated
// in Estrin's scheme so the dependency chain is 4 multiplications deep instead of 10; 2^k from the
// exponent bits. Below -700 (and for NaN) the result is e^-700, which no sum of weights can tell from zero.
template <int W>
[[gnu::always_inline]] inline Vd<W> exp_nonpositive(Vd<W> x) {
  using V = Vd<W>;
  x = x >= splat<W>(-700.0) ? x : splat<W>(-700.0);
  constexpr double kInvLn2 = 1.4426950408889634;
  constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;
  constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52: adding it rounds to an integer
  const V shifted = x * splat<W>(kInvLn2) + splat<W>(kRound);
  const V k = shifted - splat<W>(kRound);
  const V r = (x - k * splat<W>(kLn2Hi)) - k * splat<W>(kLn2Lo);
  const V r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
  const V q01 = splat<W>(1.0) + r;
  const V q23 = splat<W>(1.0 / 2) + splat<W>(1.0 / 6) * r;
  const V q45 = splat<W>(1.0 / 24) + splat<W>(1.0 / 120) * r;
  const V q67 = splat<W>(1.0 / 720) + splat<W>(1.0 / 5040) * r;
  const V q8a = splat<W>(1.0 / 40320) + splat<W>(1.0 / 362880) * r + splat<W>(1.0 / 3628800) * r2;
  const V p = ((q01 + q23 * r2) + (q45 + q67 * r2) * r4) + q8a * r8;
  // The low bits of `shifted` hold k as a two's-complement integer.
  Vi<W> ki, round_bits;
  std::memcpy(&ki, &shifted, sizeof ki);
  const V round = splat<W>(kRound);
  std::memcpy(&round_bits, &round, sizeof round_bits);
  const Vi<W> bits = ((ki - round_bits) + 1023) << 52;
  V scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return p * scale;
}

// Tukey's estimator, the default and the one --auto uses, for faces [first, last): neighbours k, k+1,
// k+2, k+3 of face i go to lanes 0-3 (lanes past the end of a neighbourhood, and neighbours the estimator
// rejects, get weight 0), each lane sums its own, and the four lane sums are added as (0+1)+(2+3).
template <int W, class Rows>
[[gnu::always_inline]] inline void filter_tukey(const FaceGeometry& g, const Rows& nbh, double sigma_c,
                                                double global_sigma_s, const std::vector<double>* face_sigma,
                                                std::vector<Vec3>& out, long first, long last) {
  using V = Vd<W>;
  constexpr int kGroups = 4 / W;
  const V inv_two_sc2 = splat<W>(1.0 / (2.0 * sigma_c * sigma_c));
  const Vec3* normals = g.normals.data();
  const Vec3* centroids = g.centroids.data();
  const double* areas = g.areas.data();
  for (long i = first; i < last; ++i) {
    const double sigma_s = face_sigma != nullptr ? (*face_sigma)[i] : global_sigma_s;
    const V ss2 = splat<W>(sigma_s * sigma_s);
    const V inv_ss2 = splat<W>(1.0 / (sigma_s * sigma_s));
    const Vec3& ni = normals[i];
    const Vec3& ci = centroids[i];
    const V nx = splat<W>(ni.x()), ny = splat<W>(ni.y()), nz = splat<W>(ni.z());
    const V cx = splat<W>(ci.x()), cy = splat<W>(ci.y()), cz = splat<W>(ci.z());
    V sx[kGroups], sy[kGroups], sz[kGroups];
    for (int q = 0; q < kGroups; ++q) sx[q] = sy[q] = sz[q] = splat<W>(0.0);
    int count = 0;
    const int* row = nbh.row(i, count);
    for (int k = 0; k < count; k += 4) {
      for (int q = 0; q < kGroups; ++q) {
        V mx, my, mz, ex, ey, ez, a, live;
        for (int l = 0; l < W; ++l) {
          const int at = k + q * W + l;
          const bool in = at < count;
          const int j = in ? row[at] : static_cast<int>(i);
          live[l] = in ? 1.0 : 0.0;
          mx[l] = normals[j].x(), my[l] = normals[j].y(), mz[l] = normals[j].z();
          ex[l] = centroids[j].x(), ey[l] = centroids[j].y(), ez[l] = centroids[j].z();
          a[l] = areas[j];
        }
        const V dx = nx - mx, dy = ny - my, dz = nz - mz;
        const V x2 = dx * dx + dy * dy + dz * dz;
        ex = cx - ex, ey = cy - ey, ez = cz - ez;
        const V d2 = ex * ex + ey * ey + ez * ez;
        const V u = splat<W>(1.0) - x2 * inv_ss2;
        const V w = splat<W>(0.5) * u * u;
        V f = (a * exp_nonpositive<W>(-d2 * inv_two_sc2) * w) * live;
        f = x2 <= ss2 ? f : splat<W>(0.0);
        sx[q] += f * mx;
        sy[q] += f * my;
        sz[q] += f * mz;
      }
    }
    double lane[3][4];
    for (int q = 0; q < kGroups; ++q)
      for (int l = 0; l < W; ++l) lane[0][q * W + l] = sx[q][l], lane[1][q * W + l] = sy[q][l], lane[2][q * W + l] = sz[q][l];
    const Vec3 sum((lane[0][0] + lane[0][1]) + (lane[0][2] + lane[0][3]), (lane[1][0] + lane[1][1]) + (lane[1][2] + lane[1][3]),
                   (lane[2][0] + lane[2][1]) + (lane[2][2] + lane[2][3]));
    const double len = sum.norm();
    out[i] = len > 0.0 ? Vec3(sum / len) : ni;
  }
}

template <class Rows>
__attribute__((target("avx2"))) void filter_tukey_avx2(const FaceGeometry& g, const Rows& nbh, double sigma_c,
                                                       double sigma_s, const std::vector<double>* face_sigma,
                                                       std::vector<Vec3>& out, long first, long last) {
  filter_tukey<4>(g, nbh, sigma_c, sigma_s, face_sigma, out, first, last);
}

template <class Rows>
void filter_tukey_sse2(const FaceGeometry& g, const Rows& nbh, double sigma_c, double sigma_s,
                       const std::vector<double>* face_sigma, std::vector<Vec3>& out, long first, long last) {
  filter_tukey<2>(g, nbh, sigma_c, sigma_s, face_sigma, out, first, last);
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

namespace {

// `make_rows()` gives each thread its view of the neighbourhood table.
template <class MakeRows>
void filter_with(const FaceGeometry& g, MakeRows make_rows, double sigma_c, double sigma_s, RobustEstimator estimator,
                 std::vector<Vec3>& filtered, const std::vector<double>* face_sigma) {
  filtered.resize(g.normals.size());
  using Rows = decltype(make_rows());
  switch (estimator) {
    case RobustEstimator::tukey: {
      const auto nf = static_cast<long>(g.normals.size());
      constexpr long kBlock = 512;
      const auto kernel = g_isa == FilterIsa::best && cpu_has_avx2() ? filter_tukey_avx2<Rows> : filter_tukey_sse2<Rows>;
#pragma omp parallel
      {
        const Rows rows = make_rows();
#pragma omp for schedule(dynamic, 1)
        for (long b = 0; b < (nf + kBlock - 1) / kBlock; ++b)
          kernel(g, rows, sigma_c, sigma_s, face_sigma, filtered, b * kBlock, std::min(nf, (b + 1) * kBlock));
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
                         const std::vector<double>* face_sigma) {
  filter_with(geometry, [&] { return PlainRows{neighbourhoods}; }, sigma_c, sigma_s, estimator, filtered, face_sigma);
}

void filter_face_normals(const FaceGeometry& geometry, const PackedRows& neighbourhoods, double sigma_c,
                         double sigma_s, RobustEstimator estimator, std::vector<Vec3>& filtered,
                         const std::vector<double>* face_sigma) {
  filter_with(geometry, [&] { return UnpackedRows{neighbourhoods, row_buffer(neighbourhoods)}; }, sigma_c, sigma_s, estimator,
              filtered, face_sigma);
}

void filter_boundary_normals(const std::vector<Vec3>& positions, BoundaryCurves& curves,
                             const std::vector<Vec3>& filtered_face_normals, double sigma_s,
                             RobustEstimator estimator, double window) {
  std::vector<Vec3>& filtered = curves.normals;
  const std::size_t ne = curves.edges.size();
  std::vector<Vec3> m(ne), mid(ne);
  std::vector<double> len(ne);
  double mean_len = 0.0;
  for (std::size_t e = 0; e < ne; ++e) {
    const auto& edge = curves.edges[e];
    const Vec3 d = positions[edge.b] - positions[edge.a];
    len[e] = d.norm();
    mean_len += len[e];
    mid[e] = 0.5 * (positions[edge.a] + positions[edge.b]);
    const Vec3 out = d.cross(filtered_face_normals[edge.face]);
    const double l = out.norm();
    m[e] = l > 0.0 ? Vec3(out / l) : Vec3::Zero();
  }
  filtered.assign(ne, Vec3::Zero());
  if (ne == 0) return;
  mean_len /= static_cast<double>(ne);
  const double sigma_c = mean_len;
  const double radius = window * mean_len;
  const auto loops = static_cast<long>(curves.loop_edges.rows());
#pragma omp parallel for schedule(dynamic, 1)
  for (long l = 0; l < loops; ++l) {
    const int* edges = curves.loop_edges.begin(l);
    const int n = curves.loop_edges.size(l);
    const bool closed = curves.loop_closed[l] != 0;
    for (int k = 0; k < n; ++k) {
      const int i = edges[k];
      Vec3 sum = Vec3::Zero();
      auto add = [&](int j) {
        const double x = (m[i] - m[j]).norm();
        const double d = (mid[i] - mid[j]).norm();
        sum += len[j] * std::exp(-d * d / (2.0 * sigma_c * sigma_c)) * robust_weight(estimator, x, sigma_s) * m[j];
        return d <= radius;
      };
      add(i);
      // Walk both ways along the loop while within the radius (at most half the loop, and at most
      // kBoundaryWindowMaxEdges, each way).
      for (int step = 1; step <= std::min(n / 2, kBoundaryWindowMaxEdges); ++step) {
        int kk = k + step;
        if (kk >= n) {
          if (!closed) break;
          kk -= n;
        }
        if ((mid[edges[kk]] - mid[i]).norm() > radius || !add(edges[kk])) break;
      }
      for (int step = 1; step <= std::min((n - 1) / 2, kBoundaryWindowMaxEdges); ++step) {
        int kk = k - step;
        if (kk < 0) {
          if (!closed) break;
          kk += n;
        }
        if ((mid[edges[kk]] - mid[i]).norm() > radius || !add(edges[kk])) break;
      }
      const double l2 = sum.norm();
      filtered[i] = l2 > 0.0 ? Vec3(sum / l2) : m[i];
    }
  }
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
