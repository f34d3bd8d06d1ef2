#include "scanmesh/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "scanmesh/errors.h"

namespace scanmesh {
namespace {

namespace fs = std::filesystem;

// Temporaries the signal handler removes: fixed storage, because a handler may only call
// async-signal-safe functions (unlink) and must not allocate or lock.
constexpr int kSlots = 256;
constexpr std::size_t kPathMax = 4096;
char g_paths[kSlots][kPathMax];
std::atomic<int> g_state[kSlots];  // 0 free, 1 being filled, 2 a live temporary

extern "C" void remove_temporaries_and_die(int sig) {
  for (int i = 0; i < kSlots; ++i)
    if (g_state[i].load() == 2) ::unlink(g_paths[i]);
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      ::sigaction(sig, nullptr, &old);
      if (old.sa_handler != SIG_DFL) continue;  // the program handles it itself (or ignores it)
      struct sigaction sa {};
      sa.sa_handler = remove_temporaries_and_die;
      sigemptyset(&sa.sa_mask);
      ::sigaction(sig, &sa, nullptr);
    }
  });
}

int register_temporary(const std::string& path) {
  if (path.size() >= kPathMax) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_state[i].compare_exchange_strong(expected, 1)) {
      std::memcpy(g_paths[i], path.c_str(), path.size() + 1);
      g_state[i].store(2);
      return i;
    }
  }
  return -1;  // more than kSlots at once: still removed by the transaction, not by a signal
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_state[slot].store(0);
}

fs::path folder_of(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

// ".NAME.tmp.PID." prefix of this process's temporaries for `target`.
std::string temp_prefix(const fs::path& target) { return std::string(".").append(target.filename().string()).append(".tmp."); }

// Removes temporaries for `target` whose writing process no longer exists (a run killed with SIGKILL).
void remove_stale_temporaries(const fs::path& target) {
  const std::string prefix = temp_prefix(target);
  DIR* d = ::opendir(folder_of(target).c_str());
  if (d == nullptr) return;
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const long pid = std::strtol(name.c_str() + prefix.size(), nullptr, 10);
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) ::unlink((folder_of(target) / name).c_str());
  }
  ::closedir(d);
}

[[noreturn]] void fail(const std::string& path, const std::string& why) { throw OutputError("cannot write '" + path + "': " + why); }

}  // namespace

struct OutputTransaction::Impl {
  struct Entry {
    std::string target, temp;
    int slot = -1;
  };
  std::vector<Entry> entries;
  void discard(Entry& e) {
    if (!e.temp.empty()) ::unlink(e.temp.c_str());
    unregister_temporary(e.slot);
    e.temp.clear();
    e.slot = -1;
  }
};

OutputTransaction::OutputTransaction() : impl_(std::make_unique<Impl>()) { install_handlers(); }

OutputTransaction::~OutputTransaction() {
  for (auto& e : impl_->entries) impl_->discard(e);
}

void OutputTransaction::write(const std::string& path, std::string_view bytes) {
  write_with(path, [bytes](const ByteSink& sink) { sink(bytes); });
}

void OutputTransaction::write_with(const std::string& path, const std::function<void(const ByteSink&)>& produce) {
  const fs::path target(path);
  check_writable(path);
  remove_stale_temporaries(target);
  std::string tmpl = (folder_of(target) / (temp_prefix(target) + std::to_string(::getpid()) + ".XXXXXX")).string();
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0) fail(path, std::strerror(errno));
  Impl::Entry entry{path, tmpl, register_temporary(tmpl)};
  const ByteSink sink = [&](std::string_view bytes) {
    const char* p = bytes.data();
    std::size_t left = bytes.size();
    while (left > 0) {
      const ssize_t n = ::write(fd, p, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        fail(path, std::strerror(errno));
      }
      p += n;
      left -= static_cast<std::size_t>(n);
    }
  };
  try {
    produce(sink);
  } catch (...) {
    ::close(fd);
    impl_->discard(entry);
    throw;
  }
  // Give the file ordinary permissions (mkstemp creates it 0600), respecting the umask.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const std::string why = std::strerror(errno);
    impl_->discard(entry);
    fail(path, why);
  }
  for (auto& e : impl_->entries)
    if (e.target == path) {
      impl_->discard(e);
      e = entry;
      return;
    }
  impl_->entries.push_back(entry);
}

void OutputTransaction::commit() {
  // Lock every target folder (in a fixed order, so two committing runs cannot deadlock), rename, unlock.
  std::vector<std::string> folders;
  for (const auto& e : impl_->entries) folders.push_back(fs::absolute(folder_of(e.target)).lexically_normal().string());
  std::sort(folders.begin(), folders.end());
  folders.erase(std::unique(folders.begin(), folders.end()), folders.end());
  std::vector<int> locks;
  for (const auto& f : folders) {
    const int fd = ::open(f.c_str(), O_RDONLY | O_DIRECTORY);
    if (fd >= 0) {
      while (::flock(fd, LOCK_EX) != 0 && errno == EINTR) {
      }
      locks.push_back(fd);
    }
  }
  std::string error;
  for (auto it = impl_->entries.rbegin(); it != impl_->entries.rend(); ++it) {
    auto& e = *it;
    if (std::rename(e.temp.c_str(), e.target.c_str()) != 0) {
      error = "cannot write '" + e.target + "': " + std::strerror(errno);
      break;
    }
    unregister_temporary(e.slot);
    e.temp.clear();
    e.slot = -1;
  }
  for (int fd : locks) ::close(fd);  // closing releases the lock
  for (auto& e : impl_->entries) impl_->discard(e);
  impl_->entries.clear();
  if (!error.empty()) throw OutputError(error);
}

std::vector<std::string> OutputTransaction::targets() const {
  std::vector<std::string> t;
  for (const auto& e : impl_->entries) t.push_back(e.target);
  return t;
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  OutputTransaction t;
  t.write(path, bytes);
  t.commit();
}

void write_file_atomically(const std::string& path, const std::function<void(const ByteSink&)>& produce) {
  OutputTransaction t;
  t.write_with(path, produce);
  t.commit();
}

void check_writable(const std::string& path) {
  const fs::path dir = folder_of(fs::path(path));
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) fail(path, "folder '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK | X_OK) != 0) fail(path, "folder '" + dir.string() + "' is not writable (" + std::strerror(errno) + ")");
  if (fs::is_directory(path, ec)) fail(path, "it is a folder");
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError("cannot read '" + path + "': it is a directory");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw InputError("cannot open '" + path + "': " + std::strerror(errno));
  std::string data;
  // A regular file is read into one buffer of its size (growing a string chunk by chunk copied a big
  // file several times over and briefly held up to twice its size); what is not a regular file (a pipe)
  // or grew meanwhile is read in chunks after that.
  struct stat st {};
  if (::fstat(::fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
    data.resize(static_cast<std::size_t>(st.st_size));
    data.resize(std::fread(data.data(), 1, data.size(), f));
  }
  char buf[1 << 16];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) data.append(buf, n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw InputError("cannot read '" + path + "': read error");
  return data;
}

std::string read_file_head(const std::string& path, std::size_t max_bytes) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw InputError("cannot open '" + path + "': " + std::strerror(errno));
  std::string data(max_bytes, '\0');
  data.resize(std::fread(data.data(), 1, max_bytes, f));
  std::fclose(f);
  return data;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec) &&
         std::filesystem::equivalent(a, b, ec);
}

}  // namespace scanmesh
