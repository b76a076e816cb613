#include "slidespec/parameters.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

namespace slidespec {

const char* to_string(ChainEnds chain) { return chain == ChainEnds::open ? "open" : "ring"; }
const char* to_string(Renewal renewal) {
  return renewal == Renewal::poisson ? "poisson" : "periodic";
}

double Parameters::random_force_variance() const {
  const double f_kin = friction_per_miniblock();
  return alpha * alpha * f_kin * f_kin / 12.0;
}

Landmarks landmarks(const Parameters& p) {
  const double drive_excess = p.F_drive - p.F_kin;
  Landmarks l{};
  l.renewal_rate = p.v / p.a;
  l.omega_c = std::sqrt(p.N * p.k0 / p.M);
  l.diffusion = p.alpha * p.alpha * p.F_kin * p.F_kin * p.a * p.v /
                (12.0 * p.N * drive_excess * drive_excess);
  l.eq1_prefactor = p.alpha * p.alpha * p.F_kin * p.F_kin * p.v * p.v * p.v /
                    (12.0 * M_PI * p.N * p.a * drive_excess * drive_excess);
  l.coupling_eps = p.alpha * p.F_kin / (drive_excess * std::sqrt(6.0 * p.N));
  l.forces_can_stall = p.alpha * p.F_kin >= 2.0 * drive_excess;
  return l;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {"reference", "the paper's reference case (Fig. 2 violet, Fig. 3 alpha=1)", {}},
      {"fast", "faster sliding (Fig. 2 green)", {{"v", "5e-3"}}},
      {"short-renewal", "shorter renewal distance (Fig. 2 red)", {{"a", "1e-4"}}},
      {"many-contacts", "more miniblocks (Fig. 2 yellow)", {{"N", "100"}}},
      {"weak-noise", "weak random forces (Fig. 3)", {{"alpha", "0.1"}}},
      {"medium-noise", "medium random forces (Fig. 3)", {{"alpha", "0.5"}}},
      {"concrete-fit", "fit to rubber on concrete (Fig. 6)", {{"alpha", "0.4"}}},
  };
  return all;
}

const std::vector<std::string>& parameter_keys() {
  static const std::vector<std::string> keys = {"N",     "M",     "m",     "k0",      "k1",
                                                "eta0",  "eta1",  "v",     "a",       "alpha",
                                                "F_drive", "F_kin", "chain", "renewal"};
  return keys;
}

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t");
  return s.substr(first, last - first + 1);
}

double parse_real(const std::string& key, const std::string& text) {
  const std::string t = trim(text);
  if (t.empty()) throw InputError("parameter " + key + ": missing value");
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size())
    throw InputError("parameter " + key + ": '" + text + "' is not a number");
  if (!std::isfinite(value) || errno == ERANGE)
    throw InputError("parameter " + key + ": '" + text + "' is not a finite number");
  return value;
}

int parse_count(const std::string& key, const std::string& text) {
  const double value = parse_real(key, text);
  if (value != std::floor(value) || std::fabs(value) > 1e9)
    throw InputError("parameter " + key + ": '" + text + "' is not a whole number");
  return static_cast<int>(value);
}

}  // namespace

ParameterBuilder::ParameterBuilder(const std::string& case_name) {
  for (const Case& c : cases()) {
    if (c.name != case_name) continue;
    for (const auto& [key, value] : c.changes) set(key, value);
    user_set_v_ = false;
    user_set_eta1_ = false;
    return;
  }
  std::string names;
  for (const Case& c : cases()) names += (names.empty() ? "" : ", ") + c.name;
  throw InputError("unknown case '" + case_name + "' (known: " + names + ")");
}

ParameterBuilder& ParameterBuilder::set(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("malformed override '" + assignment + "': expected KEY=VALUE");
  return set(trim(assignment.substr(0, eq)), assignment.substr(eq + 1));
}

ParameterBuilder& ParameterBuilder::set(const std::string& key, const std::string& value) {
  Parameters& p = params_;
  if (key == "N") p.N = parse_count(key, value);
  else if (key == "M") p.M = parse_real(key, value);
  else if (key == "m") p.m = parse_real(key, value);
  else if (key == "k0") p.k0 = parse_real(key, value);
  else if (key == "k1") p.k1 = parse_real(key, value);
  else if (key == "eta0") p.eta0 = parse_real(key, value);
  else if (key == "eta1") { p.eta1 = parse_real(key, value); user_set_eta1_ = true; }
  else if (key == "v") { p.v = parse_real(key, value); user_set_v_ = true; }
  else if (key == "a") p.a = parse_real(key, value);
  else if (key == "alpha") p.alpha = parse_real(key, value);
  else if (key == "F_drive") p.F_drive = parse_real(key, value);
  else if (key == "F_kin") p.F_kin = parse_real(key, value);
  else if (key == "chain") {
    const std::string t = trim(value);
    if (t == "open") p.chain = ChainEnds::open;
    else if (t == "ring") p.chain = ChainEnds::ring;
    else throw InputError("parameter chain: '" + value + "' is not open or ring");
  } else if (key == "renewal") {
    const std::string t = trim(value);
    if (t == "poisson") p.renewal = Renewal::poisson;
    else if (t == "periodic") p.renewal = Renewal::periodic;
    else throw InputError("parameter renewal: '" + value + "' is not poisson or periodic");
  } else {
    std::string known;
    for (const auto& k : parameter_keys()) known += (known.empty() ? "" : " ") + k;
    throw InputError("unknown parameter '" + key + "' (known: " + known + ")");
  }
  return *this;
}

Parameters ParameterBuilder::build() const {
  Parameters p = params_;
  auto positive = [](const char* key, double value) {
    if (!(value > 0))
      throw InputError(std::string("parameter ") + key + ": must be > 0 (got " +
                       std::to_string(value) + ")");
  };
  auto non_negative = [](const char* key, double value) {
    if (!(value >= 0))
      throw InputError(std::string("parameter ") + key + ": must be >= 0 (got " +
                       std::to_string(value) + ")");
  };
  if (user_set_v_ && user_set_eta1_)
    throw InputError("parameters v and eta1: give one of them, the other is derived");
  if (p.N < 1) throw InputError("parameter N: must be at least 1 (got " + std::to_string(p.N) + ")");
  if (p.chain == ChainEnds::ring && p.N < 3)
    throw InputError("parameter chain: a ring needs N >= 3 (got N = " + std::to_string(p.N) + ")");
  positive("M", p.M);
  positive("m", p.m);
  positive("k0", p.k0);
  non_negative("k1", p.k1);
  non_negative("eta0", p.eta0);
  positive("a", p.a);
  non_negative("alpha", p.alpha);
  non_negative("F_kin", p.F_kin);
  if (!(p.F_drive > p.F_kin))
    throw InputError("parameters F_drive, F_kin: F_drive must exceed F_kin for steady sliding (got " +
                     std::to_string(p.F_drive) + " <= " + std::to_string(p.F_kin) + ")");
  if (user_set_eta1_) {
    positive("eta1", p.eta1);
    p.v = (p.F_drive - p.F_kin) / (p.N * p.m * p.eta1);
  } else {
    positive("v", p.v);
    p.eta1 = (p.F_drive - p.F_kin) / (p.N * p.m * p.v);
  }
  if (!std::isfinite(p.v) || !std::isfinite(p.eta1) || !(p.v > 0) || !(p.eta1 > 0))
    throw InputError("parameters v, eta1: the derived value is not a finite positive number");
  return p;
}

std::vector<std::string> read_parameter_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("parameter file '" + path + "': cannot be read");
  nlohmann::json doc;
  try {
    in >> doc;
  } catch (const nlohmann::json::exception& e) {
    throw InputError("parameter file '" + path + "': not valid JSON (" + e.what() + ")");
  }
  if (!doc.is_object())
    throw InputError("parameter file '" + path + "': expected a JSON object of KEY: value");
  std::vector<std::string> assignments;
  for (const auto& [key, value] : doc.items()) {
    if (value.is_string()) assignments.push_back(key + "=" + value.get<std::string>());
    else if (value.is_number()) {
      std::ostringstream text;
      text.precision(17);
      text << value.get<double>();
      assignments.push_back(key + "=" + text.str());
    } else {
      throw InputError("parameter file '" + path + "': value of " + key +
                       " is neither a number nor a string");
    }
  }
  return assignments;
}

std::vector<std::pair<std::string, std::string>> describe(const Parameters& p) {
  auto num = [](double x) {
    std::ostringstream s;
    s.precision(std::numeric_limits<double>::max_digits10);
    s << x;
    return s.str();
  };
  return {{"N", std::to_string(p.N)}, {"M", num(p.M)},
          {"m", num(p.m)},           {"k0", num(p.k0)},
          {"k1", num(p.k1)},         {"eta0", num(p.eta0)},
          {"eta1", num(p.eta1)},     {"v", num(p.v)},
          {"a", num(p.a)},           {"alpha", num(p.alpha)},
          {"F_drive", num(p.F_drive)}, {"F_kin", num(p.F_kin)},
          {"chain", to_string(p.chain)}, {"renewal", to_string(p.renewal)}};
}

}  // namespace slidespec
