#include "slidespec/parameters.hpp"

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/suggest.hpp"

namespace slidespec {

const char* to_string(ChainEnds chain) { return chain == ChainEnds::open ? "open" : "ring"; }
const char* to_string(Renewal renewal) { return renewal == Renewal::poisson ? "poisson" : "periodic"; }

Level Parameters::level(int l) const {
  if (l == 1) return {N, m, k0, k1, eta0, a, alpha, chain};
  return sublevels.at(static_cast<std::size_t>(l - 2));
}

bool Parameters::touches(int l) const {
  if (touching.empty()) return l == levels;
  return std::find(touching.begin(), touching.end(), l) != touching.end();
}

long long Parameters::blocks(int l) const {
  long long count = 1;
  for (int k = 1; k <= l; ++k) count *= level(k).N;
  return count;
}

long long Parameters::touching_blocks() const {
  long long count = 0;
  for (int l = 1; l <= levels; ++l)
    if (touches(l)) count += blocks(l);
  return count;
}

double Parameters::random_force_variance(int l) const {
  const double f_kin = friction_per_miniblock();
  const double strength = level(l).alpha;
  return strength * strength * f_kin * f_kin / 12.0;
}

double Parameters::renewal_rate() const {
  double fastest = 0;
  for (int l = 1; l <= levels; ++l)
    if (touches(l)) fastest = std::max(fastest, renewal_rate(l));
  return fastest;
}

Landmarks landmarks(const Parameters& p) {
  const double drive_excess = p.F_drive - p.F_kin;
  Landmarks l{};
  l.renewal_rate = p.renewal_rate();
  l.omega_c = std::sqrt(p.N * p.k0 / p.M);
  // A force held exactly a (periodic) has half the zero-frequency power of one held an
  // exponential distance of mean a: int (1 - |s|/a)_+ ds = a against int exp(-|s|/a) ds = 2a.
  const double periodic_share = p.renewal == Renewal::periodic ? 0.5 : 1.0;
  l.diffusion =
      periodic_share * p.alpha * p.alpha * p.F_kin * p.F_kin * p.a * p.v / (12.0 * p.N * drive_excess * drive_excess);
  l.eq1_prefactor =
      p.alpha * p.alpha * p.F_kin * p.F_kin * p.v * p.v * p.v / (12.0 * M_PI * p.N * p.a * drive_excess * drive_excess);
  l.coupling_eps = p.alpha * p.F_kin / (drive_excess * std::sqrt(6.0 * p.N));
  l.forces_can_stall = p.alpha * p.F_kin >= 2.0 * drive_excess;
  if (p.levels > 1) {
    // The same landmarks summed over the touching levels (for one level the sums reduce
    // to the expressions above, which are kept so that flat outputs stay bit for bit).
    // Below every corner the tree moves as one body with drag (F_drive - F_kin)/v.
    double force_variance = 0, diffusion = 0, eq1 = 0, resistance = 0;
    for (int level = 1; level <= p.levels; ++level) {
      if (!p.touches(level)) continue;
      const double contacts = static_cast<double>(p.blocks(level));
      const double s2 = p.random_force_variance(level);
      force_variance += contacts * s2;
      diffusion += contacts * s2 * p.level(level).a;
      eq1 += contacts * s2 / p.level(level).a;
      resistance += contacts * p.level(level).alpha * p.friction_per_miniblock() / 2;
    }
    l.diffusion = diffusion * p.v / (drive_excess * drive_excess);
    l.diffusion *= periodic_share;
    l.eq1_prefactor = eq1 * p.v * p.v * p.v / (M_PI * drive_excess * drive_excess);
    l.coupling_eps = std::sqrt(2 * force_variance) / drive_excess;
    l.forces_can_stall = resistance >= drive_excess;
  }
  return l;
}

double expected_jump_energy(const Parameters& p, double distance) {
  double energy = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l))
      energy += 2 * p.random_force_variance(l) * static_cast<double>(p.blocks(l)) * distance / p.level(l).a;
  return energy;
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
      // Level 2: contacts ten times smaller, D = 0.1 mm (k0 ~ E D, m ~ rho D^3, eta0 ~
      // sqrt(k0/m), a ~ D); both levels touch. docs/hierarchy.md derives each value.
      {"hierarchical",
       "blocks on blocks: ten 0.1 mm microcontacts on each miniblock (docs/model.md §6)",
       {{"levels", "2"},
        {"N_2", "10"},
        {"m_2", "1e-8"},
        {"k0_2", "1e3"},
        {"k1_2", "10"},
        {"eta0_2", "8e4"},
        {"a_2", "1e-4"},
        {"alpha_2", "1"},
        {"touching", "1,2"}}},
  };
  return all;
}

const std::vector<std::string>& parameter_keys() {
  static const std::vector<std::string> keys = {
      "N",     "M",       "m",      "k0",       "k1",  "eta0", "eta1", "v",    "a",      "alpha", "F_drive", "F_kin",
      "chain", "renewal", "levels", "touching", "N_l", "m_l",  "k0_l", "k1_l", "eta0_l", "a_l",   "alpha_l", "chain_l"};
  return keys;
}

namespace {

// "_l", built by appending: GCC 12 warns falsely (-Wrestrict) on "_" + std::to_string(l).
std::string level_suffix(int l) {
  std::string suffix = "_";
  suffix += std::to_string(l);
  return suffix;
}

// Keys that every level has; KEY_l sets level l's.
const std::vector<std::string>& level_key_names() {
  static const std::vector<std::string> names = {"N", "m", "k0", "k1", "eta0", "a", "alpha", "chain"};
  return names;
}

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
  if (end != t.c_str() + t.size()) throw InputError("parameter " + key + ": '" + text + "' is not a number");
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

ChainEnds parse_chain(const std::string& key, const std::string& value) {
  const std::string t = trim(value);
  if (t == "open") return ChainEnds::open;
  if (t == "ring") return ChainEnds::ring;
  throw InputError("parameter " + key + ": '" + value + "' is not open or ring");
}

void set_level_key(Level& level, const std::string& name, const std::string& key, const std::string& value) {
  if (name == "N")
    level.N = parse_count(key, value);
  else if (name == "m")
    level.m = parse_real(key, value);
  else if (name == "k0")
    level.k0 = parse_real(key, value);
  else if (name == "k1")
    level.k1 = parse_real(key, value);
  else if (name == "eta0")
    level.eta0 = parse_real(key, value);
  else if (name == "a")
    level.a = parse_real(key, value);
  else if (name == "alpha")
    level.alpha = parse_real(key, value);
  else
    level.chain = parse_chain(key, value);
}

/// Splits "KEY_l" into a per-level key name and l >= 1; l = 0 when it is not one.
std::pair<std::string, int> split_level_key(const std::string& key) {
  const auto underscore = key.rfind('_');
  if (underscore == std::string::npos || underscore + 1 == key.size()) return {key, 0};
  const std::string name = key.substr(0, underscore), suffix = key.substr(underscore + 1);
  if (suffix.find_first_not_of("0123456789") != std::string::npos || suffix.size() > 3) return {key, 0};
  if (std::find(level_key_names().begin(), level_key_names().end(), name) == level_key_names().end()) return {key, 0};
  return {name, std::stoi(suffix)};
}

/// A deeper level's defaults: the level above scaled to a contact ten times smaller
/// (k0 ~ E D, k1 ~ k0, m ~ rho D^3, eta0 ~ sqrt(k0/m), a ~ D; docs/hierarchy.md).
Level scaled_below(const Level& above) {
  Level below = above;
  below.N = 10;
  below.m = above.m / 1000;
  below.k0 = above.k0 / 10;
  below.k1 = above.k1 / 10;
  below.eta0 = above.eta0 * 10;
  below.a = above.a / 10;
  return below;
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
  std::vector<std::string> known;
  for (const Case& c : cases()) known.push_back(c.name);
  throw InputError("unknown case '" + case_name + "'" + io::did_you_mean(case_name, known) + " (known: " + names + ")");
}

ParameterBuilder& ParameterBuilder::set(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("malformed override '" + assignment + "': expected KEY=VALUE");
  return set(trim(assignment.substr(0, eq)), assignment.substr(eq + 1));
}

ParameterBuilder& ParameterBuilder::set(const std::string& key, const std::string& value) {
  Parameters& p = params_;
  const auto [name, l] = split_level_key(key);
  if (l == 1) return set(name, value);
  if (l >= 2) {
    Level check;
    set_level_key(check, name, key, value);  // a malformed value fails here, naming the key
    if (level_keys_.size() < static_cast<std::size_t>(l - 1)) level_keys_.resize(static_cast<std::size_t>(l - 1));
    level_keys_[static_cast<std::size_t>(l - 2)].emplace_back(name, value);
    return *this;
  }
  if (key == "levels")
    p.levels = parse_count(key, value);
  else if (key == "touching") {
    p.touching.clear();
    std::stringstream list(value);
    for (std::string item; std::getline(list, item, ',');) p.touching.push_back(parse_count(key, item));
    std::sort(p.touching.begin(), p.touching.end());
    p.touching.erase(std::unique(p.touching.begin(), p.touching.end()), p.touching.end());
  } else if (key == "N")
    p.N = parse_count(key, value);
  else if (key == "M")
    p.M = parse_real(key, value);
  else if (key == "m")
    p.m = parse_real(key, value);
  else if (key == "k0")
    p.k0 = parse_real(key, value);
  else if (key == "k1")
    p.k1 = parse_real(key, value);
  else if (key == "eta0")
    p.eta0 = parse_real(key, value);
  else if (key == "eta1") {
    p.eta1 = parse_real(key, value);
    user_set_eta1_ = true;
  } else if (key == "v") {
    p.v = parse_real(key, value);
    user_set_v_ = true;
  } else if (key == "a")
    p.a = parse_real(key, value);
  else if (key == "alpha")
    p.alpha = parse_real(key, value);
  else if (key == "F_drive")
    p.F_drive = parse_real(key, value);
  else if (key == "F_kin")
    p.F_kin = parse_real(key, value);
  else if (key == "chain")
    p.chain = parse_chain(key, value);
  else if (key == "renewal") {
    const std::string t = trim(value);
    if (t == "poisson")
      p.renewal = Renewal::poisson;
    else if (t == "periodic")
      p.renewal = Renewal::periodic;
    else
      throw InputError("parameter renewal: '" + value + "' is not poisson or periodic");
  } else {
    std::string known;
    for (const auto& k : parameter_keys()) known += (known.empty() ? "" : " ") + k;
    throw InputError("unknown parameter '" + key + "'" + io::did_you_mean(key, parameter_keys()) + " (known: " + known +
                     ")");
  }
  return *this;
}

namespace {

// Inputs are kept within 1e-100..1e100 so that products and ratios of a few of them (the
// landmarks, the stepper's coefficients) stay far from overflow and underflow.
constexpr double kSmallest = 1e-100, kLargest = 1e100;

std::string format_real(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

void check_magnitude(const std::string& key, double value) {
  const double size = std::fabs(value);
  if (size != 0 && !(size >= kSmallest && size <= kLargest))
    throw InputError("parameter " + key + ": " + format_real(value) +
                     " is outside 1e-100..1e100 (its derived "
                     "quantities would not be representable)");
}

/// Every derived rate and landmark a run or the theory uses must be a normal number.
void check_derived(const Parameters& p) {
  const Landmarks l = landmarks(p);
  auto normal = [](const char* what, double value, bool zero_allowed) {
    if (!std::isfinite(value) || (!(zero_allowed && value == 0) && !std::isnormal(value)))
      throw InputError(std::string("parameters: derived ") + what + " = " + format_real(value) +
                       " is not a representable number; bring the parameters it depends on closer to 1");
  };
  normal("omega_c = sqrt(N k0 / M)", l.omega_c, false);
  normal("v / a (renewal rate)", l.renewal_rate, false);
  normal("D (diffusion)", l.diffusion, true);
  normal("Eq. (1) prefactor", l.eq1_prefactor, true);
  for (int level = 1; level <= p.levels; ++level) {
    const Level b = p.level(level);
    normal("k0 / m (miniblock resonance squared)", b.k0 / b.m, false);
    normal("k1 / m", b.k1 / b.m, true);
    normal("random force variance", p.random_force_variance(level), true);
  }
}

}  // namespace

Parameters ParameterBuilder::build() const {
  Parameters p = params_;
  auto positive = [](const std::string& key, double value) {
    if (!(value > 0)) throw InputError("parameter " + key + ": must be > 0 (got " + std::to_string(value) + ")");
    check_magnitude(key, value);
  };
  auto non_negative = [](const std::string& key, double value) {
    if (!(value >= 0)) throw InputError("parameter " + key + ": must be >= 0 (got " + std::to_string(value) + ")");
    check_magnitude(key, value);
  };
  if (user_set_v_ && user_set_eta1_) throw InputError("parameters v and eta1: give one of them, the other is derived");
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
  build_levels(p);
  for (int l = 2; l <= p.levels; ++l) {
    const Level level = p.level(l);
    const std::string suffix = level_suffix(l);
    if (level.chain == ChainEnds::ring && level.N < 3)
      throw InputError("parameter chain" + suffix + ": a ring needs N" + suffix + " >= 3 (got " +
                       std::to_string(level.N) + ")");
    positive("m" + suffix, level.m);
    positive("k0" + suffix, level.k0);
    non_negative("k1" + suffix, level.k1);
    non_negative("eta0" + suffix, level.eta0);
    positive("a" + suffix, level.a);
    non_negative("alpha" + suffix, level.alpha);
  }
  // Substrate damping acts on the touching blocks, at one rate eta1 for all of them.
  double touching_mass = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) touching_mass += static_cast<double>(p.blocks(l)) * p.level(l).m;
  check_magnitude("F_drive", p.F_drive);
  if (!(p.F_drive > p.F_kin))
    throw InputError("parameters F_drive, F_kin: F_drive must exceed F_kin for steady sliding (got " +
                     std::to_string(p.F_drive) + " <= " + std::to_string(p.F_kin) + ")");
  if (user_set_eta1_) {
    positive("eta1", p.eta1);
    p.v = (p.F_drive - p.F_kin) / (touching_mass * p.eta1);
  } else {
    positive("v", p.v);
    p.eta1 = (p.F_drive - p.F_kin) / (touching_mass * p.v);
  }
  if (!std::isfinite(p.v) || !std::isfinite(p.eta1) || !(p.v > 0) || !(p.eta1 > 0))
    throw InputError("parameters v, eta1: the derived value is not a finite positive number");
  check_magnitude(user_set_eta1_ ? "v (derived from eta1)" : "eta1 (derived from v)", user_set_eta1_ ? p.v : p.eta1);
  check_magnitude("F_drive - F_kin", p.F_drive - p.F_kin);
  check_derived(p);
  return p;
}

void ParameterBuilder::build_levels(Parameters& p) const {
  // At most 10^7 blocks in all: the exact theory solves over every one of them.
  if (p.levels < 1 || p.levels > 8)
    throw InputError("parameter levels: must be between 1 and 8 (got " + std::to_string(p.levels) + ")");
  if (level_keys_.size() > static_cast<std::size_t>(p.levels - 1)) {
    const std::size_t deepest = level_keys_.size() + 1;
    throw InputError("parameter " + level_keys_.back().front().first + level_suffix(static_cast<int>(deepest)) +
                     ": level " + std::to_string(deepest) + " is below the lowest (levels=" + std::to_string(p.levels) +
                     ")");
  }
  p.sublevels.clear();
  for (int l = 2; l <= p.levels; ++l) {
    Level level = scaled_below(p.level(l - 1));
    if (static_cast<std::size_t>(l - 2) < level_keys_.size())
      for (const auto& [name, value] : level_keys_[static_cast<std::size_t>(l - 2)])
        set_level_key(level, name, name + level_suffix(l), value);
    p.sublevels.push_back(level);
  }
  for (int l : p.touching)
    if (l < 1 || l > p.levels)
      throw InputError("parameter touching: level " + std::to_string(l) + " is not in 1.." + std::to_string(p.levels));
  for (int l = 2; l <= p.levels; ++l)
    if (p.level(l).N < 1)
      throw InputError("parameter N_" + std::to_string(l) + ": must be at least 1 (got " +
                       std::to_string(p.level(l).N) + ")");
  long long total = 0;
  for (int l = 1; l <= p.levels; ++l) {
    total += p.blocks(l);
    if (total > 10000000) throw InputError("parameter levels: the tree would have more than 10^7 blocks");
  }
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
  if (!doc.is_object()) throw InputError("parameter file '" + path + "': expected a JSON object of KEY: value");
  // A run's output JSON: its "parameters" block, where eta1 is listed beside the v it
  // was derived from (or v beside eta1: they agree, and v is kept).
  if (doc.contains("parameters") && doc["parameters"].is_object()) doc = doc["parameters"];
  if (doc.contains("v") && doc.contains("eta1")) doc.erase("eta1");
  std::vector<std::string> assignments;
  for (const auto& [key, value] : doc.items()) {
    if (value.is_string())
      assignments.push_back(key + "=" + value.get<std::string>());
    else if (value.is_number_integer())
      assignments.push_back(key + "=" + std::to_string(value.get<long long>()));
    else if (value.is_number()) {
      char text[32];
      assignments.push_back(key + "=" +
                            std::string(text, std::to_chars(text, text + sizeof text, value.get<double>()).ptr));
    } else {
      throw InputError("parameter file '" + path + "': value of " + key + " is neither a number nor a string");
    }
  }
  return assignments;
}

std::vector<std::pair<std::string, std::string>> describe(const Parameters& p) {
  auto num = [](double x) {  // shortest text that reads back as x
    char text[32];
    return std::string(text, std::to_chars(text, text + sizeof text, x).ptr);
  };
  std::vector<std::pair<std::string, std::string>> described = {{"N", std::to_string(p.N)},
                                                                {"M", num(p.M)},
                                                                {"m", num(p.m)},
                                                                {"k0", num(p.k0)},
                                                                {"k1", num(p.k1)},
                                                                {"eta0", num(p.eta0)},
                                                                {"eta1", num(p.eta1)},
                                                                {"v", num(p.v)},
                                                                {"a", num(p.a)},
                                                                {"alpha", num(p.alpha)},
                                                                {"F_drive", num(p.F_drive)},
                                                                {"F_kin", num(p.F_kin)},
                                                                {"chain", to_string(p.chain)},
                                                                {"renewal", to_string(p.renewal)}};
  if (p.levels > 1) {
    described.emplace_back("levels", std::to_string(p.levels));
    std::string touching;
    for (int l = 1; l <= p.levels; ++l)
      if (p.touches(l)) {
        if (!touching.empty()) touching += ',';
        touching += std::to_string(l);
      }
    described.emplace_back("touching", touching);
    for (int l = 2; l <= p.levels; ++l) {
      const Level level = p.level(l);
      const std::string suffix = level_suffix(l);
      described.emplace_back("N" + suffix, std::to_string(level.N));
      described.emplace_back("m" + suffix, num(level.m));
      described.emplace_back("k0" + suffix, num(level.k0));
      described.emplace_back("k1" + suffix, num(level.k1));
      described.emplace_back("eta0" + suffix, num(level.eta0));
      described.emplace_back("a" + suffix, num(level.a));
      described.emplace_back("alpha" + suffix, num(level.alpha));
      described.emplace_back("chain" + suffix, to_string(level.chain));
    }
  }
  return described;
}

}  // namespace slidespec
