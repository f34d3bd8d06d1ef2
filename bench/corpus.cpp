#include "corpus.h"

#include <algorithm>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadricDecimation.h>
#include <vtkSmartPointer.h>

#include "helpers.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/topology.h"

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
      // A dense scan of a smooth statue (269k faces), denser at its own edge length than any other model;
      // one group with its coarser versions below (the grids hold only those; docs/EXPERIMENTS.md, "Dense
      // smooth scans" and "The dense scans in the fit").
      {"igea-tristrips.ply", "organic"},
  };
  for (const auto& [file, kind] : train)
    if (fs::exists(data / "train" / file, ec)) models.push_back({fs::path(file).stem().string(), kind, data / "train" / file, {}, 0, {}});
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
      models.push_back({name, name == "bunny" ? "organic" : "mechanical", dir / "clean.obj", {}, 0, {}});
      it = models.end() - 1;
    }
    it->given.push_back(dir / "noisy.obj");  // fandisk-0.3 and fandisk-0.7 are one model
  }
  const std::vector<std::pair<std::string, std::string>> meshes = {
      {"bunny-adaptive.off", "organic"}, {"hemisphere-open.off", "mechanical"}, {"featuretype.stl", "mechanical"},
      {"dragon-202k.ply", "organic"}};
  for (const auto& [file, kind] : meshes)
    if (fs::exists(data / "meshes" / file, ec)) models.push_back({fs::path(file).stem().string(), kind, data / "meshes" / file, {}, 0, {}});
  // Dense organic models: three closed coarse ones subdivided once (23k, 23k and 48k faces). At their own
  // edge length they look nearly flat between neighbours, as dense scans do.
  for (const char* name : {"spot", "cow", "homer"}) {
    auto it = std::find_if(models.begin(), models.end(), [&](const Model& m) { return m.name == name; });
    if (it != models.end()) models.push_back({it->name + "-dense", it->kind, it->clean, {}, 1, it->name});
  }
  // Coarser versions of the Igea scan (269k faces, so dense that neighbouring faces are nearly coplanar):
  // a smooth statue at the resolution of the organic meshes users bring, held back with the scan itself.
  const auto igea = std::find_if(models.begin(), models.end(), [](const Model& m) { return m.name == "igea-tristrips"; });
  if (igea != models.end()) {
    const Model scan = *igea;  // (push_back below may move the vector)
    for (const std::size_t faces : {20000, 60000})
      models.push_back({"igea-" + std::to_string(faces / 1000) + "k", scan.kind, scan.clean, {}, 0, scan.name, false, faces});
  }
  // A generated CAD part with locally refined bands: none of the files has such a tessellation.
  models.push_back({"refined-cylinder", "mechanical", {}, {}, 0, {}, true});
  for (Model& m : models)
    if (m.group.empty()) m.group = m.name;
  return models;
}

Mesh loop_subdivide(const Mesh& mesh) {
  const Topology t = build_topology(mesh);
  const std::size_t nv = mesh.num_vertices();
  Mesh out;
  out.positions.resize(nv + t.edges.size());
  // Old vertices.
  for (std::size_t v = 0; v < nv; ++v) {
    const int* n = t.vertex_vertices.begin(v);
    const int k = t.vertex_vertices.size(v);
    const Vec3& p = mesh.positions[v];
    if (t.boundary_vertex[v]) {
      // The two neighbours along boundary edges.
      Vec3 sum = Vec3::Zero();
      int found = 0;
      for (const int* f = t.vertex_faces.begin(v); f != t.vertex_faces.end(v); ++f)
        for (int c = 0; c < 3; ++c) {
          const int e = t.face_edges[*f][c];
          if (t.edge_faces.size(e) != 1) continue;
          const int other = t.edges[e][0] == static_cast<int>(v) ? t.edges[e][1] : t.edges[e][1] == static_cast<int>(v) ? t.edges[e][0] : -1;
          if (other >= 0) sum += mesh.positions[other], ++found;
        }
      out.positions[v] = found == 2 ? Vec3(0.75 * p + 0.125 * sum) : p;  // corners and odd boundaries stay
      continue;
    }
    if (k < 3) {
      out.positions[v] = p;
      continue;
    }
    const double beta = k == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * k);
    Vec3 sum = Vec3::Zero();
    for (int j = 0; j < k; ++j) sum += mesh.positions[n[j]];
    out.positions[v] = (1.0 - k * beta) * p + beta * sum;
  }
  // Edge points.
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    const Vec3& a = mesh.positions[t.edges[e][0]];
    const Vec3& b = mesh.positions[t.edges[e][1]];
    if (t.edge_faces.size(e) != 2) {
      out.positions[nv + e] = 0.5 * (a + b);
      continue;
    }
    Vec3 opposite = Vec3::Zero();
    for (const int* f = t.edge_faces.begin(e); f != t.edge_faces.end(e); ++f)
      for (int c : mesh.faces[*f])
        if (c != t.edges[e][0] && c != t.edges[e][1]) opposite += mesh.positions[c];
    out.positions[nv + e] = 0.375 * (a + b) + 0.125 * opposite;
  }
  out.faces.reserve(4 * mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Face& c = mesh.faces[f];
    // face_edges[f] = edges (c0,c1), (c1,c2), (c2,c0)
    const int m01 = static_cast<int>(nv) + t.face_edges[f][0], m12 = static_cast<int>(nv) + t.face_edges[f][1],
              m20 = static_cast<int>(nv) + t.face_edges[f][2];
    out.faces.push_back({c[0], m01, m20});
    out.faces.push_back({m01, c[1], m12});
    out.faces.push_back({m20, m12, c[2]});
    out.faces.push_back({m01, m12, m20});
  }
  return out;
}

Mesh decimate(const Mesh& mesh, std::size_t faces) {
  if (faces >= mesh.num_faces()) return mesh;
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  for (const Vec3& p : mesh.positions) points->InsertNextPoint(p.x(), p.y(), p.z());
  auto triangles = vtkSmartPointer<vtkCellArray>::New();
  for (const Face& f : mesh.faces) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    triangles->InsertNextCell(3, ids);
  }
  auto input = vtkSmartPointer<vtkPolyData>::New();
  input->SetPoints(points);
  input->SetPolys(triangles);
  auto filter = vtkSmartPointer<vtkQuadricDecimation>::New();
  filter->SetInputData(input);
  filter->SetTargetReduction(1.0 - static_cast<double>(faces) / static_cast<double>(mesh.num_faces()));
  filter->Update();
  vtkPolyData* out = filter->GetOutput();
  Mesh result;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    double p[3];
    out->GetPoint(i, p);
    result.positions.emplace_back(p[0], p[1], p[2]);
  }
  vtkCellArray* polys = out->GetPolys();
  polys->InitTraversal();
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  while (polys->GetNextCell(n, ids))
    if (n == 3) result.faces.push_back({static_cast<int>(ids[0]), static_cast<int>(ids[1]), static_cast<int>(ids[2])});
  return result;
}

// FNV-1a: a seed that is the same with every standard library (std::hash is not).
std::uint64_t seed_of(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::vector<Pair> load_pairs(const Model& model) {
  std::vector<Pair> pairs;
  Mesh clean = model.generated ? test::make_zippered_cylinder() : read_mesh(model.clean.string());
  for (int s = 0; s < model.subdivisions; ++s) clean = loop_subdivide(clean);
  if (model.decimate_to > 0) clean = decimate(clean, model.decimate_to);
  const std::string group = model.group.empty() ? model.name : model.group;
  const std::string prefix = model.subdivisions > 0    ? "dense-"
                             : model.decimate_to > 0 ? std::to_string(model.decimate_to / 1000) + "k-"
                                                     : "";
  for (const auto& given : model.given)
    pairs.push_back({group, "given-" + given.parent_path().filename().string(), model.kind, clean, read_mesh(given.string())});
  for (const Variant& v : corpus_variants()) {
    Pair p{group, prefix + v.name(), model.kind, clean, clean};
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

std::vector<double> parse_list(const char* s) {
  std::vector<double> v;
  std::stringstream in(s);
  for (std::string tok; std::getline(in, tok, ',');) v.push_back(std::atof(tok.c_str()));
  return v;
}

bool listed(const Model& model, const std::string& list) {
  const std::string padded = "," + list + ",";
  const std::string group = model.group.empty() ? model.name : model.group;
  return padded.find("," + model.name + ",") != std::string::npos || padded.find("," + group + ",") != std::string::npos;
}

std::optional<std::vector<Model>> corpus_models_from_args(int argc, char** argv) {
  std::filesystem::path data = "../shared/data";
  std::string only;
  std::vector<Model> outside;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--mesh") && i + 1 < argc) {
      const fs::path file = argv[++i];
      outside.push_back({file.stem().string(), "outside", file, {}, 0, file.stem().string()});
    } else data = argv[i];
  }
  // Models from outside the corpus: what no rule was fitted on, the corpus left out.
  if (!outside.empty()) return outside;
  std::vector<Model> models = corpus_models(data);
  if (models.empty()) {
    std::printf("skipped: %s not found\n", data.c_str());
    return std::nullopt;
  }
  if (!only.empty()) models.erase(std::remove_if(models.begin(), models.end(), [&](const Model& m) { return m.name != only; }), models.end());
  return models;
}

}  // namespace scanmesh::bench
