#pragma once
// The state of a loaded pipeline, shared by the loader (load.cpp) and the run loop (run.cpp).
#include <memory>
#include <string>
#include <vector>

#include "stage.h"

namespace scanmesh {

namespace detail {
struct StageSlot {
  Where where;
  std::vector<std::string> inputs;  ///< tags of the stages whose data this one takes (one, or several to combine)
  int inputs_line = 0;
  YAML::Node options;               ///< the stage's map (with marks for line numbers)
  std::unique_ptr<Stage> stage;
  std::vector<std::pair<std::string, std::string>> resolved;  ///< every option's value after binding
};
}  // namespace detail

struct Pipeline::Impl {
  std::string path;
  PipelineOptions options;
  std::vector<detail::StageSlot> slots;
  std::string output;
  YAML::Node resolved;
};

}  // namespace scanmesh
