// scanmesh: thin command-line front end over the scanmesh libraries.
// Exit codes: 0 ok, 1 bad input (file missing or malformed, or an output could not be written), 2 bad usage.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <new>

#include "cli_common.h"
#include "scanmesh/errors.h"

namespace {

const char* kHelp =
    "scanmesh " SCANMESH_VERSION " - from raw 3D scans to clean, high-fidelity triangle meshes\n"
    "\n"
    "usage: scanmesh COMMAND [ARGS] [--help]\n"
    "\n"
    "commands:\n"
    "  run PIPELINE     run a YAML pipeline (see configs/): scan -> mesh -> denoise -> report\n"
    "  mesh CLOUD OUT   point cloud (.pcd .ply .xyz) -> cleaned triangle mesh (PCL)\n"
    "  scan MESH OUT    virtual depth scanner: noisy clouds of a clean mesh from several views\n"
    "  denoise IN OUT   robust two-stage mesh denoising (Yadav et al. 2019), --auto picks parameters\n"
    "  noise IN OUT     add synthetic noise (gaussian, uniform, impulsive) for experiments\n"
    "  eval MESH        quality metrics, against a reference with --reference REF\n"
    "  version          print the version\n"
    "\n"
    "Mesh formats: .obj .off .ply .stl (ascii and binary). Run 'scanmesh COMMAND --help' for details.\n";

#ifndef SCANMESH_EXT
// `mesh`, `scan` and `run` live in scanmesh-ext beside this executable (see tools/CMakeLists.txt).
[[noreturn]] void exec_extended(char** argv) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path ext = (ec ? std::filesystem::path(argv[0]) : self).parent_path() / "scanmesh-ext";
  ::execv(ext.c_str(), argv);
  std::cerr << "scanmesh " << argv[1] << ": error: cannot start '" << ext.string() << "': " << std::strerror(errno)
            << " (it is built together with scanmesh)\n";
  std::exit(1);
}
#endif

}  // namespace

int main(int argc, char** argv) {
  using namespace scanmesh;
  if (argc < 2) {
    std::cerr << kHelp;
    return cli::kBadUsage;
  }
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  cli::install_memory_guard(command);
  try {
    if (command == "denoise") return cli::run_denoise(args);
    if (command == "noise") return cli::run_noise(args);
    if (command == "eval") return cli::run_eval(args);
#ifdef SCANMESH_EXT
    if (command == "mesh") return cli::run_mesh(args);
    if (command == "scan") return cli::run_scan(args);
    if (command == "run") return cli::run_pipeline(args);
#else
    if (command == "mesh" || command == "scan" || command == "run") exec_extended(argv);
#endif
    if (command == "version" || command == "--version") {
      std::cout << "scanmesh " SCANMESH_VERSION "\n";
      return cli::kOk;
    }
    if (command == "help" || command == "--help" || command == "-h") {
      std::cout << kHelp;
      return cli::kOk;
    }
    std::cerr << "scanmesh: unknown command '" << command << "'; commands: run, mesh, scan, denoise, noise, eval, version\n";
    return cli::kBadUsage;
  } catch (const UsageError& e) {
    std::cerr << "scanmesh " << command << ": error: " << e.what() << "\n";
    return cli::kBadUsage;
  } catch (const InputError& e) {
    std::cerr << "scanmesh " << command << ": error: " << e.what() << "\n";
    return cli::kBadInput;
  } catch (const OutputError& e) {
    std::cerr << "scanmesh " << command << ": error: " << e.what() << "\n";
    return cli::kBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "scanmesh " << command << ": error: out of memory (limit " << cli::memory_limit_mb()
              << " MB: the machine's physical memory, or SCANMESH_MAX_MEMORY_MB)\n";
    return cli::kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "scanmesh " << command << ": internal error: " << e.what() << "\n";
    return cli::kBadInput;
  }
}
