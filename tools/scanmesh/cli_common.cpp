#include "cli_common.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <exception>
#include <new>

#include <cstdio>
#include <iostream>

#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"
#include "scanmesh/mesh_io.h"

namespace scanmesh::cli {

bool parse(const std::vector<std::string>& args, const po::options_description& options,
           const std::vector<std::string>& positional, po::variables_map& vm, const std::string& usage,
           const std::string& details) {
  po::options_description all;
  all.add(options);
  po::options_description hidden;
  for (const auto& name : positional) hidden.add_options()(name.c_str(), po::value<std::string>());
  hidden.add_options()("help,h", "show help");
  all.add(hidden);
  po::positional_options_description pos;
  for (const auto& name : positional) pos.add(name.c_str(), 1);
  try {
    po::store(po::command_line_parser(args).options(all).positional(pos).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw UsageError(std::string(e.what()) + "\nusage: " + usage + "\n(see --help)");
  }
  if (vm.count("help") != 0U) {
    std::cout << "usage: " << usage << "\n\n" << details << "\n" << options << "\n";
    return false;
  }
  for (const auto& name : positional)
    if (vm.count(name) == 0U) throw UsageError("missing " + name + "\nusage: " + usage + "\n(see --help)");
  return true;
}

Progress::Progress(std::string label, bool quiet)
    : label_(std::move(label)), quiet_(quiet), tty_(::isatty(STDERR_FILENO) != 0) {}

void Progress::operator()(int done, int total) {
  if (quiet_ || total <= 0) return;
  const int percent = 100 * done / total;
  if (tty_) {
    if (percent == last_percent_) return;
    const int width = 30;
    const int filled = width * done / total;
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% (%d/%d)", label_.c_str(), filled, "==============================",
                 width - filled, "", percent, done, total);
    if (done == total) std::fputc('\n', stderr);
  } else {
    // Plain lines, one per quarter, for logs.
    if (percent / 25 == last_percent_ / 25 && done != total) return;
    std::fprintf(stderr, "%s: %d/%d\n", label_.c_str(), done, total);
  }
  last_percent_ = percent;
}

namespace {

double g_limit_mb = 0.0;
std::string g_command;

[[noreturn]] void out_of_memory_exit() {
  std::fprintf(stderr, "scanmesh %s: error: out of memory (limit %.0f MB: the machine's physical memory, or SCANMESH_MAX_MEMORY_MB)\n",
               g_command.c_str(), g_limit_mb);
  std::_Exit(kBadInput);
}

bool under_address_sanitizer() {
#if defined(__SANITIZE_ADDRESS__)
  return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return true;
#else
  return false;
#endif
#else
  return false;
#endif
}

}  // namespace

double memory_limit_mb() { return g_limit_mb; }

void install_memory_guard(const std::string& command) {
  g_command = command;
  std::set_new_handler(nullptr);
  std::set_terminate([] {
    // An exception escaping an OpenMP region ends here; out of memory gets its message and exit code.
    if (const std::exception_ptr e = std::current_exception()) {
      try {
        std::rethrow_exception(e);
      } catch (const std::bad_alloc&) {
        out_of_memory_exit();
      } catch (...) {
      }
    }
    std::fprintf(stderr, "scanmesh %s: internal error (terminate)\n", g_command.c_str());
    std::abort();
  });
  if (under_address_sanitizer()) return;
  double mb = 0.0;
  if (const char* env = std::getenv("SCANMESH_MAX_MEMORY_MB")) {
    mb = std::atof(env);
  } else {
    std::FILE* f = std::fopen("/proc/meminfo", "r");
    char line[256];
    while (f != nullptr && std::fgets(line, sizeof line, f) != nullptr) {
      unsigned long long kb = 0;
      if (std::sscanf(line, "MemTotal: %llu kB", &kb) == 1) {
        mb = static_cast<double>(kb) / 1024.0;
        break;
      }
    }
    if (f != nullptr) std::fclose(f);
  }
  if (!(mb > 0.0)) return;
  rlimit r{};
  ::getrlimit(RLIMIT_AS, &r);
  const auto bytes = static_cast<rlim_t>(mb * 1048576.0);
  if (r.rlim_max != RLIM_INFINITY && bytes > r.rlim_max) return;
  r.rlim_cur = bytes;
  if (::setrlimit(RLIMIT_AS, &r) == 0) g_limit_mb = mb;
}

void print_warnings(const std::vector<std::string>& warnings, bool quiet) {
  if (quiet) return;
  for (const auto& w : warnings) std::cerr << "warning: " << w << "\n";
}

}  // namespace scanmesh::cli
