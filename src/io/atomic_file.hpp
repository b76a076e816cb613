// Output files appear whole or not at all.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <sys/types.h>
#include <vector>

namespace slidespec::io {

/// The system failed a write while working (a full disk, say): not the input's fault. The
/// CLI exits with status 1; Python raises OSError.
class WriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The largest run state read (bytes): far above any run's, far below a machine's memory.
inline constexpr std::size_t kMostStateBytes = std::size_t{1} << 30;

/// Writes `content` to a temporary file beside `path`, flushes it to disk and renames it
/// over `path`, so a reader (or an interrupt) never sees a half-written file.
void write_atomically(const std::string& path, const std::string& content);

/// Several outputs that appear together or not at all. Each is written to a temporary
/// beside it and flushed first; commit() then renames them in order. If a rename fails
/// (or anything before it, a full disk say), every file already renamed is put back as it
/// was (restored from a hard link to the old file, or removed if it was new) and no
/// temporary remains. Only a crash between the renames (power loss, SIGKILL) can leave a
/// part of the set new; then each file is still whole, old or new. A committed set also
/// removes the temporaries of its files that such a crash left (the prefix lock keeps
/// every other writer of them away).
class OutputSet {
 public:
  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet();  // removes the temporaries of an uncommitted set

  /// Writes `content` to the temporary of `path` (throws WriteError, nothing visible).
  void add(const std::string& path, const std::string& content);
  /// A fresh empty temporary for `path`, ending in `extension` (".png"), for another program
  /// to write; it joins the set. Returns its name.
  std::string add_written_by_other(const std::string& path, const std::string& extension);
  /// The temporary that will become `path` (to read a table before it is committed).
  const std::string& temporary(const std::string& path) const;
  /// `path` is not produced after all (a plot that failed to draw): an old file there, of
  /// another run, goes with the commit, so no old member of the set stays beside new ones.
  void drop(const std::string& path);
  void commit();

 private:
  struct Pending {
    std::string path, temp;
  };
  std::vector<Pending> pending_;
  void forget_pending();
};

/// While alive, holds an exclusive lock on PREFIX.lock for each prefix (flock, released
/// by the kernel if the process dies), so two commands never write one output prefix at
/// once. A prefix already locked throws InputError naming it. The lock files are removed
/// when the locks are released.
class OutputLock {
 public:
  explicit OutputLock(const std::vector<std::string>& prefixes);
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();

 private:
  struct Held {
    std::string path;
    int fd;
  };
  std::vector<Held> held_;
};

/// From now on SIGINT, SIGTERM, SIGHUP and SIGQUIT remove the lock files this process holds
/// and the temporaries of its uncommitted output sets before they end it as they would have: a command killed by a
/// signal leaves no PREFIX.lock (run replaces the INT and TERM handlers with its own, which save its state first).
void remove_locks_on_signals();

/// Whether SIGHUP was ignored when remove_locks_on_signals() was called (nohup): it stays so.
bool hangups_ignored();

/// Until forget_on_signals(path), those signals also remove `path`: a scratch file, or a
/// scratch directory, removed once the files published in it are gone.
void remove_on_signals(const std::string& path);
void forget_on_signals(const std::string& path);

/// From now on those signals first end `child` (the plotter, drawing into a temporary that
/// they remove); 0 names none.
void stop_on_signals(pid_t child);

/// Removes `path` (a finished run's state) and flushes its directory, so the removal
/// itself is durable; a file already gone is fine.
void remove_durably(const std::string& path);

/// The whole of a file (a saved run state, say); FileError "WHAT: cannot read PATH", or
/// naming the limit when it holds more than `most_bytes` (so an endless stream ends).
std::string read_file(const std::string& path, const std::string& what, std::size_t most_bytes = kMostStateBytes);

/// Throws InputError naming the problem if files PREFIX.* cannot be created: checked
/// before any computation starts, so a bad --out fails in a second, not after an hour.
void check_output_prefix(const std::string& prefix);

}  // namespace slidespec::io
