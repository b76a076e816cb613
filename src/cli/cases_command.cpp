// `slidespec cases`: the named cases and their parameters.
#include <iostream>
#include <memory>

#include "cli/command.hpp"

namespace slidespec::cli {

namespace {

class CasesCommand final : public Command {
 public:
  explicit CasesCommand(CLI::App& app)
      : Command(app.add_subcommand("cases", "list the named cases and their parameters")) {}

  int run() override {
    for (const Case& c : cases()) {
      const Parameters p = ParameterBuilder(c.name).build();
      std::cout << c.name << "\t" << c.description << "\n ";
      for (const auto& [key, value] : describe(p)) std::cout << " " << key << "=" << value;
      std::cout << "\n";
    }
    return 0;
  }
};

}  // namespace

std::unique_ptr<Command> make_cases_command(CLI::App& app) { return std::make_unique<CasesCommand>(app); }

}  // namespace slidespec::cli
