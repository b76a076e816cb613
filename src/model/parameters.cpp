#include "slidespec/parameters.hpp"

#include <algorithm>
#include <functional>
#include <charconv>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <type_traits>

#include "model/stall.hpp"
#include "util/numbers.hpp"
#include "util/suggest.hpp"

namespace slidespec {

namespace {

// "open, ring" (the enum's words as the preprocessor writes them) -> {"open", "ring"}.
std::vector<std::string> split_words(const std::string& list) {
  std::vector<std::string> split;
  std::stringstream words(list);
  for (std::string word; std::getline(words, word, ',');) split.push_back(word.substr(word.find_first_not_of(' ')));
  return split;
}

}  // namespace

#define SLIDESPEC_WORDS(Type, ...)                                          \
  const std::vector<std::string>& words(Type) {                             \
    static const std::vector<std::string> list = split_words(#__VA_ARGS__); \
    return list;                                                            \
  }                                                                         \
  const char* to_string(Type value) { return words(value)[static_cast<std::size_t>(value)].c_str(); }
#include "slidespec/parameters.def"

#define SLIDESPEC_PARAMETER_IN_LEVEL_level(statement) statement
#define SLIDESPEC_PARAMETER_IN_LEVEL_model(statement)

Level Parameters::level(int l) const {
  if (l != 1) return sublevels.at(static_cast<std::size_t>(l - 2));
  Level first;
#define SLIDESPEC_PARAMETER(key, type, reference, range, unit, symbol, scope, shown, doc) \
  SLIDESPEC_PARAMETER_IN_LEVEL_##scope(first.key = key;)
#include "slidespec/parameters.def"
  return first;
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

double stall_resistance(const Parameters& p) {
  // One level: alpha F_kin / 2, which stall decisions compare with F_drive - F_kin exactly
  // as alpha F_kin against twice it (halving is exact).
  if (p.levels == 1) return p.alpha * p.F_kin / 2;
  double resistance = 0;
  for (int level = 1; level <= p.levels; ++level)
    if (p.touches(level))
      resistance += static_cast<double>(p.blocks(level)) * p.level(level).alpha * p.friction_per_miniblock() / 2;
  return resistance;
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
  l.forces_can_stall = stall_resistance(p) >= drive_excess;
  if (p.levels > 1) {
    // The same landmarks summed over the touching levels (for one level the sums reduce
    // to the expressions above, which are kept so that flat outputs stay bit for bit).
    // Below every corner the tree moves as one body with drag (F_drive - F_kin)/v.
    double force_variance = 0, diffusion = 0, eq1 = 0;
    for (int level = 1; level <= p.levels; ++level) {
      if (!p.touches(level)) continue;
      const double contacts = static_cast<double>(p.blocks(level));
      const double s2 = p.random_force_variance(level);
      force_variance += contacts * s2;
      diffusion += contacts * s2 * p.level(level).a;
      eq1 += contacts * s2 / p.level(level).a;
    }
    l.diffusion = diffusion * p.v / (drive_excess * drive_excess);
    l.diffusion *= periodic_share;
    l.eq1_prefactor = eq1 * p.v * p.v * p.v / (M_PI * drive_excess * drive_excess);
    l.coupling_eps = std::sqrt(2 * force_variance) / drive_excess;
  }
  l.omega_resonance = l.omega_c;
  l.spring_offset = 0;
  if (p.drive == Drive::spring) {
    // The load point holds the block near its steady place: no diffusion, and below omega_s
    // the spring, not the drag (F_drive - F_kin) / v of the contacts, sets the response.
    l.diffusion = 0;
    l.omega_s = p.k_drive * p.v / drive_excess;
    l.spring_offset = p.F_drive / p.k_drive;
    l.omega_resonance = std::sqrt((p.blocks(1) * p.level(1).k0 + p.k_drive) / p.M);
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

namespace {

// "_l", built by appending: GCC 12 warns falsely (-Wrestrict) on "_" + std::to_string(l).
std::string level_suffix(int l) {
  std::string suffix = "_";
  suffix += std::to_string(l);
  return suffix;
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
  std::string problem;
  const std::optional<double> value = util::parse_decimal(t, problem);
  if (!value && problem.find("smallest normal") != std::string::npos)
    throw InputError("parameter " + key + ": " + problem +
                     "; parameters lie within 1e-100..1e100, or are 0 where 0 is allowed");
  if (!value) throw InputError("parameter " + key + ": " + problem);
  return *value;
}

int parse_count(const std::string& key, const std::string& text) {
  const double value = parse_real(key, text);
  if (value != std::floor(value)) throw InputError("parameter " + key + ": '" + text + "' is not a whole number");
  // Counts beyond an int are far past every count's own range, which names the limit.
  if (std::fabs(value) > 1e9)
    throw InputError("parameter " + key + ": '" + text + "' is far beyond any count the model holds");
  return static_cast<int>(value);
}

// "a or b", "a, b or c".
std::string either(const std::vector<std::string>& words) {
  std::string text;
  for (std::size_t k = 0; k < words.size(); ++k) {
    text += k == 0 ? "" : k + 1 == words.size() ? " or " : ", ";
    text += words[k];
  }
  return text;
}

// One parse, text and range check per type of member (parameters.def's `type` column).
void parse(const std::string& key, const std::string& text, double& value) { value = parse_real(key, text); }
void parse(const std::string& key, const std::string& text, int& value) { value = parse_count(key, text); }
void parse(const std::string& key, const std::string& text, LevelList& levels) {
  levels.clear();
  if (trim(text).empty() || trim(text).back() == ',')
    throw InputError("parameter " + key + ": '" + text + "' is not a list of levels (e.g. 1,2)");
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) levels.push_back(parse_count(key, item));
  std::sort(levels.begin(), levels.end());
  if (std::adjacent_find(levels.begin(), levels.end()) != levels.end())
    throw InputError("parameter " + key + ": '" + text + "' names a level twice");
}
template <class Word>  // the word types of parameters.def
void parse(const std::string& key, const std::string& text, Word& value) {
  const std::vector<std::string>& list = words(Word{});
  const auto found = std::find(list.begin(), list.end(), trim(text));
  if (found == list.end()) throw InputError("parameter " + key + ": '" + text + "' is not " + either(list));
  value = static_cast<Word>(found - list.begin());
}

std::string text(double value) { return util::format_number(value); }
std::string text(int value) { return std::to_string(value); }
std::string text(const LevelList& levels) {
  std::string list;
  for (int l : levels) {
    if (!list.empty()) list += ',';
    list += std::to_string(l);
  }
  return list;
}
template <class Word>  // the word types of parameters.def
std::string text(Word value) {
  return to_string(value);
}

std::string bound(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string allowed(const Range& range, bool count) {
  if (std::isfinite(range.high)) return "between " + bound(range.low) + " and " + bound(range.high);
  if (!std::isfinite(range.low)) return "";
  if (count && range.low_included) return "at least " + bound(range.low);
  return (range.low_included ? ">= " : "> ") + bound(range.low);
}

bool inside(const Range& range, double value) {
  return (range.low_included ? value >= range.low : value > range.low) && value <= range.high;
}

// Inputs are kept within 1e-100..1e100 so that products and ratios of a few of them (the
// landmarks, the stepper's coefficients) stay far from overflow and underflow.
constexpr double kSmallest = 1e-100, kLargest = 1e100;

void check_magnitude(const std::string& key, double value) {
  const double size = std::fabs(value);
  if (size != 0 && !(size >= kSmallest && size <= kLargest))
    throw InputError("parameter " + key + ": " + bound(value) +
                     " is outside 1e-100..1e100 (its derived "
                     "quantities would not be representable)");
}

void check(const ParameterInfo& row, const std::string& key, double value) {
  if (!inside(row.range, value))
    throw InputError("parameter " + key + ": must be " + row.allowed + " (got " + bound(value) + ")");
  check_magnitude(key, value);
}
void check(const ParameterInfo& row, const std::string& key, int value) {
  if (!inside(row.range, value))
    throw InputError("parameter " + key + ": must be " + row.allowed + " (got " + std::to_string(value) + ")");
}
template <class Value>
void check(const ParameterInfo&, const std::string&, const Value&) {}  // words and level lists: parsed is valid

template <class T>
const char* kind() {
  if constexpr (std::is_same_v<T, int>) return "count";
  if constexpr (std::is_same_v<T, double>) return "real";
  if constexpr (std::is_same_v<T, LevelList>) return "levels";
  return "word";
}

template <class T>
std::vector<std::string> words_of() {
  if constexpr (std::is_enum_v<T>)
    return words(T{});
  else
    return {};
}

// parameters.def's `shown` column.
bool always(const Parameters&) { return true; }
bool in_trees(const Parameters& p) { return p.levels > 1; }
bool with_spring(const Parameters& p) { return p.drive == Drive::spring; }

template <class T>
ParameterInfo row(const char* key, Range range, const char* unit, const char* symbol, bool per_level, const char* doc,
                  bool (*shown)(const Parameters&)) {
  ParameterInfo info{key, kind<T>(), range, "", unit, symbol, per_level, doc, words_of<T>(), "", shown};
  info.allowed = info.words.empty() ? allowed(range, info.kind == "count") : either(info.words);
  return info;
}

// The rows without their reference values (parameter_table() adds those, by building the
// reference case, which needs the rows).
const std::vector<ParameterInfo>& rows() {
  static const std::vector<ParameterInfo> table = {
#define SLIDESPEC_PARAMETER(key, type, reference, range, unit, symbol, scope, shown, doc) \
  row<type>(#key, ranges::range, unit, symbol, #scope == std::string("level"), doc, shown),
#include "slidespec/parameters.def"
  };
  return table;
}

const ParameterInfo& table_row(const std::string& key) {
  for (const ParameterInfo& info : rows())
    if (info.key == key) return info;
  throw std::logic_error("parameters.def has no row " + key);
}

/// visit(row, member) for every row of parameters.def, in its order.
template <class Model, class Visit>
void for_each_parameter(Model& p, Visit&& visit) {
#define SLIDESPEC_PARAMETER(key, type, reference, range, unit, symbol, scope, shown, doc) visit(table_row(#key), p.key);
#include "slidespec/parameters.def"
}

/// visit(row, member) for every per-level row, on one level.
template <class LevelT, class Visit>
void for_each_level_parameter(LevelT& level, Visit&& visit) {
#define SLIDESPEC_PARAMETER(key, type, reference, range, unit, symbol, scope, shown, doc) \
  SLIDESPEC_PARAMETER_IN_LEVEL_##scope(visit(table_row(#key), level.key);)
#include "slidespec/parameters.def"
}

void set_level_key(Level& level, const std::string& name, const std::string& key, const std::string& value) {
  for_each_level_parameter(level, [&](const ParameterInfo& info, auto& member) {
    if (info.key == name) parse(key, value, member);
  });
}

/// Splits "KEY_l" into a per-level key name and l >= 1; l = 0 when it is not one.
std::pair<std::string, int> split_level_key(const std::string& key) {
  const auto underscore = key.rfind('_');
  if (underscore == std::string::npos || underscore + 1 == key.size()) return {key, 0};
  const std::string name = key.substr(0, underscore), suffix = key.substr(underscore + 1);
  if (suffix.find_first_not_of("0123456789") != std::string::npos || suffix.size() > 3) return {key, 0};
  const auto& table = rows();
  const bool per_level = std::any_of(table.begin(), table.end(),
                                     [&](const ParameterInfo& info) { return info.per_level && info.key == name; });
  if (!per_level) return {key, 0};
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
    given_.clear();
    return;
  }
  std::string names;
  for (const Case& c : cases()) names += (names.empty() ? "" : ", ") + c.name;
  std::vector<std::string> known;
  for (const Case& c : cases()) known.push_back(c.name);
  throw InputError("unknown case '" + case_name + "'" + util::did_you_mean(case_name, known) + " (known: " + names +
                   ")");
}

Parameters build_case(const std::string& case_name, const std::vector<std::string>& assignments) {
  return build_case(case_name, "", assignments);
}

Parameters build_case(const std::string& case_name, const std::string& parameter_file,
                      const std::vector<std::string>& assignments) {
  ParameterBuilder builder(case_name);
  if (!parameter_file.empty())
    for (const std::string& assignment : read_parameter_file(parameter_file)) builder.set(assignment);
  for (const std::string& assignment : assignments) builder.set(assignment);
  return builder.build();
}

ParameterBuilder& ParameterBuilder::set(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("malformed override '" + assignment + "': expected KEY=VALUE");
  return set(trim(assignment.substr(0, eq)), assignment.substr(eq + 1));
}

ParameterBuilder& ParameterBuilder::set(const std::string& key, const std::string& value) {
  const auto [name, l] = split_level_key(key);
  if (l == 1) return set(name, value);
  if (l >= 2) {
    Level check;
    set_level_key(check, name, key, value);  // a malformed value fails here, naming the key
    if (level_keys_.size() < static_cast<std::size_t>(l - 1)) level_keys_.resize(static_cast<std::size_t>(l - 1));
    level_keys_[static_cast<std::size_t>(l - 2)].emplace_back(name, value);
    given_.push_back(key);
    return *this;
  }
  bool known = false;
  for_each_parameter(params_, [&](const ParameterInfo& info, auto& member) {
    if (info.key != key) return;
    parse(key, value, member);
    known = true;
  });
  if (!known) {
    std::string keys;
    for (const auto& k : parameter_keys()) keys += (keys.empty() ? "" : " ") + k;
    throw InputError("unknown parameter '" + key + "'" + util::did_you_mean(key, parameter_keys()) +
                     " (known: " + keys + ")");
  }
  given_.push_back(key);
  return *this;
}

bool ParameterBuilder::given(const std::string& key) const {
  return std::find(given_.begin(), given_.end(), key) != given_.end();
}

namespace {

// The exact theory solves the structure's modes in doubles and loses digits with the
// contrast of two terms whose difference it needs. A chain spring 1e12 times k0 left C_x
// wrong by 4e-6 at the resonance, 1e15 times failed its lumping, 1e18 times gave a C_x 1e5
// off at low omega; a miniblock's damping eta0 1e9 times the substrate's eta1, 3e-6 at
// 0.01 rad/s, 2.4e14 times, 14% everywhere. Up to these contrasts C_x holds to about 1e-8,
// and beyond them the chain is rigid, the miniblocks stuck to their parent, anyway.
constexpr double kStiffestChainContrast = 1e9;
constexpr double kStickiestDampingContrast = 1e6;

void check_contrast(const std::string& key, double value, const std::string& other, double other_value, double most,
                    const std::string& unit) {
  if (!(value > most * other_value)) return;
  throw InputError("parameter " + key + ": " + bound(value) + " " + unit + " is " + bound(value / other_value) +
                   " times " + other + ", beyond the " + bound(most) +
                   " the exact theory resolves (and far past where raising it changes C_x): give " + key + " at most " +
                   bound(most * other_value) + " " + unit + ", or " + other + " at least " + bound(value / most) + " " +
                   unit);
}

/// eta0 of a touching level against the substrate's eta1 = (F_drive - F_kin) / (touching
/// mass x v): where eta1 is derived, the drive and the speed are the likelier cause.
void check_damping_contrast(const Parameters& p, bool eta1_derived,
                            const std::function<bool(const std::string&)>& given) {
  for (int level = 1; level <= p.levels; ++level) {
    const double eta0 = p.level(level).eta0;
    if (!p.touches(level) || !(eta0 > kStickiestDampingContrast * p.eta1)) continue;
    const std::string key = "eta0" + (level == 1 ? std::string() : level_suffix(level));
    const double factor = eta0 / (kStickiestDampingContrast * p.eta1);  // > 1
    const std::string beyond = ", beyond the " + bound(kStickiestDampingContrast) +
                               " the exact theory resolves (and far past where raising it changes C_x)";
    if (!eta1_derived || given(key)) check_contrast(key, eta0, "eta1", p.eta1, kStickiestDampingContrast, "1/s");
    throw InputError("parameters F_drive, v: eta1 = (F_drive - F_kin) / (touching mass x v) = " + bound(p.eta1) +
                     " 1/s lies " + bound(eta0 / p.eta1) + " times below " + key + " = " + bound(eta0) + " 1/s" +
                     beyond + ": give F_drive at least " + text(p.F_kin + (p.F_drive - p.F_kin) * factor) +
                     " N, v at most " + bound(p.v / factor) + " m/s, or " + key + " at most " + bound(eta0 / factor) +
                     " 1/s");
  }
}

/// Every derived rate and landmark a run or the theory uses must be a normal number.
void check_derived(const Parameters& p) {
  const Landmarks l = landmarks(p);
  auto normal = [](const char* what, double value, bool zero_allowed) {
    if (!std::isfinite(value) || (!(zero_allowed && value == 0) && !std::isnormal(value)))
      throw InputError(std::string("parameters: derived ") + what + " = " + bound(value) +
                       " is not a representable number; bring the parameters it depends on closer to 1");
  };
  normal("omega_c = sqrt(N k0 / M)", l.omega_c, false);
  if (p.drive == Drive::spring) normal("omega_s = k_drive v / (F_drive - F_kin)", l.omega_s, false);
  normal("v / a (renewal rate)", l.renewal_rate, false);
  normal("D (diffusion)", l.diffusion, true);
  normal("Eq. (1) prefactor", l.eq1_prefactor, true);
  for (int level = 1; level <= p.levels; ++level) {
    const Level b = p.level(level);
    normal("k0 / m (miniblock resonance squared)", b.k0 / b.m, false);
    normal("k1 / m", b.k1 / b.m, true);
    const std::string suffix = level == 1 ? "" : level_suffix(level);
    check_contrast("k1" + suffix, b.k1, "k0" + suffix, b.k0, kStiffestChainContrast, "N/m");
    normal("random force variance", p.random_force_variance(level), true);
  }
}

}  // namespace

Parameters ParameterBuilder::build() const {
  Parameters p = params_;
  if (given("v") && given("eta1")) throw InputError("parameters v and eta1: give one of them, the other is derived");
  // Of v and eta1 the one not given is derived below, and checked there.
  const std::string derived = given("eta1") ? "v" : "eta1";
  // Keys of a bounded range first: an unbounded one's rule relates it to others (F_drive >
  // F_kin), so where both are wrong the bounded key's message is the one that helps.
  for (const bool bounded : {true, false})
    for_each_parameter(p, [&](const ParameterInfo& info, const auto& value) {
      if (info.key != derived && bounded == (info.range.low > -ranges::kUnbounded)) check(info, info.key, value);
    });
  if (p.drive == Drive::spring && p.k_drive == 0)
    throw InputError("parameter k_drive: drive=spring needs the spring's stiffness k_drive > 0 [N/m]");
  if (p.drive == Drive::force && p.k_drive != 0)
    throw InputError(
        "parameter k_drive: a drive spring's stiffness needs drive=spring (drive is force; k_drive=0 leaves it out)");
  if (p.chain == ChainEnds::ring && p.N < 3)
    throw InputError("parameter chain: a ring needs N >= 3 (got N = " + std::to_string(p.N) + ")");
  build_levels(p);
  for (int l = 2; l <= p.levels; ++l) {
    const Level level = p.level(l);
    if (level.chain == ChainEnds::ring && level.N < 3)
      throw InputError("parameter chain" + level_suffix(l) + ": a ring needs N" + level_suffix(l) + " >= 3 (got " +
                       std::to_string(level.N) + ")");
  }
  // Substrate damping acts on the touching blocks, at one rate eta1 for all of them.
  double touching_mass = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) touching_mass += static_cast<double>(p.blocks(l)) * p.level(l).m;
  if (!(p.F_drive > p.F_kin))
    throw InputError("parameters F_drive, F_kin: F_drive must exceed F_kin for steady sliding (got " + text(p.F_drive) +
                     " <= " + text(p.F_kin) + ")");
  if (given("eta1"))
    p.v = (p.F_drive - p.F_kin) / (touching_mass * p.eta1);
  else
    p.eta1 = (p.F_drive - p.F_kin) / (touching_mass * p.v);
  if (!std::isfinite(p.v) || !std::isfinite(p.eta1) || !(p.v > 0) || !(p.eta1 > 0))
    throw InputError("parameters v, eta1: the derived value is not a finite positive number");
  check_magnitude(derived == "v" ? "v (derived: (F_drive - F_kin) / (touching mass x eta1))"
                                 : "eta1 (derived: (F_drive - F_kin) / (touching mass x v))",
                  derived == "v" ? p.v : p.eta1);
  check_magnitude("F_drive - F_kin", p.F_drive - p.F_kin);
  check_derived(p);
  check_damping_contrast(p, derived == "eta1", [this](const std::string& key) { return given(key); });
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
    for_each_level_parameter(
        p.sublevels[static_cast<std::size_t>(l - 2)],
        [&](const ParameterInfo& info, const auto& value) { check(info, info.key + level_suffix(l), value); });
  if (p.touching.empty()) p.touching = {p.levels};  // the lowest level, said explicitly
  long long total = 0;
  for (int l = 1; l <= p.levels; ++l) {
    total += p.blocks(l);
    if (total <= 10000000) continue;
    // The level whose count crosses the limit is the one to lower.
    std::string key = "N";
    if (l > 1) key += level_suffix(l);
    throw InputError("parameter " + key + ": the tree would have " + std::to_string(total) +
                     " blocks or more, beyond the 10^7 that a run's memory and the exact theory hold");
  }
}

std::vector<std::string> read_parameter_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw FileError("parameter file '" + path + "': cannot be read");
  nlohmann::json doc;
  try {
    in >> doc;
  } catch (const nlohmann::json::exception& e) {
    throw InputError("parameter file '" + path + "': not valid JSON (" + e.what() + ")");
  }
  if (!doc.is_object()) throw InputError("parameter file '" + path + "': expected a JSON object of KEY: value");
  // A run's output JSON: its "parameters" block, where eta1 is listed beside the v it
  // was derived from (or v beside eta1: they agree, and v is kept).
  if (doc.contains("parameters") && doc["parameters"].is_object()) {
    // Only the block is read: a parameter beside it would be dropped without a word.
    const std::vector<std::string>& keys = parameter_keys();
    for (const auto& [key, value] : doc.items())
      if (std::find(keys.begin(), keys.end(), key) != keys.end())
        throw InputError("parameter file '" + path + "': " + key +
                         " is given outside its \"parameters\" block, the one read; give it inside the block");
    doc = nlohmann::json(doc["parameters"]);
  }
  // analyze's JSON holds a record's spectrum and no "parameters" block: its keys are no model's.
  if (doc.contains("usable_band") || doc.contains("record"))
    throw InputError("parameter file '" + path +
                     "': an analyze output, which holds no model parameters; give a run's JSON or an object of "
                     "parameters");
  if (doc.contains("v") && doc.contains("eta1")) doc.erase("eta1");
  std::vector<std::string> assignments;
  for (const auto& [key, value] : doc.items()) {
    if (value.is_string())
      assignments.push_back(key + "=" + value.get<std::string>());
    else if (value.is_number_integer())
      assignments.push_back(key + "=" + std::to_string(value.get<long long>()));
    else if (value.is_number())
      assignments.push_back(key + "=" + util::format_number(value.get<double>()));
    else
      throw InputError("parameter file '" + path + "': value of " + key + " is neither a number nor a string");
  }
  return assignments;
}

std::vector<std::pair<std::string, std::string>> describe(const Parameters& p) {
  std::vector<std::pair<std::string, std::string>> described;
  for_each_parameter(p, [&](const ParameterInfo& info, const auto& value) {
    if (info.shown(p)) described.emplace_back(info.key, text(value));
  });
  for (int l = 2; l <= p.levels; ++l)
    for_each_level_parameter(p.sublevels[static_cast<std::size_t>(l - 2)],
                             [&](const ParameterInfo& info, const auto& value) {
                               described.emplace_back(info.key + level_suffix(l), text(value));
                             });
  return described;
}

const std::vector<ParameterInfo>& parameter_table() {
  static const std::vector<ParameterInfo> table = [] {
    std::vector<ParameterInfo> with_reference = rows();
    const Parameters reference = ParameterBuilder("reference").build();
    for_each_parameter(reference, [&](const ParameterInfo& info, const auto& value) {
      with_reference[static_cast<std::size_t>(&info - rows().data())].reference = text(value);
    });
    return with_reference;
  }();
  return table;
}

const ParameterInfo* find_parameter(const std::string& key) {
  const std::string name = split_level_key(key).first;
  for (const ParameterInfo& info : parameter_table())
    if (info.key == name) return &info;
  return nullptr;
}

const std::vector<std::string>& parameter_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> all;
    for (const ParameterInfo& info : parameter_table()) all.push_back(info.key);
    for (const ParameterInfo& info : parameter_table())
      if (info.per_level) all.push_back(info.key + "_l");
    return all;
  }();
  return keys;
}

}  // namespace slidespec
