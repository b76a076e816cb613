#include "cli/plot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/parameters.hpp"

namespace slidespec::cli {

namespace {

std::string from_environment(const char* name, const std::string& fallback) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? value : fallback;
}

/// The directory of plot_spectra.py: $SLIDESPEC_TOOLS, else beside an installed
/// executable (PREFIX/bin/slidespec -> PREFIX/share/slidespec), else the source tree.
std::string tools_directory() {
  std::error_code error;
  const auto executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const auto installed = executable.parent_path().parent_path() / "share" / "slidespec";
    if (std::filesystem::exists(installed / "plot_spectra.py", error))
      return from_environment("SLIDESPEC_TOOLS", installed);
  }
  return from_environment("SLIDESPEC_TOOLS", SLIDESPEC_TOOLS_DIR);
}

/// A scratch directory for the theory lines, removed with everything in it.
class ScratchDirectory {
 public:
  ScratchDirectory() {
    std::string pattern = (std::filesystem::temp_directory_path() / "slidespec-plot-XXXXXX").string();
    if (mkdtemp(pattern.data()) != nullptr) path_ = pattern;
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

int run_tool(std::vector<std::string> args) {
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
  return WEXITSTATUS(status);
}

}  // namespace

void FigureStyle::add_to(CLI::App& command) {
  command.add_option("--format", format, "figure format: png|pdf|svg (default png)");
  add_size_to(command);
}

void FigureStyle::add_size_to(CLI::App& command) {
  command.add_option("--size", size, "figure size WxH in inches (default 7x5; 7x6.2 with the residual panel)");
  command.add_option("--dpi", dpi, "figure resolution in dots per inch (default 150)");
}

void FigureStyle::check() const {
  if (format != "png" && format != "pdf" && format != "svg")
    throw InputError("--format: unknown figure format '" + format + "' (known: png, pdf, svg)");
  if (!size.empty()) {
    double width = 0, height = 0;
    char rest = 0;
    if (std::sscanf(size.c_str(), "%lfx%lf%c", &width, &height, &rest) != 2 || !(width >= 0.5 && width <= 100) ||
        !(height >= 0.5 && height <= 100))
      throw InputError("--size: '" + size + "' is not WxH in inches (e.g. 7x5, each 0.5 to 100)");
  }
  if (!(dpi >= 10 && dpi <= 2400)) throw InputError("--dpi: must be between 10 and 2400");
}

std::string format_of(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::string name = extension.empty() ? "" : extension.substr(1);
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  if (name != "png" && name != "pdf" && name != "svg")
    throw InputError(path + ": unknown figure format '" + extension + "' (known: .png, .pdf, .svg)");
  return name;
}

int plot(const std::vector<std::string>& tables, const std::string& out, const std::string& title,
         const FigureStyle& style) {
  // Debian's interpreter, not whatever python3 comes first on PATH: matplotlib is there.
  const std::string python = from_environment("SLIDESPEC_PYTHON", SLIDESPEC_DEFAULT_PYTHON);
  const std::string script = tools_directory() + "/plot_spectra.py";
  std::vector<std::string> args = {python, script};
  args.insert(args.end(), tables.begin(), tables.end());
  args.insert(args.end(), {"-o", out, "--dpi", io::format_number(style.dpi)});
  if (!title.empty()) args.insert(args.end(), {"--title", title});
  if (!style.size.empty()) args.insert(args.end(), {"--size", style.size});
  std::string colors;
  for (const std::string& color : style.colors) colors += (colors.empty() ? "" : ",") + color;
  if (!colors.empty()) args.insert(args.end(), {"--colors", colors});

  ScratchDirectory scratch;
  std::string theory_lines;
  bool any_theory = false;
  for (std::size_t k = 0; k < tables.size(); ++k) {
    const auto [omegas, spectrum] = fine_theory_of_table(tables[k]);
    std::string path = "-";
    if (!omegas.empty() && !scratch.path().empty()) {
      std::ostringstream table;
      table << "# exact first-order theory on a fine grid\n# omega\tC_x\n";
      for (std::size_t i = 0; i < omegas.size(); ++i)
        table << io::format_number(omegas[i]) << "\t" << io::format_number(spectrum[i]) << "\n";
      path = scratch.path() + "/theory_" + std::to_string(k) + ".tsv";
      io::write_atomically(path, table.str());
      any_theory = true;
    }
    theory_lines += (k == 0 ? "" : ",") + path;
  }
  if (any_theory) args.insert(args.end(), {"--theory", theory_lines});

  const int status = run_tool(args);
  if (status == 127)
    std::cerr << "slidespec: cannot start " << python << " " << script << " (is python3-matplotlib installed?)\n";
  return status;
}

}  // namespace slidespec::cli
