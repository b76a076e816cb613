#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>

#include "slidespec/input_error.hpp"

namespace slidespec::io {

namespace {
std::string directory_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}
}  // namespace

namespace {
void write_all(int fd, const std::string& temp, const std::string& content) {
  const char* data = content.data();
  size_t left = content.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, data, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::close(fd);
      ::unlink(temp.c_str());
      throw WriteError("cannot write " + temp + ": " + why);
    }
    data += written;
    left -= static_cast<size_t>(written);
  }
  fchmod(fd, 0644);
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    ::unlink(temp.c_str());
    throw WriteError("cannot flush " + temp);
  }
}

// A name the writer gives a temporary of `path`: PATH.tmp.XXXXXX (mkstemp's six letters
// or digits), PATH.tmp.XXXXXX.EXT (one another program writes), PATH.tmp.old.PID (a backup).
bool is_temporary_of(const std::string& name, const std::string& path_name) {
  const std::string stem = path_name + ".tmp.";
  if (name.size() <= stem.size() || name.compare(0, stem.size(), stem) != 0) return false;
  const std::string rest = name.substr(stem.size());
  auto all_of = [](const std::string& text, int (*kind)(int)) {
    for (const char c : text)
      if (!kind(static_cast<unsigned char>(c))) return false;
    return !text.empty();
  };
  if (rest.compare(0, 4, "old.") == 0) return all_of(rest.substr(4), isdigit);
  if (rest.size() < 6 || !all_of(rest.substr(0, 6), isalnum)) return false;
  return rest.size() == 6 || (rest[6] == '.' && all_of(rest.substr(7), isalnum));
}

// Removes the temporaries of `paths` left by a process that died before its rename (a
// SIGKILL, a power loss). Called once they are committed: the prefix lock keeps any other
// writer of them away, so every temporary of them but this process's own is stale. Each
// path once per process (a run's checkpoints rewrite one state), each directory read once.
void remove_stale_temporaries(const std::vector<std::string>& paths) {
  namespace fs = std::filesystem;
  static std::mutex mutex;
  static std::set<std::string> cleaned;
  const std::lock_guard<std::mutex> lock(mutex);
  std::map<std::string, std::vector<std::string>> names_by_directory;
  for (const std::string& path : paths)
    if (cleaned.insert(path).second)
      names_by_directory[directory_of(path)].push_back(fs::path(path).filename().string());
  for (const auto& [directory, names] : names_by_directory) {
    std::error_code error;
    for (fs::directory_iterator entry(directory, error), end; !error && entry != end; entry.increment(error)) {
      const std::string found = entry->path().filename().string();
      for (const std::string& name : names)
        if (is_temporary_of(found, name)) ::unlink(entry->path().c_str());
    }
  }
}

void sync_directory(const std::string& path) {
  const int fd = ::open(directory_of(path).c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}
}  // namespace

namespace {
// What a signal handler removes: lock files held and temporaries of uncommitted sets, as
// plain bytes in fixed slots. A slot is published by writing its path and then its first
// byte, and withdrawn by clearing that byte, so the handler reads no half-made name.
constexpr int kMostRemovable = 64;
char removable[kMostRemovable][4096];
std::atomic<int> removable_count{0};
std::atomic<pid_t> removable_owner{0};  // a child forked to run the plotter removes none
std::atomic<pid_t> child_stopped{0};

void publish_removable(const std::string& path) {
  if (path.empty() || path.size() >= sizeof removable[0]) return;
  int k = 0;
  const int count = removable_count.load();
  while (k < count && removable[k][0] != '\0') ++k;
  if (k == kMostRemovable) return;
  std::memcpy(removable[k] + 1, path.c_str() + 1, path.size());
  std::atomic_signal_fence(std::memory_order_seq_cst);
  removable[k][0] = path[0];
  removable_owner = ::getpid();
  if (k == count) removable_count = k + 1;
}

void withdraw_removable(const std::string& path) {
  const int count = removable_count.load();
  for (int k = 0; k < count; ++k)
    if (removable[k][0] != '\0' && path == removable[k]) removable[k][0] = '\0';
}

// Holds back the signals that remove files, from a file's creation until it is published:
// a signal between the two would leave a lock or a temporary nobody removes. On the
// creating thread; the locks are taken before any worker thread starts.
class SignalsHeld {
 public:
  SignalsHeld() {
    sigset_t held;
    sigemptyset(&held);
    for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&held, signal);
    pthread_sigmask(SIG_BLOCK, &held, &before_);
  }
  ~SignalsHeld() { pthread_sigmask(SIG_SETMASK, &before_, nullptr); }
  SignalsHeld(const SignalsHeld&) = delete;
  SignalsHeld& operator=(const SignalsHeld&) = delete;

 private:
  sigset_t before_{};
};

extern "C" void remove_files_and_end(int signal) {
  // The plotter would go on writing a temporary removed here, or read a table gone.
  if (const pid_t child = child_stopped.load(); child > 0) ::kill(child, SIGKILL);
  if (::getpid() == removable_owner.load()) {
    for (int k = 0; k < removable_count.load(); ++k)
      if (removable[k][0] != '\0') ::unlink(removable[k]);
    // Directories after every file: a scratch directory empties before it goes.
    for (int k = 0; k < removable_count.load(); ++k)
      if (removable[k][0] != '\0') ::rmdir(removable[k]);
  }
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}
}  // namespace

void write_atomically(const std::string& path, const std::string& content) {
  OutputSet one;
  one.add(path, content);
  one.commit();
}

OutputSet::~OutputSet() {
  for (const Pending& p : pending_)
    if (!p.temp.empty()) {
      ::unlink(p.temp.c_str());
      withdraw_removable(p.temp);
    }
}

void OutputSet::forget_pending() {
  for (const Pending& p : pending_) withdraw_removable(p.temp);
  pending_.clear();
}

void OutputSet::add(const std::string& path, const std::string& content) {
  std::string temp = path + ".tmp.XXXXXX";
  int fd = -1;
  {
    const SignalsHeld held;
    fd = mkstemp(temp.data());
    if (fd < 0) throw WriteError("cannot create " + temp + ": " + std::strerror(errno));
    publish_removable(temp);
  }
  write_all(fd, temp, content);
  pending_.push_back({path, temp});
}

std::string OutputSet::add_written_by_other(const std::string& path, const std::string& extension) {
  std::string temp = path + ".tmp.XXXXXX" + extension;
  const SignalsHeld held;
  const int fd = mkstemps(temp.data(), static_cast<int>(extension.size()));
  if (fd < 0) throw WriteError("cannot create " + temp + ": " + std::strerror(errno));
  ::close(fd);
  publish_removable(temp);
  pending_.push_back({path, temp});
  return temp;
}

const std::string& OutputSet::temporary(const std::string& path) const {
  for (const Pending& p : pending_)
    if (p.path == path && !p.temp.empty()) return p.temp;
  throw std::logic_error("OutputSet: no " + path);
}

void OutputSet::drop(const std::string& path) {
  for (auto p = pending_.begin(); p != pending_.end(); ++p)
    if (p->path == path) {
      ::unlink(p->temp.c_str());
      withdraw_removable(p->temp);
      p->temp.clear();
      return;
    }
}

void OutputSet::commit() {
  // The other program's file must be on disk too before it replaces anything.
  for (const Pending& p : pending_) {
    if (p.temp.empty()) continue;
    const int fd = ::open(p.temp.c_str(), O_RDONLY);
    if (fd < 0 || ::fsync(fd) != 0) {
      if (fd >= 0) ::close(fd);
      throw WriteError("cannot flush " + p.temp);
    }
    ::close(fd);
  }
  // A hard link keeps each old file, so a failed rename further on can put it back.
  std::vector<std::string> backups(pending_.size());
  auto remove_backups = [&] {
    for (const std::string& b : backups)
      if (!b.empty()) ::unlink(b.c_str());
  };
  for (std::size_t k = 0; k < pending_.size(); ++k) {
    if (::access(pending_[k].path.c_str(), F_OK) != 0) continue;
    backups[k] = pending_[k].path + ".tmp.old." + std::to_string(::getpid());
    ::unlink(backups[k].c_str());  // left by a dead process of the same id, if anything
    if (::link(pending_[k].path.c_str(), backups[k].c_str()) != 0) {
      const std::string why = std::strerror(errno);
      const std::string kept = pending_[k].path;
      backups[k].clear();
      remove_backups();
      for (const Pending& p : pending_)
        if (!p.temp.empty()) ::unlink(p.temp.c_str());
      forget_pending();
      throw WriteError("cannot keep the old " + kept + " while replacing it: " + why);
    }
  }
  for (std::size_t k = 0; k < pending_.size(); ++k) {
    const Pending& p = pending_[k];
    if (p.temp.empty() ? (::unlink(p.path.c_str()) == 0 || errno == ENOENT)
                       : std::rename(p.temp.c_str(), p.path.c_str()) == 0)
      continue;
    const std::string why = std::strerror(errno);
    for (std::size_t j = 0; j < k; ++j) {
      if (!backups[j].empty())
        std::rename(backups[j].c_str(), pending_[j].path.c_str());
      else
        ::unlink(pending_[j].path.c_str());
      backups[j].clear();
    }
    remove_backups();
    const std::string failed = pending_[k].path;
    for (std::size_t j = k; j < pending_.size(); ++j)
      if (!pending_[j].temp.empty()) ::unlink(pending_[j].temp.c_str());
    forget_pending();
    throw WriteError("cannot write " + failed + ": " + why + " (no output of the set was changed)");
  }
  remove_backups();
  std::vector<std::string> committed;
  for (const Pending& p : pending_) {
    committed.push_back(p.path);
    sync_directory(p.path);
  }
  remove_stale_temporaries(committed);
  forget_pending();
}

namespace {
bool hangups_ignored_at_start = false;
}  // namespace

void remove_locks_on_signals() {
  // nohup's ignored SIGHUP is kept: such a command is meant to outlive its terminal.
  struct sigaction hangup {};
  hangups_ignored_at_start = sigaction(SIGHUP, nullptr, &hangup) == 0 && hangup.sa_handler == SIG_IGN;
  for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT})
    if (signal != SIGHUP || !hangups_ignored_at_start) std::signal(signal, remove_files_and_end);
}

bool hangups_ignored() { return hangups_ignored_at_start; }

void stop_on_signals(pid_t child) { child_stopped = child; }

void remove_on_signals(const std::string& path) { publish_removable(path); }

void forget_on_signals(const std::string& path) { withdraw_removable(path); }

OutputLock::OutputLock(const std::vector<std::string>& prefixes) {
  for (const std::string& prefix : prefixes) {
    const std::string path = prefix + ".lock";
    bool duplicate = false;
    for (const Held& h : held_) duplicate = duplicate || h.path == path;
    if (duplicate) continue;
    // A lock taken on a file another holder has just removed would lock nothing: take it
    // again until the locked file is the one at `path`.
    for (int attempt = 0;; ++attempt) {
      const SignalsHeld held;
      const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (fd < 0) throw FileError(prefix + ": cannot create the lock file " + path + ": " + std::strerror(errno));
      if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        ::close(fd);
        throw InputError(prefix + ": another slidespec is writing this output prefix (" + path +
                         " is locked); wait for it or choose another {out}");
      }
      struct stat opened {
      }, named{};
      if (::fstat(fd, &opened) == 0 && ::stat(path.c_str(), &named) == 0 && opened.st_ino == named.st_ino &&
          opened.st_dev == named.st_dev) {
        held_.push_back({path, fd});
        publish_removable(path);
        break;
      }
      ::close(fd);
      if (attempt > 100) throw InputError(prefix + ": cannot lock " + path);
    }
  }
}

OutputLock::~OutputLock() {
  const SignalsHeld held;
  for (const Held& h : held_) {
    withdraw_removable(h.path);
    ::unlink(h.path.c_str());
    ::close(h.fd);
  }
}

void remove_durably(const std::string& path) {
  if (::unlink(path.c_str()) == 0) sync_directory(path);
}

void check_output_prefix(const std::string& prefix) {
  if (prefix.empty()) throw InputError("{out}: empty output prefix");
  if (std::filesystem::is_directory(prefix))
    throw InputError("{out} " + prefix + ": is a directory; give a prefix such as " + prefix + "/spectrum");
  const std::string dir = directory_of(prefix);
  if (!std::filesystem::is_directory(dir))
    throw FileError("{out} " + prefix + ": directory " + dir + " does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw FileError("{out} " + prefix + ": directory " + dir + " is not writable");
}

std::string read_file(const std::string& path, const std::string& what, std::size_t most_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(what + ": cannot read " + path);
  std::string bytes;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    bytes.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (bytes.size() > most_bytes)
      throw InputError(what + ": " + path + " is longer than " + std::to_string(most_bytes) +
                       " bytes, the most this file may hold");
  }
  return bytes;
}

}  // namespace slidespec::io
