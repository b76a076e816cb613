#include "cli/plot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <iostream>

namespace slidespec::cli {

namespace {
std::string from_environment(const char* name, const char* fallback) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? value : fallback;
}
}  // namespace

int plot(const std::vector<std::string>& tables, const std::string& png, const std::string& title) {
  // Debian's interpreter, not whatever python3 comes first on PATH: matplotlib is there.
  const std::string python = from_environment("SLIDESPEC_PYTHON", SLIDESPEC_DEFAULT_PYTHON);
  const std::string script = from_environment("SLIDESPEC_TOOLS", SLIDESPEC_TOOLS_DIR) + "/plot_spectra.py";
  std::vector<std::string> args = {python, script};
  args.insert(args.end(), tables.begin(), tables.end());
  args.insert(args.end(), {"-o", png});
  if (!title.empty()) args.insert(args.end(), {"--title", title});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  const pid_t child = fork();
  if (child == 0) {
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  if (child < 0 || waitpid(child, &status, 0) < 0 || !WIFEXITED(status)) return 127;
  if (WEXITSTATUS(status) == 127)
    std::cerr << "slidespec: cannot start " << python << " " << script
              << " (is python3-matplotlib installed?)\n";
  return WEXITSTATUS(status);
}

}  // namespace slidespec::cli
