// Pose refinement on the Stanford bunny's range scans (bun000, bun045, bun090, posed by bun.conf): the
// views as posed (what registration changes there), then the second and third views moved by 5 degrees
// about a random axis through the bunny and 1 cm in a random direction, several seeds; prints how far the
// registered poses end from the ones registration finds without the perturbation.
// usage: scanmesh_register_views [CLOUDS_DIR] [--method point_to_plane|gicp]   (skips if the scans are absent)
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "scanmesh/cloud_io.h"
#include "scanmesh/combine_views.h"
#include "guarded_main.h"

using namespace scanmesh;

static int run(int argc, char** argv) {
  std::string dir = "../shared/data/clouds";
  RegisterOptions options;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--method") && i + 1 < argc) {
      RegisterOptions::schema().find("register_method")->set(options, argv[++i]);
    } else {
      dir = argv[i];
    }
  }
  const std::string scans = dir + "/bunny-range-scans";
  if (!std::filesystem::exists(scans + "/bun000.ply")) {
    std::printf("skipped: %s/bun000.ply not found\n", scans.c_str());
    return 0;
  }
  std::vector<PointCloud> posed;
  for (const char* name : {"bun000.ply", "bun045.ply", "bun090.ply"}) posed.push_back(read_cloud(scans + "/" + name));
  Vec3 centre = Vec3::Zero();
  std::size_t n = 0;
  for (const Vec3& p : posed[0].points)
    if (p.allFinite()) centre += p, ++n;
  centre /= static_cast<double>(n);

  std::vector<PointCloud> base = posed;
  auto t0 = std::chrono::steady_clock::now();
  const std::vector<ViewAlignment> reference = register_views(base, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("as posed by bun.conf: view 2 corrected by %.3f deg / %.3f mm, view 3 by %.3f deg / %.3f mm (%.1f s)\n",
              reference[1].rotation_deg, 1e3 * reference[1].translation, reference[2].rotation_deg, 1e3 * reference[2].translation, seconds);
  std::printf("| seed | view | residual rotation (deg) | residual offset at the bunny (mm) | overlap | seconds |\n|---|---|---|---|---|---|\n");
  double worst = 0.0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<PointCloud> views = posed;
    std::vector<Eigen::Isometry3d> moved(3, Eigen::Isometry3d::Identity());
    for (int k = 1; k < 3; ++k) {
      const Vec3 axis = Vec3(g(rng), g(rng), g(rng)).normalized(), dir3 = Vec3(g(rng), g(rng), g(rng)).normalized();
      Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
      p.linear() = Eigen::AngleAxisd(5.0 * 3.14159265358979323846 / 180.0, axis).toRotationMatrix();
      p.translation() = centre - p.linear() * centre + 0.01 * dir3;
      moved[k] = p;
      for (Vec3& q : views[k].points)
        if (q.allFinite()) q = p * q;
      if (views[k].sensor_origin) views[k].sensor_origin = p * *views[k].sensor_origin;
    }
    t0 = std::chrono::steady_clock::now();
    const std::vector<ViewAlignment> a = register_views(views, options);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (int k = 1; k < 3; ++k) {
      // Against the pose registration reaches from the unperturbed start.
      const Eigen::Isometry3d residual = reference[k].correction.inverse() * a[k].correction * moved[k];
      const double angle = Eigen::AngleAxisd(residual.linear()).angle() * 180.0 / 3.14159265358979323846;
      const double offset = (residual * centre - centre).norm();
      worst = std::max(worst, angle);
      std::printf("| %u | %d | %.3f | %.3f | %.0f%% | %.1f |\n", seed, k + 1, angle, 1e3 * offset, 100.0 * a[k].overlap, s);
    }
  }
  std::printf("worst residual rotation: %.3f deg\n", worst);
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
