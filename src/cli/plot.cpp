#include "cli/plot.hpp"

#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "io/atomic_file.hpp"
#include "util/numbers.hpp"
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

/// A scratch directory for the theory lines, removed with everything in it, also by a
/// signal that ends the command while the plotter reads them.
class ScratchDirectory {
 public:
  ScratchDirectory() {
    // A TMPDIR that is no directory must not fail a figure after the work: /tmp serves.
    std::error_code unusable;
    std::filesystem::path root = std::filesystem::temp_directory_path(unusable);
    if (unusable) root = "/tmp";
    std::string pattern = (root / "slidespec-plot-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) return;
    path_ = pattern;
    io::remove_on_signals(path_);
  }
  ~ScratchDirectory() {
    if (path_.empty()) return;
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
    for (const std::string& file : files_) io::forget_on_signals(file);
    io::forget_on_signals(path_);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  const std::string& path() const { return path_; }

  /// Writes `content` to NAME in the directory; returns its path.
  std::string write(const std::string& name, const std::string& content) {
    std::string file = path_ + "/" + name;
    io::remove_on_signals(file);
    files_.push_back(file);
    io::write_atomically(file, content);
    return file;
  }

 private:
  std::string path_;
  std::vector<std::string> files_;
};

/// A plotting process started ahead of its work: tools/plot_server.py loads matplotlib and
/// then waits for plot_spectra.py's arguments on its stdin.
struct WaitingPlotter {
  pid_t pid = -1;
  int socket = -1;  // our end of the plotter's stdin
  std::string python, script;
};

WaitingPlotter& waiting_plotter() {
  static WaitingPlotter plotter;
  return plotter;
}

WaitingPlotter start_server() {
  WaitingPlotter plotter;
  // Debian's interpreter, not whatever python3 comes first on PATH: matplotlib is there.
  plotter.python = from_environment("SLIDESPEC_PYTHON", SLIDESPEC_DEFAULT_PYTHON);
  plotter.script = tools_directory() + "/plot_server.py";
  std::vector<std::string> args = {plotter.python, plotter.script};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // A socket, not a pipe: a send to a plotter that died fails with EPIPE (MSG_NOSIGNAL)
  // instead of raising SIGPIPE in this process.
  int ends[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0) return plotter;
  const pid_t child = fork();
  if (child == 0) {
    // Ctrl-C stops the run, which then draws what accumulated: the plotter must outlive it.
    std::signal(SIGINT, SIG_IGN);
    std::signal(SIGHUP, SIG_IGN);
    if (dup2(ends[1], STDIN_FILENO) < 0) _exit(127);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(ends[1]);
  if (child < 0) {
    close(ends[0]);
    return plotter;
  }
  plotter.pid = child;
  plotter.socket = ends[0];
  io::stop_on_signals(child);
  return plotter;
}

/// Hands the plotter its arguments (NUL-separated, then end of input) and waits for it:
/// its exit status, 128 + the signal that killed it, or 127 when it could not start.
int finish(WaitingPlotter& plotter, const std::vector<std::string>& args) {
  if (plotter.pid < 0) return 127;
  std::string message;
  for (const std::string& a : args) message.append(a).push_back('\0');
  for (std::size_t sent = 0; sent < message.size();) {
    const ssize_t n = send(plotter.socket, message.data() + sent, message.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the plotter is gone: its status says how
    sent += static_cast<std::size_t>(n);
  }
  close(plotter.socket);
  int status = 0;
  while (waitpid(plotter.pid, &status, 0) < 0)
    if (errno != EINTR) return 127;
  plotter.pid = -1;
  io::stop_on_signals(0);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 127;
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
    // Digits and points, as the plotter reads them: sscanf would take 0x10x5 for 16 by 5.
    const bool plain = size.find_first_not_of("0123456789.x") == std::string::npos;
    const std::size_t times = plain ? size.find('x') : std::string::npos;
    std::string problem;
    const auto width = times == std::string::npos ? std::nullopt : util::parse_decimal(size.substr(0, times), problem);
    const auto height =
        times == std::string::npos ? std::nullopt : util::parse_decimal(size.substr(times + 1), problem);
    if (!width || !height || !(*width >= 0.5 && *width <= 100) || !(*height >= 0.5 && *height <= 100))
      throw InputError("--size: '" + size + "' is not WxH in inches (e.g. 7x5, each 0.5 to 100)");
  }
  if (!(dpi >= 10 && dpi <= 2400)) throw InputError("--dpi: must be between 10 and 2400");
  constexpr double kMostPixels = 32767;  // a side of an image cairo draws
  double width = 7, height = 6.2;
  if (!size.empty()) std::sscanf(size.c_str(), "%lfx%lf", &width, &height);
  if (format == "png" && std::max(width, height) * dpi > kMostPixels)
    throw InputError("--dpi: a " + util::format_number(width) + "x" + util::format_number(height) + " in PNG at " +
                     util::format_number(dpi) + " dpi is wider than " + util::format_number(kMostPixels) +
                     " pixels; lower --dpi or use --format pdf or svg");
}

void check_title(const std::string& title, const FigureStyle& style) {
  // A 12 pt title in matplotlib's sans-serif averages about 10 characters per inch.
  constexpr double kTitleCharactersPerInch = 10;
  constexpr double kDefaultWidth = 7;  // [in], plot_spectra.py's
  double width = kDefaultWidth;
  if (!style.size.empty()) std::sscanf(style.size.c_str(), "%lf", &width);
  // Characters, not bytes: UTF-8 continuation bytes are not counted.
  const auto characters = static_cast<std::size_t>(
      std::count_if(title.begin(), title.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
  const auto fitting = static_cast<std::size_t>(kTitleCharactersPerInch * width);
  if (characters > fitting)
    throw InputError("--title: " + std::to_string(characters) + " characters do not fit above a " +
                     util::format_number(width) + " in wide figure (at most " + std::to_string(fitting) +
                     "); shorten it or widen --size");
}

std::string format_of(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::string name = extension.empty() ? "" : extension.substr(1);
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  if (name != "png" && name != "pdf" && name != "svg")
    throw InputError(path + ": unknown figure format '" + extension + "' (known: .png, .pdf, .svg)");
  return name;
}

void start_plotter() {
  WaitingPlotter& plotter = waiting_plotter();
  if (plotter.pid < 0) plotter = start_server();
}

int plot(const std::vector<std::string>& tables, const std::string& out, const std::string& title,
         const FigureStyle& style) {
  WaitingPlotter plotter = waiting_plotter().pid >= 0 ? waiting_plotter() : start_server();
  waiting_plotter() = {};
  // Values joined to their options and paths that start with '-' led by './': the
  // plotter's parser would take -dash.tsv or a title '-x' for an option.
  std::vector<std::string> args;
  for (const std::string& table : tables) args.push_back(table.rfind('-', 0) == 0 ? "./" + table : table);
  args.insert(args.end(), {"--out=" + out, "--dpi=" + util::format_number(style.dpi)});
  if (!title.empty()) args.push_back("--title=" + title);
  if (!style.size.empty()) args.push_back("--size=" + style.size);
  std::string colors;
  for (const std::string& color : style.colors) colors += (colors.empty() ? "" : ",") + color;
  if (!colors.empty()) args.push_back("--colors=" + colors);
  if (!style.layout.empty()) args.push_back("--layout=" + style.layout);

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
        table << util::format_number(omegas[i]) << "\t" << util::format_number(spectrum[i]) << "\n";
      path = scratch.write("theory_" + std::to_string(k) + ".tsv", table.str());
      any_theory = true;
    }
    theory_lines += (k == 0 ? "" : ",") + path;
  }
  if (any_theory) args.push_back("--theory=" + theory_lines);

  const int status = finish(plotter, args);
  // Which interpreter ran, and how to choose another: the usual cure of a plotter that fails.
  const std::string source =
      std::getenv("SLIDESPEC_PYTHON") != nullptr ? " (from SLIDESPEC_PYTHON)" : " (SLIDESPEC_PYTHON chooses another)";
  if (status == 127) {
    const bool runnable = access(plotter.python.c_str(), X_OK) == 0;
    std::cerr << "slidespec: cannot start the plotter: the interpreter " << plotter.python << source
              << (runnable ? "" : std::string(": ") + std::strerror(errno)) << "\n";
  } else if (status > 128) {
    std::cerr << "slidespec: the plotter was killed by signal " << status - 128 << "\n";
  } else if (status != 0 && status != 2) {  // 2: plot_spectra.py refused its input and said why
    std::cerr << "slidespec: the plotter " << plotter.script << " failed (exit status " << status
              << ") under the interpreter " << plotter.python << source
              << "; unless it said why above, does that interpreter have matplotlib?\n";
  }
  std::error_code unreadable;
  if (status == 0 && std::filesystem::file_size(out, unreadable) == 0) {
    // A plotter that claims success must have drawn something: an empty figure is a failure.
    std::cerr << "slidespec: the plotter " << plotter.python << " ended with status 0 but drew nothing\n";
    return 1;
  }
  return status == 0 || status == 2 ? status : 1;
}

}  // namespace slidespec::cli
