#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "slidespec/parameters.hpp"

namespace slidespec::io {

namespace {
std::string directory_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}
}  // namespace

void write_atomically(const std::string& path, const std::string& content) {
  std::string temp = path + ".tmp.XXXXXX";
  const int fd = mkstemp(temp.data());
  if (fd < 0)
    throw std::runtime_error("cannot create " + temp + ": " + std::strerror(errno));
  const char* data = content.data();
  size_t left = content.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, data, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::close(fd);
      ::unlink(temp.c_str());
      throw std::runtime_error("cannot write " + temp + ": " + why);
    }
    data += written;
    left -= static_cast<size_t>(written);
  }
  fchmod(fd, 0644);
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    ::unlink(temp.c_str());
    throw std::runtime_error("cannot flush " + temp);
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(temp.c_str());
    throw std::runtime_error("cannot rename " + temp + " to " + path + ": " + why);
  }
}

void check_output_prefix(const std::string& prefix) {
  if (prefix.empty()) throw InputError("--out: empty output prefix");
  if (std::filesystem::is_directory(prefix))
    throw InputError("--out " + prefix + ": is a directory; give a prefix such as " + prefix +
                     "/spectrum");
  const std::string dir = directory_of(prefix);
  if (!std::filesystem::is_directory(dir))
    throw InputError("--out " + prefix + ": directory " + dir + " does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw InputError("--out " + prefix + ": directory " + dir + " is not writable");
}

std::string read_file(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(what + ": cannot read " + path);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

}  // namespace slidespec::io
