#include "corpus.h"

#include <algorithm>
#include <cstdio>
#include <cstdint>

#include "scanmesh/mesh_io.h"

namespace scanmesh::bench {
namespace fs = std::filesystem;

std::string Variant::name() const {
  const char* k = kind == NoiseKind::gaussian ? "gaussian" : kind == NoiseKind::uniform ? "uniform" : "impulsive";
  const char* d = direction == NoiseDirection::random ? "random" : "normal";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s-%s-%.1f", k, d, level);
  return buf;
}

const std::vector<Variant>& corpus_variants() {
  // Levels 0.1-0.5 x mean edge, the three noise kinds and both directions, as the literature uses them.
  static const std::vector<Variant> v = {
      {NoiseKind::gaussian, NoiseDirection::random, 0.1}, {NoiseKind::gaussian, NoiseDirection::random, 0.3},
      {NoiseKind::gaussian, NoiseDirection::normal, 0.2}, {NoiseKind::uniform, NoiseDirection::random, 0.4},
      {NoiseKind::uniform, NoiseDirection::normal, 0.3}, {NoiseKind::impulsive, NoiseDirection::random, 0.5},
  };
  return v;
}

std::vector<Model> corpus_models(const fs::path& data) {
  std::vector<Model> models;
  std::error_code ec;
  if (!fs::is_directory(data, ec)) return models;
  // train/: SOURCES.md says which are organic and which mechanical.
  const std::vector<std::pair<std::string, std::string>> train = {
      {"spot.obj", "organic"},        {"cow.obj", "organic"},      {"alligator.obj", "organic"},
      {"homer.obj", "organic"},       {"cheburashka.obj", "organic"}, {"rocker-arm.obj", "mechanical"},
      {"beetle.obj", "mechanical"},   {"teapot.obj", "mechanical"}, {"woody.obj", "organic"},
  };
  for (const auto& [file, kind] : train)
    if (fs::exists(data / "train" / file, ec)) models.push_back({fs::path(file).stem().string(), kind, data / "train" / file, {}});
  // pairs/: the clean halves are models; the noisy halves are real (or reference) noisy inputs.
  std::vector<fs::path> pair_dirs;
  if (fs::is_directory(data / "pairs", ec))
    for (const auto& e : fs::directory_iterator(data / "pairs")) pair_dirs.push_back(e.path());
  std::sort(pair_dirs.begin(), pair_dirs.end());
  for (const auto& dir : pair_dirs) {
    const std::string folder = dir.filename().string();
    const std::string name = folder.substr(0, folder.find('-'));
    auto it = std::find_if(models.begin(), models.end(), [&](const Model& m) { return m.name == name; });
    if (it == models.end()) {
      models.push_back({name, name == "bunny" ? "organic" : "mechanical", dir / "clean.obj", {}});
      it = models.end() - 1;
    }
    it->given.push_back(dir / "noisy.obj");  // fandisk-0.3 and fandisk-0.7 are one model
  }
  const std::vector<std::pair<std::string, std::string>> meshes = {
      {"bunny-adaptive.off", "organic"}, {"hemisphere-open.off", "mechanical"}, {"featuretype.stl", "mechanical"},
      {"dragon-202k.ply", "organic"}};
  for (const auto& [file, kind] : meshes)
    if (fs::exists(data / "meshes" / file, ec)) models.push_back({fs::path(file).stem().string(), kind, data / "meshes" / file, {}});
  return models;
}

// FNV-1a: a seed that is the same with every standard library (std::hash is not).
std::uint64_t seed_of(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::vector<Pair> load_pairs(const Model& model) {
  std::vector<Pair> pairs;
  const Mesh clean = read_mesh(model.clean.string());
  for (const auto& given : model.given)
    pairs.push_back({model.name, "given-" + given.parent_path().filename().string(), model.kind, clean, read_mesh(given.string())});
  for (const Variant& v : corpus_variants()) {
    Pair p{model.name, v.name(), model.kind, clean, clean};
    NoiseOptions o;
    o.level = v.level;
    o.kind = v.kind;
    o.direction = v.direction;
    o.seed = seed_of(model.name + "/" + v.name());
    add_noise(p.noisy, o);
    pairs.push_back(std::move(p));
  }
  return pairs;
}

}  // namespace scanmesh::bench
