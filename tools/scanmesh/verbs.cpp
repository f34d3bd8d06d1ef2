// The verbs that are pipelines: `denoise`, `noise`, `mesh` and `scan` each build a list of stages and run
// it through the same Pipeline as `scanmesh run`. Their flags are the stages' options, read from the
// options structs' schemas (flag = YAML key with '-' for '_'), so --help, defaults, ranges and checks are
// the pipeline's own; every check and message exists once.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>

#include "cli_common.h"
#include "scanmesh/errors.h"
#include "scanmesh/pipeline.h"
#include "scanmesh/report.h"

namespace scanmesh::cli {
namespace {

struct VerbStage {
  std::string type, tag;
};

struct Verb {
  std::string name, usage, summary;
  std::string in, out;                  ///< positional names (reader's and writer's filename)
  std::vector<VerbStage> stages;        ///< between the reader and the writer
  std::vector<std::string> hidden;      ///< reader options that do not apply (e.g. text-cloud columns for meshes)
};

const std::vector<Verb>& verbs() {
  static const std::vector<Verb> v = {
      {"denoise", "scanmesh denoise IN OUT [options]",
       "Removes scanner noise from a triangle mesh while keeping sharp features, boundaries and volume (robust two-stage\n"
       "denoising, Yadav, Reitebuch, Polthier 2019). Vertex order and connectivity are kept, so OUT compares face by face\n"
       "with IN. --auto chooses the parameters from the mesh; values given explicitly still win.",
       "IN", "OUT", {{"mesh.denoise", "denoise"}}, {"columns", "viewpoint_pose"}},
      {"noise", "scanmesh noise IN OUT [options]",
       "Adds synthetic noise to a clean mesh (vertex order and faces unchanged), for experiments and tests.", "IN", "OUT",
       {{"mesh.noise", "noise"}}, {"columns", "viewpoint_pose"}},
      {"mesh", "scanmesh mesh CLOUD OUT [options]",
       "Turns a scanner point cloud (.pcd .ply .xyz .txt .csv .pts) into a triangle mesh: dequantize depth-camera frames,\n"
       "voxel grid (off by default), outlier removal, normals, meshing (method auto: organized grids by their pixels,\n"
       "otherwise greedy projection, or screened Poisson where that fits the points better), clean-up. Lengths: a number\n"
       "in scene units, N*spacing (mean point spacing), N*edge or N% of the bounding-box diagonal.",
       "CLOUD", "OUT",
       {{"cloud.dequantize", ""}, {"cloud.voxel", ""}, {"cloud.outliers", ""}, {"cloud.normals", ""}, {"mesh.auto", "mesh"}, {"mesh.cleanup", ""}},
       {}},
      {"scan", "scanmesh scan MESH OUT.ply|OUT.pcd [options]",
       "Virtual depth scanner: ray-casts MESH from several viewpoints, adds depth noise along each ray and writes the merged\n"
       "cloud (each point's normal: the direction to its sensor). Gives scans whose ground truth (MESH) is known.",
       "MESH", "OUT", {{"scan.virtual", "scan"}}, {"columns", "viewpoint_pose"}},
  };
  return v;
}

// One flag of a verb: which stage it belongs to and what the schema says of it.
struct Flag {
  std::size_t stage = 0;  // index in the full stage list (0 = reader, last = writer)
  StageOption option;
};

std::string wrap(const std::string& text, std::size_t indent, std::size_t width = 100) {
  std::istringstream words(text);
  std::string word, out, line;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > width - indent) {
      out += line + "\n" + std::string(indent, ' ');
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  return out + line;
}

void print_help(const Verb& verb, const std::vector<std::string>& types, const std::map<std::string, Flag>& flags) {
  std::cout << "usage: " << verb.usage << "\n\n" << verb.summary << "\n";
  for (std::size_t s = 0; s < types.size(); ++s) {
    bool header = false;
    for (const auto& [flag, f] : flags) {
      if (f.stage != s) continue;
      if (!header) {
        std::cout << "\n" << (s == 0 ? "reading" : s + 1 == types.size() ? "writing" : "options of " + types[s] + " (YAML keys of that stage)") << ":\n";
        header = true;
      }
      const FieldInfo& i = f.option.info;
      std::string head = "  " + flag + (i.type == FieldType::flag ? "" : " VALUE");
      std::cout << head << "\n      " << wrap(i.doc + " [" + i.domain() + "; default " + f.option.default_value + "]", 6) << "\n";
    }
  }
  std::cout << "\ncommon:\n"
               "  --report             also write OUT.report.json (sidecar), OUT.report/ (figures) and OUT.report.html\n"
               "  --strict             exit 1 when the result is degraded (written, but its scan fit falls short)\n"
               "  --threads N          threads (0 = all cores); the output does not depend on it\n"
               "  --quiet, -q          print errors only\n"
               "  --help, -h           this help\n"
               "Switches take no value (--auto) or true/false (--auto=false). Exit codes: 0 ok, 1 bad input or a failed\n"
               "run, 2 bad usage.\n";
}

}  // namespace

bool is_pipeline_verb(const std::string& name) {
  for (const auto& v : verbs())
    if (v.name == name) return true;
  return false;
}

int run_verb(const std::string& name, const std::vector<std::string>& args) {
  const Verb* verb = nullptr;
  for (const auto& v : verbs())
    if (v.name == name) verb = &v;
  if (!verb) throw UsageError("unknown command '" + name + "'");

  // The full stage list and the flags its options give.
  std::vector<std::string> types = {"read"};
  for (const auto& s : verb->stages) types.push_back(s.type);
  types.push_back("write");
  std::map<std::string, Flag> flags;
  for (std::size_t s = 0; s < types.size(); ++s)
    for (const StageOption& o : stage_options(types[s])) {
      if (o.info.name == "filename") continue;
      if (s == 0 && std::find(verb->hidden.begin(), verb->hidden.end(), o.info.name) != verb->hidden.end()) continue;
      const std::string flag = o.info.flag();
      if (flags.count(flag)) throw std::logic_error("option '" + o.info.name + "' of " + types[s] + " is also an option of another stage of " + name);
      flags[flag] = {s, o};
    }

  // Arguments: two positionals, the stages' options, and the common flags.
  std::vector<std::string> positional;
  std::vector<std::vector<std::pair<std::string, std::string>>> options(types.size());
  int threads = 0;
  bool quiet = false, strict = false, report = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      print_help(*verb, types, flags);
      return kOk;
    }
    if (a.size() < 2 || a[0] != '-' || a == "-") {
      positional.push_back(a);
      continue;
    }
    if (a == "-q" || a == "--quiet") {
      quiet = true;
      continue;
    }
    std::string key = a, value;
    bool has_value = false;
    if (const auto eq = a.find('='); eq != std::string::npos) {
      key = a.substr(0, eq);
      value = a.substr(eq + 1);
      has_value = true;
    }
    auto take_value = [&]() {
      if (has_value) return value;
      if (i + 1 >= args.size()) throw UsageError(key + " needs a value (see --help)");
      return args[++i];
    };
    if (key == "--threads") {
      const std::string t = take_value();
      try {
        std::size_t used = 0;
        threads = std::stoi(t, &used);
        if (used != t.size() || threads < 0) throw std::invalid_argument(t);
      } catch (const std::exception&) {
        throw UsageError("--threads: expected a whole number >= 0, got '" + t + "'");
      }
      continue;
    }
    if (key == "--strict" || key == "--report") {
      (key == "--strict" ? strict : report) = true;
      continue;
    }
    const auto f = flags.find(key);
    if (f == flags.end()) {
      std::vector<std::string> known;
      for (const auto& [k, unused] : flags) known.push_back(k);
      std::string hint;
      std::size_t best = 1000;
      for (const auto& k : known) {
        std::size_t d = 0;  // a cheap distance: shared prefix length against the longer name
        while (d < k.size() && d < key.size() && k[d] == key[d]) ++d;
        const std::size_t miss = std::max(k.size(), key.size()) - d;
        if (miss < best) best = miss, hint = k;
      }
      throw UsageError("unknown option '" + key + "'" + (best <= 4 ? "; did you mean " + hint + "?" : "") + " (see --help)");
    }
    const std::string text = f->second.option.info.type == FieldType::flag && !has_value ? "true" : take_value();
    options[f->second.stage].emplace_back(f->second.option.info.name, text);
  }
  if (positional.size() != 2)
    throw UsageError(std::string(positional.size() < 2 ? "missing " + (positional.empty() ? verb->in : verb->out) : "too many arguments") +
                     "\nusage: " + verb->usage + "\n(see --help)");

  std::vector<StageSpec> specs;
  specs.push_back({"read", "", options[0]});
  specs.back().options.insert(specs.back().options.begin(), {"filename", positional[0]});
  for (std::size_t s = 0; s < verb->stages.size(); ++s) specs.push_back({verb->stages[s].type, verb->stages[s].tag, options[s + 1]});
  if (report) specs.push_back({"report", "", {}});
  specs.push_back({"write", "", options.back()});
  specs.back().options.insert(specs.back().options.begin(), {"filename", positional[1]});

  PipelineOptions po;
  po.threads = threads;
  std::unique_ptr<Progress> bar;
  if (!quiet) {
    po.progress = [&bar](const std::string& stage, int done, int total) {
      if (!bar) bar = std::make_unique<Progress>(stage, false);
      (*bar)(done, total);
      if (done == total) bar.reset();
    };
    po.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  }
  Pipeline pipeline = Pipeline::build(specs, po);
  const PipelineResult r = pipeline.run();
  print_warnings(r.warnings, quiet);
  if (r.status != "ok" && strict) {
    std::fprintf(stderr, "scanmesh %s: error: the result is %s (--strict); written to %s\n", name.c_str(), r.status.c_str(), r.output.c_str());
    return kBadInput;
  }
  if (!quiet) {
    std::fprintf(stderr, "[done, %.2f s : %s%s] -> %s\n", r.seconds, r.summary.c_str(), r.status == "ok" ? "" : (", " + r.status).c_str(),
                 r.output.c_str());
    if (report) std::fprintf(stderr, "report: %s\n", report_paths(r.output).html.c_str());
  }
  return kOk;
}

}  // namespace scanmesh::cli
