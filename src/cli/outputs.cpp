#include "cli/outputs.hpp"

#include <climits>
#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "slidespec/parameters.hpp"

namespace slidespec::cli {

namespace {

namespace fs = std::filesystem;

struct File {
  std::string path;
  std::string option;  // the option that named it, for the message
};

// The longest name the atomic writer derives from an output: PATH.tmp.XXXXXX.png.
constexpr std::size_t kLongestSuffix = 20;

bool valid_utf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto lead = static_cast<unsigned char>(s[i]);
    const std::size_t more = lead < 0x80                   ? 0
                             : lead >= 0xc2 && lead < 0xe0 ? 1
                             : lead >= 0xe0 && lead < 0xf0 ? 2
                             : lead >= 0xf0 && lead < 0xf5 ? 3
                                                           : 4;
    if (more == 4 || i + more >= s.size()) return false;
    for (std::size_t k = 1; k <= more; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return false;
    i += more + 1;
  }
  return true;
}

std::vector<std::string> given(const CLI::App& command, const std::string& name) {
  const CLI::Option* option = command.get_option_no_throw(name);
  if (option == nullptr || option->count() == 0) return {};
  return option->results();
}

std::string one(const CLI::App& command, const std::string& name, const std::string& fallback) {
  const auto values = given(command, name);
  return values.empty() ? fallback : values.back();
}

void check_name(const File& f) {
  if (!valid_utf8(f.path)) throw InputError(f.option + ": the file name '" + f.path + "' is not valid UTF-8");
  if (f.path.size() + kLongestSuffix >= PATH_MAX)
    throw InputError(f.option + ": the path '" + f.path.substr(0, 40) + "...' is too long");
}

void check_input(const File& f) {
  if (f.path == "-") return;  // standard input
  check_name(f);
  std::error_code error;
  const fs::file_status status = fs::status(f.path, error);
  if (!fs::exists(status)) throw InputError(f.option + ": " + f.path + " does not exist");
  if (fs::is_directory(status)) throw InputError(f.option + ": " + f.path + " is a directory, not a file");
  if (::access(f.path.c_str(), R_OK) != 0) throw InputError(f.option + ": " + f.path + " is not readable");
}

void check_output(const File& f) {
  check_name(f);
  const std::string name = fs::path(f.path).filename().string();
  const long most =
      ::pathconf(fs::path(f.path).parent_path().empty() ? "." : fs::path(f.path).parent_path().c_str(), _PC_NAME_MAX);
  const std::size_t limit = most > 0 ? static_cast<std::size_t>(most) : 255;
  if (name.size() + kLongestSuffix > limit)
    throw InputError(f.option + ": the file name " + name.substr(0, 40) + "... is longer than the " +
                     std::to_string(limit - kLongestSuffix) + " bytes an output name may have here");
  std::error_code error;
  if (fs::is_directory(f.path, error))
    throw InputError(f.option + ": " + f.path + " is a directory, not a file it could write");
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
  const fs::path x = fs::weakly_canonical(a, error);
  const fs::path y = fs::weakly_canonical(b, error);
  return !error && x == y;
}

std::vector<File> with_extensions(const std::string& prefix, const std::string& option,
                                  std::initializer_list<const char*> extensions) {
  std::vector<File> files;
  for (const char* extension : extensions) files.push_back({prefix + extension, option});
  return files;
}

/// The chosen command's inputs and outputs, as its own code names them.
void files_of(const CLI::App& command, std::vector<File>& inputs, std::vector<File>& outputs) {
  const std::string name = command.get_name();
  for (const std::string& path : given(command, "--params")) inputs.push_back({path, "--params"});
  auto add_outputs = [&](const std::vector<File>& files) { outputs.insert(outputs.end(), files.begin(), files.end()); };
  if (name == "theory") {
    for (const std::string& path : given(command, "--omega-file")) inputs.push_back({path, "--omega-file"});
    const std::string out = one(command, "--out", "");
    if (!out.empty()) add_outputs(with_extensions(out, "--out", {".tsv"}));
  } else if (name == "run") {
    const std::string resume = one(command, "--resume", "");
    if (!resume.empty()) inputs.push_back({resume + ".state", "--resume"});
    const std::string out = one(command, "--out", resume.empty() ? "spectrum" : resume);
    add_outputs(with_extensions(out, "--out", {".tsv", ".json", ".png"}));
    // A resumed run saves its progress over the state it continues: that is its purpose.
    const std::string save = one(command, "--save-state", "");
    for (const File& state : {File{out + ".state", "--out"}, File{save, "--save-state"}})
      if (!state.path.empty() && (resume.empty() || !same_file(state.path, resume + ".state")))
        outputs.push_back(state);
  } else if (name == "merge") {
    for (const std::string& path : given(command, "parts")) inputs.push_back({path, "merge"});
    add_outputs(with_extensions(one(command, "--out", "spectrum"), "--out", {".tsv", ".json", ".png"}));
  } else if (name == "sweep") {
    const std::string out = one(command, "--out", "spectrum");
    const std::string sweep = one(command, "values", "");
    const auto equals = sweep.find('=');
    if (equals != std::string::npos) {
      std::stringstream list(sweep.substr(equals + 1));
      for (std::string value; std::getline(list, value, ',');)
        add_outputs(
            with_extensions(out + "_" + sweep.substr(0, equals) + "=" + value, "--out", {".tsv", ".json", ".state"}));
    }
    outputs.push_back({out + ".png", "--out"});
  } else if (name == "plot") {
    for (const std::string& path : given(command, "tables")) inputs.push_back({path, "plot"});
    outputs.push_back({one(command, "--out", ""), "--out"});
  } else if (name == "analyze") {
    for (const std::string& path : given(command, "file")) inputs.push_back({path, "analyze"});
    add_outputs(with_extensions(one(command, "--out", "analysis"), "--out", {".tsv", ".json", ".png"}));
  } else if (name == "synth") {
    add_outputs(with_extensions(one(command, "--out", "record"), "--out", {".csv"}));
  } else if (name == "paper") {
    const std::string directory = one(command, "--out-dir", ".");
    check_name({directory, "--out-dir"});
  }
}

}  // namespace

void require_whole_numbers(CLI::App& app) {
  const CLI::Validator whole(
      [](std::string& value) -> std::string {
        if (value.empty() || value.size() > 19 || value.find_first_not_of("0123456789") != std::string::npos)
          return "expected a whole number 0 or more, got '" + value + "'";
        return "";
      },
      "WHOLE");
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
    for (const char* name : {"--realizations", "--seed", "--threads", "--points"})
      if (CLI::Option* option = command->get_option_no_throw(name)) option->check(whole);
}

void check_files(const CLI::App& app) {
  for (const CLI::App* command : app.get_subcommands()) {
    std::vector<File> inputs, outputs;
    files_of(*command, inputs, outputs);
    for (const File& f : inputs) check_input(f);
    for (const File& f : outputs) check_output(f);
    for (const File& out : outputs)
      for (const File& in : inputs)
        if (same_file(out.path, in.path))
          throw InputError(out.option + ": the output " + out.path + " would replace the input " + in.path + " (" +
                           in.option + "); choose another output name");
  }
}

}  // namespace slidespec::cli
