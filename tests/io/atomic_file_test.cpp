// The atomic writer: single files and sets of outputs appear whole, together or not at all,
// also when the disk fills between them.
#include "io/atomic_file.hpp"

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using slidespec::io::OutputSet;

namespace {

struct Scratch {
  fs::path dir;
  Scratch() {
    std::string name = (fs::temp_directory_path() / "slidespec_io_XXXXXX").string();
    dir = mkdtemp(name.data());
  }
  ~Scratch() {
    std::error_code error;
    fs::remove_all(dir, error);
  }
  std::string operator/(const std::string& name) const { return (dir / name).string(); }
};

std::string content_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

void write_plain(const std::string& path, const std::string& content) {
  std::ofstream(path, std::ios::binary) << content;
}

/// Names in the directory other than those given: temporaries left behind.
std::vector<std::string> others(const fs::path& dir, const std::vector<std::string>& expected) {
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (std::find(expected.begin(), expected.end(), name) == expected.end()) found.push_back(name);
  }
  return found;
}

}  // namespace

TEST(AtomicWriter, ReplacesAFileWhole) {
  Scratch s;
  write_plain(s / "a.tsv", "old");
  slidespec::io::write_atomically(s / "a.tsv", "new content");
  EXPECT_EQ(content_of(s / "a.tsv"), "new content");
  EXPECT_TRUE(others(s.dir, {"a.tsv"}).empty());
}

TEST(OutputSet, CommitMakesEveryFileAppear) {
  Scratch s;
  write_plain(s / "out.tsv", "old table");
  {
    OutputSet set;
    set.add(s / "out.tsv", "table");
    set.add(s / "out.json", "{}");
    const std::string png = set.add_written_by_other(s / "out.png", ".png");
    EXPECT_EQ(png.substr(png.size() - 4), ".png");
    write_plain(png, "picture");
    EXPECT_EQ(content_of(set.temporary(s / "out.tsv")), "table");
    // Nothing is visible before the commit.
    EXPECT_EQ(content_of(s / "out.tsv"), "old table");
    EXPECT_FALSE(fs::exists(s / "out.json"));
    set.commit();
  }
  EXPECT_EQ(content_of(s / "out.tsv"), "table");
  EXPECT_EQ(content_of(s / "out.json"), "{}");
  EXPECT_EQ(content_of(s / "out.png"), "picture");
  EXPECT_TRUE(others(s.dir, {"out.tsv", "out.json", "out.png"}).empty());
}

TEST(OutputSet, AnUncommittedSetLeavesNothing) {
  Scratch s;
  write_plain(s / "out.tsv", "old");
  {
    OutputSet set;
    set.add(s / "out.tsv", "new");
    set.add(s / "out.json", "new");
  }
  EXPECT_EQ(content_of(s / "out.tsv"), "old");
  EXPECT_TRUE(others(s.dir, {"out.tsv"}).empty());
}

TEST(OutputSet, AFailedRenameRollsBackTheFilesBeforeIt) {
  Scratch s;
  write_plain(s / "out.tsv", "old table");
  fs::create_directory(s / "out.json");  // rename of a file over a directory fails
  write_plain(s / "out.json/inside", "x");
  OutputSet set;
  set.add(s / "out.png", "new picture");  // a new file: removed again
  set.add(s / "out.tsv", "new table");    // an old file: restored
  set.add(s / "out.json", "{}");
  EXPECT_THROW(set.commit(), std::runtime_error);
  EXPECT_EQ(content_of(s / "out.tsv"), "old table");
  EXPECT_FALSE(fs::exists(s / "out.png"));
  EXPECT_TRUE(fs::is_directory(s / "out.json"));
  EXPECT_TRUE(others(s.dir, {"out.tsv", "out.json"}).empty());
}

TEST(OutputSet, AFullDiskChangesNoFileOfTheSet) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs; the full-disk case is not tested here";
  Scratch s;
  const std::string mount_point = s / "small";
  fs::create_directory(mount_point);
  if (::mount("tmpfs", mount_point.c_str(), "tmpfs", 0, "size=256k") != 0)
    GTEST_SKIP() << "cannot mount a 256 KiB tmpfs here (" << std::strerror(errno)
                 << "); the full-disk case is not tested on this machine";
  struct Unmount {
    std::string path;
    ~Unmount() { ::umount(path.c_str()); }
  } unmount{mount_point};
  const std::string tsv = mount_point + "/out.tsv", json = mount_point + "/out.json";
  write_plain(tsv, "old table");
  write_plain(json, "old json");
  // Fill the disk but for about 40 KiB.
  {
    std::ofstream filler(mount_point + "/filler", std::ios::binary);
    filler << std::string(256 * 1024 - 40 * 1024 - 3 * 4096, 'f');
  }
  {
    OutputSet set;
    set.add(tsv, std::string(20 * 1024, 't'));                                      // fits
    EXPECT_THROW(set.add(json, std::string(100 * 1024, 'j')), std::runtime_error);  // does not
  }
  EXPECT_EQ(content_of(tsv), "old table");
  EXPECT_EQ(content_of(json), "old json");
  EXPECT_TRUE(others(mount_point, {"out.tsv", "out.json", "filler"}).empty());
}

TEST(OutputSet, ADroppedMemberTakesTheOldFileOfAnotherRunAlong) {
  Scratch s;
  write_plain(s / "out.tsv", "old table");
  write_plain(s / "out.png", "old picture");
  {
    OutputSet set;
    set.add(s / "out.tsv", "new table");
    set.add_written_by_other(s / "out.png", ".png");
    set.drop(s / "out.png");  // the plot failed
    set.commit();
  }
  EXPECT_EQ(content_of(s / "out.tsv"), "new table");
  EXPECT_FALSE(fs::exists(s / "out.png"));
  EXPECT_TRUE(others(s.dir, {"out.tsv"}).empty());
}
