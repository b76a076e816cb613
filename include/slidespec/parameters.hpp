// Model parameters, the named cases of docs/model.md §2, and their validation.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace slidespec {

/// Thrown for any bad user input. The message is one line that names the key
/// (or option) and what is wrong with it; the CLI prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ChainEnds { open, ring };
enum class Renewal { poisson, periodic };

const char* to_string(ChainEnds chain);
const char* to_string(Renewal renewal);

/// One level of blocks on blocks (docs/model.md §6, docs/hierarchy.md): every block of
/// the level above carries N of these on springs, chained to their siblings.
struct Level {
  int N = 10;          ///< blocks per parent
  double m = 1e-8;     ///< mass [kg]
  double k0 = 1e3;     ///< spring to the parent [N/m]
  double k1 = 10;      ///< spring to a neighbouring sibling [N/m]
  double eta0 = 8e4;   ///< damping rate to the parent [1/s]
  double a = 1e-4;     ///< mean renewal distance, if touching [m]
  double alpha = 1.0;  ///< noise strength, if touching [-]
  ChainEnds chain = ChainEnds::open;
};

/// The spring-block model of docs/model.md §1 in SI units, optionally with deeper levels
/// of blocks on blocks (§6). The flat fields N, m, k0, ... are level 1.
/// Exactly one of `v` and `eta1` is an input; the other is derived from
/// v = (F_drive - F_kin) / (eta1 * sum of the touching blocks' masses), which is
/// v = (F_drive - F_kin) / (N m eta1) for one level. Use ParameterBuilder to get a consistent set.
struct Parameters {
  int N = 30;             ///< number of miniblocks
  double M = 1.0;         ///< big block mass [kg]
  double m = 1e-5;        ///< miniblock mass [kg]
  double k0 = 1e4;        ///< miniblock-block spring [N/m]
  double k1 = 1e2;        ///< miniblock-miniblock spring [N/m]
  double eta0 = 0.8e4;    ///< miniblock-block damping rate [1/s]
  double eta1 = 0.0;      ///< miniblock-substrate damping rate [1/s] (derived when v is given)
  double v = 0.5e-3;      ///< mean sliding speed [m/s]
  double a = 1e-3;        ///< mean renewal distance [m]
  double alpha = 1.0;     ///< noise strength [-]
  double F_drive = 10.0;  ///< driving force [N]
  double F_kin = 5.0;     ///< total kinetic friction N f_kin [N]
  ChainEnds chain = ChainEnds::open;
  Renewal renewal = Renewal::poisson;
  int levels = 1;                ///< levels of blocks below the big block
  std::vector<Level> sublevels;  ///< levels 2..levels
  /// Levels that touch the substrate (eta1, a share of F_kin, random forces), ascending;
  /// empty means the lowest level only.
  std::vector<int> touching;

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
  double renewal_rate;    ///< v/a [1/s] (the fastest touching level's)
  double omega_c;         ///< sqrt(N k0 / M) [rad/s]
  double diffusion;       ///< D = alpha^2 F_kin^2 a v / (12 N (F_drive-F_kin)^2) [m^2/s]; half for periodic renewal
  double eq1_prefactor;   ///< C_x ~ prefactor / omega^4 for v/a << omega << omega_c [m^2 rad^4/s^3]
  double coupling_eps;    ///< eps = alpha F_kin / ((F_drive-F_kin) sqrt(6 N)) [-]
  bool forces_can_stall;  ///< alpha F_kin >= 2 (F_drive - F_kin)
  /// True when docs/model.md §4.1 says the first-order theory may not hold.
  bool outside_first_order() const { return coupling_eps > 0.3 || forces_can_stall; }
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
  void build_levels(Parameters& p) const;
  Parameters params_;
  bool user_set_v_ = false;
  bool user_set_eta1_ = false;
  // Deeper levels as set so far ("N_2" before or after "levels"); unset keys follow the
  // level above scaled to a ten times smaller contact (docs/hierarchy.md).
  std::vector<std::vector<std::pair<std::string, std::string>>> level_keys_;
};

/// Reads overrides from a JSON object file {"KEY": value, ...}; returns "KEY=VALUE" strings.
std::vector<std::string> read_parameter_file(const std::string& path);

/// The parameters as ordered (key, value) text pairs, for output headers.
std::vector<std::pair<std::string, std::string>> describe(const Parameters& p);

}  // namespace slidespec
