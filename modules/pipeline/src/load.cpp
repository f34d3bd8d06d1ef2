// Loading: YAML (or a command line's stage list) -> checked stages. Every configuration mistake is
// raised here, before anything runs.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>

#include "pipeline_impl.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/cloud_io.h"
#include "scanmesh/mesh_io.h"

namespace scanmesh {

using detail::Binder;
using detail::stage_registry;

namespace {

// Readers' files exist and have a known format, writers' formats are known and their folders writable,
// and no stage writes over a file the pipeline reads.
// A pipeline built from a command line names its files as arguments: a missing or unreadable input is
// bad input (exit 1), named by the file; in a YAML file it is a configuration error at its line.
[[noreturn]] void file_problem(const Pipeline::Impl& impl, const detail::StageSlot& s, const std::string& key, const std::string& file,
                               const std::string& what) {
  if (impl.path.empty()) throw InputError("'" + file + "': " + what);
  throw ConfigError(s.where.prefix() + ": key '" + key + "': '" + file + "': " + what);
}

void check_files(Pipeline::Impl& impl) {
  std::vector<std::string> inputs;
  for (auto& s : impl.slots) {
    for (const std::string& f : s.stage->files_read()) {
      const std::string key = s.where.type == "read" ? "filename" : "reference";
      std::error_code ec;
      if (!std::filesystem::exists(f, ec)) file_problem(impl, s, key, f, "No such file");
      if (std::filesystem::is_directory(f, ec))
        file_problem(impl, s, key, f, "is a folder; give one file (several views go into one mesh with cloud.merge or cloud.register)");
      if (s.where.type == "read") {
        const std::string ext = lower_extension(f);
        if (ext == ".las" || ext == ".laz" || ext == ".e57")
          file_problem(impl, s, key, f,
                       "LAS/LAZ/E57 have no reader here (no Debian library); convert to PLY or PCD first, e.g. "
                       "'pdal translate in" + ext + " out.ply' or CloudCompare's 'Save as PLY'");
        if (!is_mesh_extension(ext) && !is_cloud_extension(ext))
          file_problem(impl, s, key, f, "unknown format '" + (ext.empty() ? std::string("(no extension)") : ext) +
                                            "'; readers: .ply .obj .off .stl (meshes), .pcd .ply .xyz .txt .csv .pts (clouds)");
      }
      inputs.push_back(f);
    }
    for (const std::string& f : s.stage->files_written()) {
      const std::string ext = lower_extension(f);
      if (!is_mesh_extension(ext) && ext != ".pcd") {
        const std::string what = "unknown output format '" + (ext.empty() ? std::string("(no extension)") : ext) +
                                 "'; writers: .ply .obj .off .stl (mesh), .ply .pcd (cloud)";
        if (impl.path.empty()) throw UsageError("output '" + f + "': " + what);
        throw ConfigError(s.where.prefix() + ": key 'filename': " + what);
      }
      impl.output = f;
    }
  }
  for (auto& s : impl.slots)
    for (const std::string& f : s.stage->files_written()) {
      for (const auto& in : inputs)
        if (f == in || same_file(f, in)) {
          if (impl.path.empty()) throw UsageError("output '" + f + "' is the input file; scanmesh never overwrites its input");
          throw ConfigError(s.where.prefix() + ": key 'filename': '" + f + "' is an input of this pipeline; scanmesh never overwrites its input");
        }
      try {
        check_writable(f);
      } catch (const OutputError& e) {
        if (impl.path.empty()) throw;
        throw ConfigError(s.where.prefix() + ": key 'filename': " + e.what());
      }
    }
}

}  // namespace

Pipeline::Pipeline(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Pipeline::~Pipeline() = default;
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;
const std::string& Pipeline::output() const { return impl_->output; }
bool Pipeline::has_report() const {
  for (const auto& s : impl_->slots)
    if (s.where.type == "report") return true;
  return false;
}
std::string Pipeline::resolved_config() const { return YAML::Dump(impl_->resolved) + "\n"; }

Pipeline Pipeline::load(const std::string& path, const PipelineOptions& options) {
  std::string text;
  try {
    text = read_file(path);
  } catch (const InputError& e) {
    throw ConfigError(std::string("pipeline: ") + e.what());
  }
  return parse(text, path, options);
}

Pipeline Pipeline::parse(std::string_view yaml, const std::string& path, const PipelineOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  impl->options = options;
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml));
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw ConfigError(path + ": YAML error: " + e.msg);
  }
  YAML::Node list = root;
  if (root.IsMap()) {
    if (!root["pipeline"]) throw ConfigError(path + ":" + std::to_string(root.Mark().line + 1) + ": expected a 'pipeline:' list of stages");
    for (auto it = root.begin(); it != root.end(); ++it)
      if (it->first.Scalar() != "pipeline")
        throw ConfigError(path + ":" + std::to_string(it->first.Mark().line + 1) + ": unknown top-level key '" + it->first.Scalar() +
                          "'; the file holds 'pipeline:' only");
    list = root["pipeline"];
  }
  if (!list.IsSequence() || list.size() == 0)
    throw ConfigError(path + ":" + std::to_string(list.Mark().line + 1) + ": the pipeline must be a non-empty list of stages");

  std::map<std::string, int> tags;
  const std::size_t n = list.size();
  for (std::size_t i = 0; i < n; ++i) {
    const YAML::Node item = list[i];
    detail::StageSlot slot;
    slot.where.file = path;
    slot.where.line = item.Mark().line + 1;
    slot.where.index = static_cast<int>(i);
    if (item.IsScalar()) {
      if (i != 0 && i + 1 != n)
        throw ConfigError(path + ":" + std::to_string(slot.where.line) + ": stage " + std::to_string(i + 1) + ": a bare file name ('" +
                          item.Scalar() + "') must be the first stage (reader) or the last (writer)");
      slot.where.type = i == 0 ? "read" : "write";
      slot.options = YAML::Node(YAML::NodeType::Map);
      slot.options["filename"] = item.Scalar();
    } else if (item.IsMap()) {
      const YAML::Node type = item["type"];
      if (!type || !type.IsScalar())
        throw ConfigError(path + ":" + std::to_string(slot.where.line) + ": stage " + std::to_string(i + 1) +
                          " has no 'type'; valid types: " + detail::join(stage_registry().types()));
      slot.where.type = type.Scalar();
      if (!stage_registry().find(slot.where.type))
        throw ConfigError(path + ":" + std::to_string(type.Mark().line + 1) + ": stage " + std::to_string(i + 1) + ": unknown stage type '" +
                          slot.where.type + "'; " + detail::did_you_mean(slot.where.type, stage_registry().types()) + "valid: " + detail::join(stage_registry().types()));
      if (item["tag"]) {
        if (!item["tag"].IsScalar()) throw ConfigError(slot.where.prefix(item["tag"].Mark().line + 1) + ": 'tag' must be a name");
        slot.where.tag = item["tag"].Scalar();
        if (tags.count(slot.where.tag))
          throw ConfigError(slot.where.prefix(item["tag"].Mark().line + 1) + ": tag '" + slot.where.tag + "' is used twice");
      }
      if (const YAML::Node in = item["inputs"]) {
        std::vector<std::string> names;
        if (in.IsScalar()) names.push_back(in.Scalar());
        else if (in.IsSequence())
          for (const auto& x : in) names.push_back(x.Scalar());
        for (const auto& t : names) {
          if (!tags.count(t)) {
            std::vector<std::string> known_tags;
            for (const auto& [k, v] : tags) known_tags.push_back(k);
            throw ConfigError(slot.where.prefix(in.Mark().line + 1) + ": key 'inputs': no earlier stage has the tag '" + t + "'; " +
                              detail::did_you_mean(t, known_tags) + "tags so far: " + (known_tags.empty() ? "(none)" : detail::join(known_tags)));
          }
          slot.inputs.push_back(t);
        }
        slot.inputs_line = in.Mark().line + 1;
      }
      slot.options = item;  // the loaded node itself: its marks give line numbers
    } else {
      throw ConfigError(path + ":" + std::to_string(slot.where.line) + ": stage " + std::to_string(i + 1) +
                        " must be a file name or a map with 'type'");
    }
    if (!slot.where.tag.empty()) tags[slot.where.tag] = static_cast<int>(i);
    impl->slots.push_back(std::move(slot));
  }
  return finish(std::move(impl));
}

Pipeline Pipeline::build(const std::vector<StageSpec>& stages, const PipelineOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->options = options;  // path stays empty: messages name command-line flags
  if (stages.empty()) throw ConfigError("the pipeline has no stages");
  for (std::size_t i = 0; i < stages.size(); ++i) {
    detail::StageSlot slot;
    slot.where.index = static_cast<int>(i);
    slot.where.type = stages[i].type;
    slot.where.tag = stages[i].tag;
    if (!stage_registry().find(slot.where.type)) throw ConfigError("unknown stage type '" + slot.where.type + "'");
    slot.options = YAML::Node(YAML::NodeType::Map);
    for (const auto& [key, value] : stages[i].options) slot.options[key] = value;
    impl->slots.push_back(std::move(slot));
  }
  return finish(std::move(impl));
}

Pipeline Pipeline::finish(std::unique_ptr<Impl> impl) {
  // Command-line replacements and overrides.
  if (impl->options.input) {
    if (impl->slots.front().where.type != "read")
      throw ConfigError(impl->path + ": --input needs the pipeline to start with a reader (a file name)");
    impl->slots.front().options["filename"] = *impl->options.input;
  }
  if (impl->options.output) {
    if (impl->slots.back().where.type != "write" && !(impl->slots.size() > 1 && impl->slots.back().where.type == "report"))
      throw ConfigError(impl->path + ": --output needs the pipeline to end with a writer (a file name)");
  }
  for (const auto& set : impl->options.sets) {
    const auto eq = set.find('='), dot = set.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq)
      throw ConfigError("--set '" + set + "': expected TAG.OPTION=VALUE");
    // The tag may itself contain a dot when a stage type is used as tag (mesh.denoise.sigma_s=...).
    const std::string lhs = set.substr(0, eq), value = set.substr(eq + 1);
    const auto last_dot = lhs.rfind('.');
    const std::string tag = lhs.substr(0, last_dot), option = lhs.substr(last_dot + 1);
    detail::StageSlot* target = nullptr;
    std::vector<std::string> names;
    for (auto& s : impl->slots) {
      if (!s.where.tag.empty()) names.push_back(s.where.tag);
      if (s.where.tag == tag) target = &s;
    }
    if (!target) {
      int matches = 0;
      for (auto& s : impl->slots)
        if (s.where.type == tag) {
          target = &s;
          ++matches;
        }
      if (matches > 1) throw ConfigError("--set '" + set + "': several stages have type '" + tag + "'; give one a tag");
    }
    if (!target)
      throw ConfigError("--set '" + set + "': no stage has the tag '" + tag + "'; " + detail::did_you_mean(tag, names) +
                        "tags: " + (names.empty() ? std::string("(none)") : detail::join(names)));
    try {
      target->options[option] = YAML::Load(value);
    } catch (const YAML::Exception&) {
      target->options[option] = value;
    }
  }
  // The writer: the last "write" stage (a report may follow it).
  for (auto& s : impl->slots)
    if (s.where.type == "write" && impl->options.output) s.options["filename"] = *impl->options.output;

  // Bind every stage's options now, so every mistake surfaces before anything runs.
  YAML::Node resolved(YAML::NodeType::Sequence);
  for (auto& s : impl->slots) {
    s.stage = (*stage_registry().find(s.where.type))();
    Binder b(s.options, s.where);
    s.stage->bind(b);
    b.finish();
    s.resolved = b.resolved();
    if (s.inputs.size() > 1 && !s.stage->takes_many_inputs())
      throw ConfigError(s.where.prefix(s.inputs_line) + ": key 'inputs': this stage takes one input; got " + std::to_string(s.inputs.size()) +
                        " (cloud.merge and cloud.register combine several)");
    if (s.stage->takes_many_inputs() && s.inputs.size() < 2)
      throw ConfigError(s.where.prefix(s.inputs_line) + ": key 'inputs': list the tags of the views to combine (at least two)");
    resolved.push_back(s.options);
  }
  impl->resolved = YAML::Node(YAML::NodeType::Map);
  impl->resolved["pipeline"] = resolved;

  check_files(*impl);
  return Pipeline(std::move(impl));
}

}  // namespace scanmesh
