#pragma once
// Tiny meshes built in code for the tests.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "scanmesh/mesh.h"
#include "scanmesh/topology.h"

namespace scanmesh::test {

/// n x n quads of size h in the z = 0 plane, each split into two triangles (normals +z).
inline Mesh make_grid(int n, double h = 1.0) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.emplace_back(i * h, j * h, 0.0);
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

/// Closed axis-aligned cube [0,1]^3 with n x n quads per side (two triangles each), outward normals.
inline Mesh make_cube(int n) {
  Mesh m;
  std::map<std::tuple<long, long, long>, int> index;
  auto vertex = [&](const Vec3& p) {
    const auto key = std::make_tuple(std::lround(p.x() * n), std::lround(p.y() * n), std::lround(p.z() * n));
    auto [it, inserted] = index.try_emplace(key, static_cast<int>(m.positions.size()));
    if (inserted) m.positions.push_back(p);
    return it->second;
  };
  // Each side: origin o, in-plane axes u, v with u x v pointing outwards.
  const Vec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1), O(0, 0, 0);
  const std::array<std::array<Vec3, 3>, 6> sides = {{{O, Y, X}, {Z, X, Y}, {O, X, Z}, {Y, Z, X}, {O, Z, Y}, {X, Y, Z}}};
  for (const auto& side : sides)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 &o = side[0], &u = side[1], &v = side[2];  // not a structured binding: clang 14 cannot capture those
        auto p = [&](int a, int b) { return vertex(o + u * (double(a) / n) + v * (double(b) / n)); };
        const int a = p(i, j), b = p(i + 1, j), c = p(i + 1, j + 1), d = p(i, j + 1);
        m.faces.push_back({a, b, c});
        m.faces.push_back({a, c, d});
      }
  return m;
}

/// Unit icosphere with `levels` subdivisions (20 * 4^levels faces).
inline Mesh make_sphere(int levels) {
  Mesh m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  for (const auto& p : {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0), Vec3(0, -1, t), Vec3(0, 1, t),
                        Vec3(0, -1, -t), Vec3(0, 1, -t), Vec3(t, 0, -1), Vec3(t, 0, 1), Vec3(-t, 0, -1), Vec3(-t, 0, 1)})
    m.positions.push_back(p.normalized());
  m.faces = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
             {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = mid.try_emplace(key, static_cast<int>(m.positions.size()));
      if (inserted) m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      return it->second;
    };
    std::vector<Face> faces;
    for (const Face& f : m.faces) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      faces.push_back({f[0], a, c});
      faces.push_back({f[1], b, a});
      faces.push_back({f[2], c, b});
      faces.push_back({a, b, c});
    }
    m.faces = std::move(faces);
  }
  return m;
}

/// make_sphere(levels) made bumpy, each vertex's radius scaled by 1 + 0.05 sin(9 t) sin(8 f) + 0.05
/// cos(4 t + 3 f) (t azimuth, f polar angle): a smooth organic stand-in with relief of 5% of the radius
/// (about 28 edges per bump at 5 levels).
inline Mesh make_bumpy_sphere(int levels) {
  Mesh m = make_sphere(levels);
  for (auto& p : m.positions) {
    const double t = std::atan2(p.y(), p.x()), f = std::acos(std::clamp(p.z() / p.norm(), -1.0, 1.0));
    p *= 1.0 + 0.05 * std::sin(9 * t) * std::sin(8 * f) + 0.05 * std::cos(4 * t + 3 * f);
  }
  return m;
}

/// Spherical cap of the unit sphere around +z up to polar angle `theta_max`, built from `rings` rings of
/// `sectors` vertices plus the pole, so its boundary is a regular polygon (a circle's sampling).
inline Mesh make_cap(int rings, int sectors, double theta_max) {
  Mesh m;
  m.positions.emplace_back(0, 0, 1);
  for (int r = 1; r <= rings; ++r) {
    const double theta = theta_max * r / rings;
    for (int k = 0; k < sectors; ++k) {
      const double phi = 2.0 * M_PI * (k + 0.5 * (r % 2)) / sectors;
      m.positions.emplace_back(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  }
  auto id = [sectors](int r, int k) { return 1 + (r - 1) * sectors + ((k % sectors) + sectors) % sectors; };
  for (int k = 0; k < sectors; ++k) m.faces.push_back({0, id(1, k), id(1, k + 1)});
  for (int r = 1; r < rings; ++r)
    for (int k = 0; k < sectors; ++k) {
      // Odd rings are rotated by half a sector; pick the diagonal that keeps triangles well shaped.
      const int shift = r % 2;
      m.faces.push_back({id(r, k), id(r + 1, k + 1 - shift), id(r, k + 1)});
      m.faces.push_back({id(r + 1, k + 1 - shift), id(r, k), id(r + 1, k - shift)});
    }
  return m;
}

/// A closed CAD-like cylinder (radius 1, height 2, flat caps) whose side is tessellated coarsely (48
/// sectors) except for two bands ten times finer in both directions, joined to the coarse rings by zipper
/// strips of slivers: the locally refined tessellation CAD exporters make around details.
inline Mesh make_zippered_cylinder() {
  constexpr double kPi = 3.14159265358979323846;
  Mesh m;
  struct Ring {
    int start, count;
    double shift;  // in steps: alternate rings are offset by half a step, so triangles are not right-angled
  };
  auto add_ring = [&](double z, double radius, int count, double shift) {
    const Ring r{static_cast<int>(m.positions.size()), count, shift};
    for (int k = 0; k < count; ++k) {
      const double a = 2.0 * kPi * (k + shift) / count;
      m.positions.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
    }
    return r;
  };
  // Joins two rings by walking both in angle order (a zipper): rings of different counts give slivers.
  auto zip = [&](const Ring& a, const Ring& b, bool flip) {
    int i = 0, j = 0;
    auto angle = [](const Ring& r, int k) { return (k + r.shift) / r.count; };
    while (i < a.count || j < b.count) {
      Face f;
      if (j >= b.count || (i < a.count && angle(a, i + 1) <= angle(b, j + 1))) {
        f = {a.start + i % a.count, a.start + (i + 1) % a.count, b.start + j % b.count};
        ++i;
      } else {
        f = {a.start + i % a.count, b.start + (j + 1) % b.count, b.start + j % b.count};
        ++j;
      }
      if (flip) std::swap(f[1], f[2]);
      m.faces.push_back(f);
    }
  };
  const int coarse = 48, fine = 480;
  const double coarse_step = 0.87 * 2.0 * kPi / coarse, fine_step = 0.87 * 2.0 * kPi / fine;
  // Side: coarse, fine band, coarse, fine band, coarse (bottom to top).
  const double bounds[] = {-1.0, -0.45, -0.35, 0.35, 0.45, 1.0};
  std::vector<Ring> side;
  for (int part = 0; part < 5; ++part) {
    const bool is_fine = part % 2 == 1;
    const double step = is_fine ? fine_step : coarse_step;
    for (double z = bounds[part]; z < bounds[part + 1] - 1e-9; z += step)
      side.push_back(add_ring(z, 1.0, is_fine ? fine : coarse, 0.5 * static_cast<double>(side.size() % 2)));
  }
  side.push_back(add_ring(1.0, 1.0, coarse, 0.5 * static_cast<double>(side.size() % 2)));
  for (std::size_t r = 0; r + 1 < side.size(); ++r) zip(side[r], side[r + 1], false);
  // Flat caps: concentric rings down to a centre vertex.
  for (const bool top : {true, false}) {
    Ring outer = top ? side.back() : side.front();
    const double z = top ? 1.0 : -1.0;
    for (const double radius : {0.75, 0.5, 0.25}) {
      const Ring inner = add_ring(z, radius, std::max(6, static_cast<int>(std::lround(outer.count * radius / (radius + 0.25)))), outer.shift);
      zip(outer, inner, !top);
      outer = inner;
    }
    const int centre = static_cast<int>(m.positions.size());
    m.positions.emplace_back(0.0, 0.0, z);
    for (int k = 0; k < outer.count; ++k) {
      Face f{outer.start + k, outer.start + (k + 1) % outer.count, centre};
      if (!top) std::swap(f[1], f[2]);
      m.faces.push_back(f);
    }
  }
  return m;
}

/// Regular tetrahedron, outward normals.
inline Mesh make_tetrahedron() {
  Mesh m;
  m.positions = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
  m.faces = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  return m;
}

/// Moves every vertex by N(0, sigma) along z (for planes) using a fixed seed.
inline void jitter_z(Mesh& m, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  for (auto& p : m.positions) p.z() += n(rng);
}

/// The vertices `t` flags as boundary, in index order.
inline std::vector<int> boundary_vertices(const Topology& t) {
  std::vector<int> out;
  for (std::size_t v = 0; v < t.boundary_vertex.size(); ++v)
    if (t.boundary_vertex[v]) out.push_back(static_cast<int>(v));
  return out;
}

/// Moves each of `vertices` by N(0, sigma) in x, y and z using a fixed seed.
inline void jitter_3d(Mesh& m, const std::vector<int>& vertices, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  for (int v : vertices) m.positions[v] += Vec3(n(rng), n(rng), n(rng));
}

/// Test fixture with a fresh temporary directory per test, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("scanmesh_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  std::filesystem::path dir_;
};

}  // namespace scanmesh::test
