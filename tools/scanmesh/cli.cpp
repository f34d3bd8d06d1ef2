// The command table, shared by the two executables: `scanmesh` (light: denoise, noise, eval, without PCL,
// VTK or OpenCV, so it starts fast) and `scanmesh-full` (every command). The light one hands commands
// that need the scan stages to the full one, installed beside it or under ../libexec/scanmesh/.
#include "cli.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <new>

#include "cli_common.h"
#include "scanmesh/errors.h"
#include "scanmesh/pipeline.h"

namespace scanmesh::cli {
namespace {

const char* kHelp =
    "scanmesh " SCANMESH_VERSION " - from raw 3D scans to clean, high-fidelity triangle meshes\n"
    "\n"
    "usage: scanmesh COMMAND [ARGS] [--help]\n"
    "\n"
    "commands:\n"
    "  run PIPELINE     run a YAML pipeline (see configs/): scan -> mesh -> denoise -> report\n"
    "  mesh CLOUD OUT   point cloud (.pcd .ply .xyz .txt .csv .pts) -> cleaned triangle mesh\n"
    "  scan MESH OUT    virtual depth scanner: a noisy cloud of a clean mesh from several views\n"
    "  denoise IN OUT   robust two-stage mesh denoising (Yadav et al. 2019); --auto picks the parameters\n"
    "  noise IN OUT     add synthetic noise (gaussian, uniform, impulsive) for experiments\n"
    "  eval MESH        quality metrics; against a reference mesh or the cloud it was made from (--reference)\n"
    "  options [TYPE]   every stage's options: name, unit, range, default, meaning (--markdown for tables)\n"
    "  version          print the version\n"
    "\n"
    "Mesh formats: .obj .off .ply .stl (ascii and binary). 'scanmesh COMMAND --help' lists a command's options;\n"
    "a command's flag is the YAML key of the same option in a pipeline, with '-' for '_'.\n";

// Commands only the full executable has (they need PCL, VTK or OpenCV).
bool needs_full(const std::string& command, const std::vector<std::string>& args) {
  if (command == "mesh" || command == "scan" || command == "run" || command == "options") return true;
  for (const auto& a : args)
    if (a == "--report") return true;
  return false;
}

[[noreturn]] void exec_full(char** argv) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path dir = (ec ? std::filesystem::path(argv[0]) : self).parent_path();
  for (const auto& candidate : {dir / "scanmesh-full", dir / ".." / "libexec" / "scanmesh" / "scanmesh-full"})
    if (std::filesystem::exists(candidate)) {
      ::execv(candidate.c_str(), argv);
      std::fprintf(stderr, "scanmesh %s: error: cannot start '%s': %s\n", argv[1], candidate.c_str(), std::strerror(errno));
      std::exit(kBadInput);
    }
  std::fprintf(stderr, "scanmesh %s: error: this command needs scanmesh-full, which is installed beside scanmesh or in "
               "../libexec/scanmesh/; it was not found next to %s\n", argv[1], dir.c_str());
  std::exit(kBadInput);
}

// Runtime settings that are read from the environment only when the process starts, so the process
// re-executes itself once with them set (each only if the user has not chosen it):
// - Idle OpenMP threads spin for a while by default; on a busy machine (batch jobs side by side) that
//   makes every parallel loop many times slower: passive waiting, after a short spin (GOMP_SPINCOUNT
//   10000, tens of microseconds): waking a sleeping thread at every loop cost a small mesh an eighth of
//   its time. fandisk-0.3, 100 iterations, `mesh.denoise` stage: 0.084-0.090 s passive, 0.074-0.076 s
//   with the short spin (spinning all the time: 0.076-0.079); with both cores busy with other processes
//   (three runs each) fandisk 0.35-0.38 -> 0.25 s (one thread 0.22-0.28), dragon-202k 20 iterations
//   0.74-1.04 -> 0.73-0.86 s (one thread 0.91-1.02; a spin of 100000 made it 1.15-1.20).
// - glibc's malloc asks for transparent huge pages on its large blocks (glibc.malloc.hugetlb=1): on a
//   million-face mesh first touches of fresh memory (page faults) took a fifth of the denoiser's setup.
// - Every block of 16 MiB or more is mapped on its own and unmapped when freed
//   (glibc.malloc.mmap_threshold): by default glibc raises that limit after the first large free, so
//   later tables land in the heap and what a stage frees stays in the process. 810k-face dragon, 20
//   iterations: peak 162 -> 154 MB at the same time with a 1 MiB limit; the main job on a 307k-point
//   frame: 437-448 -> 422-430 MB. A 1 MiB limit made every table of a mid-sized mesh fresh memory,
//   which this VM clears slowly (a sixth of the 810k run's profile); 16 MiB keeps the peaks (810k:
//   143-144 MB both; the 307k-point frame 411-412 -> 413-414 MB; 3.2M faces 559-564 MB both) and saves
//   time (810k, 20 iterations, five alternating runs: 1.70-2.03 -> 1.52-1.94 s, median 1.74 -> 1.58;
//   the frame's main job 6.4-7.7 -> 5.4-5.8 s).
// - The heap keeps up to 8 MiB of freed memory at its top (glibc.malloc.trim_threshold; 128 KiB by
//   default) and grows by at least 2 MiB (glibc.malloc.top_pad), so with glibc.malloc.hugetlb its growth
//   can be backed by huge pages: each fresh 4 KiB page costs a page fault, about 10 us on this project's
//   VM, and a small mesh's steps kept faulting in the pages the step before had just handed back.
//   fandisk-0.3 (13k faces), 100 iterations, `mesh.denoise` stage, eight alternating runs: median 0.080
//   -> 0.071 s, page faults of the whole run 1574 -> 715; the main job on the mug frame 6.7-7.0 -> 5.8 s
//   at 413 -> 416 MB; 810k faces 20 iterations 1.49-1.61 -> 1.37-1.45 s at 145 -> 146 MB.
void prefer_runtime_settings(char** argv) {
  if (std::getenv("SCANMESH_NO_REEXEC") != nullptr) return;
  bool changed = false;
  if (std::getenv("OMP_WAIT_POLICY") == nullptr) {
    ::setenv("OMP_WAIT_POLICY", "PASSIVE", 1);
    if (std::getenv("GOMP_SPINCOUNT") == nullptr) ::setenv("GOMP_SPINCOUNT", "10000", 1);
    changed = true;
  }
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  std::string value = tunables != nullptr ? tunables : "";
  for (const char* setting : {"glibc.malloc.hugetlb=1", "glibc.malloc.mmap_threshold=16777216", "glibc.malloc.trim_threshold=8388608",
                              "glibc.malloc.top_pad=2097152"}) {
    const std::string name = std::string(setting).substr(0, std::string(setting).find('='));
    if (value.find(name) != std::string::npos) continue;  // the user's choice stands
    if (!value.empty()) value += ':';
    value += setting;
    changed = true;
  }
  if (changed) {
    ::setenv("GLIBC_TUNABLES", value.c_str(), 1);
    ::execv("/proc/self/exe", argv);  // on failure: carry on with the defaults
  }
}

int options_command(const std::vector<std::string>& args) {
  bool markdown = false;
  std::vector<std::string> types;
  for (const auto& a : args) {
    if (a == "--markdown") markdown = true;
    else if (a == "--help" || a == "-h") {
      std::cout << "usage: scanmesh options [--markdown] [STAGE_TYPE ...]\n\nEvery option of every stage type (or of the ones named): "
                   "name, unit and range, default, meaning.\n--markdown prints the tables the README shows.\n";
      return kOk;
    } else {
      types.push_back(a);
    }
  }
  if (types.empty()) types = stage_types();
  for (const auto& t : types) {
    const std::vector<StageOption> opts = stage_options(t);
    if (markdown) {
      std::cout << "\n`" << t << "`" << (opts.empty() ? ": no options\n" : "\n\n| key / flag | value | default | meaning |\n|---|---|---|---|\n");
      auto cell = [](const std::string& text) {  // a table cell: '|' escaped
        std::string out;
        for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
        return out;
      };
      for (const auto& o : opts) {
        std::string flag = "(argument)";
        if (o.info.name != "filename") flag.assign("`").append(o.info.flag()).append("`");
        std::cout << "| `" << o.info.name << "` / " << flag << " | " << cell(o.info.domain()) << " | " << cell(o.default_value) << " | "
                  << cell(o.info.doc) << " |\n";
      }
    } else {
      std::cout << t << ":\n";
      for (const auto& o : opts)
        std::cout << "  " << o.info.name << " (" << o.info.flag() << "): " << o.info.domain() << "; default " << o.default_value << "\n      "
                  << o.info.doc << "\n";
    }
  }
  return kOk;
}

}  // namespace

int main(int argc, char** argv, void (*add_scan_stages)()) {
  const bool full = add_scan_stages != nullptr;
  prefer_runtime_settings(argv);
  if (argc < 2) {
    std::cerr << kHelp;
    return kBadUsage;
  }
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  if (!full && needs_full(command, args)) exec_full(argv);
  if (full) add_scan_stages();
  install_memory_guard(command);
  try {
    if (is_pipeline_verb(command)) return run_verb(command, args);
    if (command == "eval") return run_eval(args);
    if (command == "run") return run_pipeline(args);
    if (command == "options") return options_command(args);
    if (command == "version" || command == "--version") {
      std::cout << "scanmesh " SCANMESH_VERSION "\n";
      return kOk;
    }
    if (command == "help" || command == "--help" || command == "-h") {
      std::cout << kHelp;
      return kOk;
    }
    std::cerr << "scanmesh: unknown command '" << command << "'; commands: run, mesh, scan, denoise, noise, eval, options, version\n";
    return kBadUsage;
  } catch (const UsageError& e) {
    std::cerr << "scanmesh " << command << ": error: " << e.what() << "\n";
    return kBadUsage;
  } catch (const InputError& e) {
    std::cerr << "scanmesh " << command << ": error: " << e.what() << "\n";
    return kBadInput;
  } catch (const OutputError& e) {
    std::cerr << "scanmesh " << command << ": error: " << e.what() << "\n";
    return kBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "scanmesh " << command << ": error: out of memory (limit " << memory_limit_mb()
              << " MB: the machine's physical memory, or SCANMESH_MAX_MEMORY_MB)\n";
    return kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "scanmesh " << command << ": internal error: " << e.what() << "\n";
    return kBadInput;
  }
}

}  // namespace scanmesh::cli
