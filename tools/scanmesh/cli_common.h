#pragma once
// Shared pieces of the scanmesh subcommands: option parsing, exit codes, progress, summaries.
#include <boost/program_options.hpp>
#include <functional>
#include <string>
#include <vector>

namespace scanmesh::cli {

namespace po = boost::program_options;

enum ExitCode { kOk = 0, kBadInput = 1, kBadUsage = 2 };

/// Parses `args` against `options` with the given positional names; prints help and returns false when
/// --help was asked for. Throws UsageError for unknown/missing options.
bool parse(const std::vector<std::string>& args, const po::options_description& options,
           const std::vector<std::string>& positional, po::variables_map& vm, const std::string& usage,
           const std::string& details);

/// Progress bar on a terminal, plain lines otherwise; silent with --quiet.
class Progress {
 public:
  Progress(std::string label, bool quiet);
  void operator()(int done, int total);

 private:
  std::string label_;
  bool quiet_, tty_;
  int last_percent_ = -1;
};

/// Bounds this process's memory so that input needing more fails with a message (exit 1) instead of
/// swapping or being killed by the kernel: the address space is limited to SCANMESH_MAX_MEMORY_MB if set,
/// else to the machine's physical memory (skipped under AddressSanitizer, which reserves far more), and
/// an allocation failing inside a parallel loop (where it cannot be caught) ends the process the same way.
void install_memory_guard(const std::string& command);

/// The limit install_memory_guard set, in MB (0 = none).
double memory_limit_mb();

/// Prints warnings to stderr unless quiet.
void print_warnings(const std::vector<std::string>& warnings, bool quiet);

/// True for the commands that are pipelines (denoise, noise, mesh, scan); run_verb runs them.
bool is_pipeline_verb(const std::string& name);
int run_verb(const std::string& name, const std::vector<std::string>& args);
int run_eval(const std::vector<std::string>& args);
int run_pipeline(const std::vector<std::string>& args);

}  // namespace scanmesh::cli
