// Model parameters, the named cases of docs/model.md §2, and their validation.
#pragma once

#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "slidespec/input_error.hpp"

namespace slidespec {

/// Levels of a tree, as `touching` lists them (ascending).
using LevelList = std::vector<int>;

// The word-valued parameters' types: enum class ChainEnds { open, ring }, ... (parameters.def).
#define SLIDESPEC_WORDS(Type, ...)      \
  enum class Type { __VA_ARGS__ };      \
  const char* to_string(Type value);    \
  /** The words in the enum's order. */ \
  const std::vector<std::string>& words(Type);
#include "slidespec/parameters.def"

/// The values a parameter may take: low < x (or low <= x when low_included), x <= high.
struct Range {
  double low, high;
  bool low_included;
};
/// The ranges parameters.def names.
namespace ranges {
inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();
inline constexpr Range any{-kUnbounded, kUnbounded, true};
inline constexpr Range positive{0, kUnbounded, false};
inline constexpr Range non_negative{0, kUnbounded, true};
constexpr Range at_least(double low) { return {low, kUnbounded, true}; }
constexpr Range between(double low, double high) { return {low, high, true}; }
}  // namespace ranges

/// One level of blocks on blocks (docs/model.md §6, docs/hierarchy.md): every block of
/// the level above carries N of these on springs, chained to their siblings. Its fields
/// are the per-level rows of parameters.def.
struct Level {
#define SLIDESPEC_PARAMETER(key, type, reference, range, unit, symbol, scope, shown, doc) \
  SLIDESPEC_PARAMETER_IN_LEVEL_##scope(type key = reference;)
#define SLIDESPEC_PARAMETER_IN_LEVEL_level(field) field
#define SLIDESPEC_PARAMETER_IN_LEVEL_model(field)
#include "slidespec/parameters.def"
#undef SLIDESPEC_PARAMETER_IN_LEVEL_level
#undef SLIDESPEC_PARAMETER_IN_LEVEL_model
};

/// The spring-block model of docs/model.md §1 in SI units, optionally with deeper levels
/// of blocks on blocks (§6). Its fields are the rows of parameters.def, with the reference
/// case's values; the per-level fields N, m, k0, ... are level 1.
/// Exactly one of `v` and `eta1` is an input; the other is derived from
/// v = (F_drive - F_kin) / (eta1 * sum of the touching blocks' masses), which is
/// v = (F_drive - F_kin) / (N m eta1) for one level. Use ParameterBuilder to get a consistent set.
struct Parameters {
#define SLIDESPEC_PARAMETER(key, type, reference, range, unit, symbol, scope, shown, doc) type key = reference;
#include "slidespec/parameters.def"
  std::vector<Level> sublevels;  ///< levels 2..levels

  /// Level l in 1..levels (level 1 from the flat fields).
  Level level(int l) const;
  bool touches(int l) const;
  /// Blocks of level l in the whole tree, N_1 ... N_l.
  long long blocks(int l) const;
  /// Blocks that touch the substrate, over all touching levels.
  long long touching_blocks() const;
  /// Kinetic friction on one touching block, f_kin = F_kin / touching_blocks() [N].
  double friction_per_miniblock() const { return F_kin / static_cast<double>(touching_blocks()); }
  /// Variance of one random force of level l, s2 = alpha_l^2 f_kin^2 / 12 [N^2].
  double random_force_variance(int l = 1) const;
  /// Renewal rate per contact of level l, lambda = v / a_l [1/s].
  double renewal_rate(int l) const { return v / level(l).a; }
  /// The fastest renewal rate of any touching level [1/s] (v / a for one level).
  double renewal_rate() const;
  /// Mean offset of a miniblock from the big block, u_bar = -F_drive / (N k0) [m].
  double mean_miniblock_offset() const { return -F_drive / (N * k0); }
};

/// Landmarks of docs/model.md §4 that follow from the parameters. For a tree the force
/// terms are summed over the touching levels (docs/hierarchy.md); omega_c stays the
/// block's resonance against the level-1 blocks.
struct Landmarks {
  double renewal_rate;  ///< v/a [1/s] (the fastest touching level's)
  double omega_c;       ///< sqrt(N k0 / M) [rad/s]
  double diffusion;  ///< D = alpha^2 F_kin^2 a v / (12 N (F_drive-F_kin)^2) [m^2/s]; half for periodic renewal; 0 with
                     ///< drive = spring
  double eq1_prefactor;   ///< C_x ~ prefactor / omega^4 for v/a << omega << omega_c [m^2 rad^4/s^3]
  double coupling_eps;    ///< eps = alpha F_kin / ((F_drive-F_kin) sqrt(6 N)) [-]
  bool forces_can_stall;  ///< alpha F_kin >= 2 (F_drive - F_kin): a constant force can stall the block
  /// drive = spring: C_x flattens below omega_s = k_drive v / (F_drive - F_kin) [rad/s]; 0 for a force.
  double omega_s;
  /// The block's resonance, sqrt((N k0 + k_drive) / M) [rad/s] (omega_c for a force; k_drive = 0).
  double omega_resonance;
  /// drive = spring: d0 = F_drive / k_drive [m], how far the load point leads the block's
  /// steady place, so that the spring's mean force k_drive d0 balances the contacts' mean
  /// friction F_kin + eta1 (sum of touching masses) v = F_drive; 0 for a force.
  double spring_offset;
};

Landmarks landmarks(const Parameters& p);

/// Expected sum of (f_new - f_old)^2 over the renewals while the block slides `distance`
/// [N^2]: 2 s2_l per mark passed, a mark every a_l on each contact of each touching level.
double expected_jump_energy(const Parameters& p, double distance);

/// A named case of docs/model.md §2: the reference case with some keys changed.
struct Case {
  std::string name;
  std::string description;
  std::vector<std::pair<std::string, std::string>> changes;  ///< KEY=VALUE over the reference
};

const std::vector<Case>& cases();

/// One row of parameters.def, for whoever lists, parses or documents the parameters.
struct ParameterInfo {
  std::string key;
  std::string kind;                  ///< "count", "real", "word" or "levels" (a list of level numbers)
  Range range;                       ///< checked by ParameterBuilder::build()
  std::string allowed;               ///< the range or the words in words: "> 0", "open or ring", ...
  std::string unit;                  ///< SI unit, "" for none
  std::string symbol;                ///< as figures write it: "*η*_{0}" (*italic*, _{subscript})
  bool per_level;                    ///< KEY_l sets level l of a tree
  std::string doc;                   ///< one line
  std::vector<std::string> words;    ///< a word-valued key's words
  std::string reference;             ///< the reference case's value, as describe() writes it
  bool (*shown)(const Parameters&);  ///< whether describe() lists the key
};

/// Every row of parameters.def, in display order.
const std::vector<ParameterInfo>& parameter_table();

/// The row of KEY or KEY_l; nullptr for an unknown key.
const ParameterInfo* find_parameter(const std::string& key);

/// Every parameter key a user may set, in display order. Per-level keys are written
/// KEY_l (N_2, m_2, k0_2, k1_2, eta0_2, a_2, alpha_2, chain_2; KEY_1 is KEY).
const std::vector<std::string>& parameter_keys();

/// Builds a validated parameter set: a case, then KEY=VALUE overrides.
class ParameterBuilder {
 public:
  /// Starts from a named case; throws InputError for an unknown name.
  explicit ParameterBuilder(const std::string& case_name = "reference");

  /// Applies one "KEY=VALUE" override; throws InputError naming the key if malformed.
  ParameterBuilder& set(const std::string& assignment);
  ParameterBuilder& set(const std::string& key, const std::string& value);

  /// Derives eta1 or v and checks every rule of docs/model.md §1-2; throws InputError.
  Parameters build() const;

 private:
  /// Whether the user set `key` (a case's own keys do not count).
  bool given(const std::string& key) const;
  void build_levels(Parameters& p) const;
  Parameters params_;
  std::vector<std::string> given_;
  // Deeper levels as set so far ("N_2" before or after "levels"); unset keys follow the
  // level above scaled to a ten times smaller contact (docs/hierarchy.md).
  std::vector<std::vector<std::pair<std::string, std::string>>> level_keys_;
};

/// Case `case_name` with `assignments` ("KEY=VALUE") set over it in order, built. Throws
/// InputError as ParameterBuilder does.
Parameters build_case(const std::string& case_name, const std::vector<std::string>& assignments);
/// The same with the overrides of a JSON file (read_parameter_file; "" for none) before
/// `assignments`: what a command's --case, --params and --set come to.
Parameters build_case(const std::string& case_name, const std::string& parameter_file,
                      const std::vector<std::string>& assignments);

/// Reads overrides from a JSON object file {"KEY": value, ...}; returns "KEY=VALUE" strings.
std::vector<std::string> read_parameter_file(const std::string& path);

/// The parameters as ordered (key, value) text pairs, for output headers.
std::vector<std::pair<std::string, std::string>> describe(const Parameters& p);

}  // namespace slidespec
