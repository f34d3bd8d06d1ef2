#pragma once
// Runs the scanmesh executable in a child process and reports how it ended (exit code or signal, peak
// memory, time, stderr), for the command-line tests.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <string>
#include <thread>
#include <vector>

#include "scanmesh/atomic_file.h"

namespace scanmesh::test {

struct Outcome {
  int exit_code = -1;  ///< -1 if killed by a signal
  int signal = 0;
  double peak_mb = 0.0;
  double seconds = 0.0;
  std::string err;
};

/// Starts scanmesh with `args`, stderr into `err_file`, stdout discarded. Returns the child's pid.
inline pid_t spawn_scanmesh(const std::vector<std::string>& args, const std::string& err_file) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 2);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    std::vector<char*> argv;
    std::string bin = SCANMESH_BIN;
    argv.push_back(bin.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(bin.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

/// Waits for a child started by spawn_scanmesh; one still running after `timeout` seconds is killed.
inline Outcome wait_scanmesh(pid_t pid, const std::string& err_file, double timeout = 120.0) {
  const auto t0 = std::chrono::steady_clock::now();
  Outcome o;
  int status = 0;
  rusage usage{};
  for (;;) {
    const pid_t r = ::wait4(pid, &status, WNOHANG, &usage);
    if (r == pid) break;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout) {
      ::kill(pid, SIGKILL);
      ::wait4(pid, &status, 0, &usage);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (WIFEXITED(status)) o.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) o.signal = WTERMSIG(status);
  o.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
  o.err = scanmesh::read_file(err_file);
  return o;
}

/// Runs scanmesh to the end (a run past `timeout` seconds is killed: a hang).
inline Outcome run_scanmesh(const std::vector<std::string>& args, const std::string& err_file, double timeout = 120.0) {
  return wait_scanmesh(spawn_scanmesh(args, err_file), err_file, timeout);
}

}  // namespace scanmesh::test
