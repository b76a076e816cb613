// `slidespec plot`: spectrum tables (of run, theory, sweep) overlaid in one picture.
#include <memory>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "cli/plot.hpp"
#include "io/atomic_file.hpp"

namespace slidespec::cli {

namespace {

class PlotCommand final : public Command {
 public:
  explicit PlotCommand(CLI::App& app) : Command(app.add_subcommand("plot", "overlay spectrum tables in one picture")) {
    CLI::App& c = subcommand();
    c.add_option("tables", tables_, "TSV files from run or theory")->required();
    c.add_option("-o,--out", out_, "the figure to write: .png, .pdf or .svg")->required();
    c.add_option("--title", title_, "title of the picture");
    figure_.add_size_to(c);
  }

  Files files() const override {
    Files files;
    for (const std::string& path : tables_) files.input(path, "plot");
    files.output(out_, "--out");
    files.prefixes.push_back({out_, "--out"});
    return files;
  }

  int run() override {
    figure_.format = format_of(out_);
    figure_.check();
    check_title(title_, figure_);
    io::check_output_prefix(out_);
    return plot(tables_, out_, title_, figure_);
  }

 private:
  std::vector<std::string> tables_;
  std::string out_, title_;
  FigureStyle figure_;
};

}  // namespace

std::unique_ptr<Command> make_plot_command(CLI::App& app, const Context&) { return std::make_unique<PlotCommand>(app); }

}  // namespace slidespec::cli
