// The exact first-order (linear-response) spectrum of docs/model.md §4.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "slidespec/parameters.hpp"

namespace slidespec {

/// Points evenly spaced in log omega from omega_min to omega_max inclusive (when
/// the span is a whole number of steps), `points_per_decade` per decade [rad/s].
std::vector<double> log_spaced_omegas(double omega_min, double omega_max, int points_per_decade);

/// Spectrum of one miniblock's random force S_f(omega) [N^2 s], two-sided, angular.
double random_force_spectrum(const Parameters& p, double omega);
/// The same for one contact of touching level `level` (its own a, alpha; rate v / a).
double random_force_spectrum(const Parameters& p, int level, double omega);

/// drive = spring: the spring's force k_drive (v t + d0 - x) fluctuates as -k_drive xi, so
/// its spectrum is k_drive^2 C_x [N^2 s] (0 for a constant force).
inline double spring_force_spectrum(const Parameters& p, double C_x) { return p.k_drive * p.k_drive * C_x; }

/// drive = spring: C_x(0), the level C_x flattens to below omega_s [m^2 s]. Throws
/// InputError for a constant force, under which C_x rises as D / (pi omega^2) instead.
double spring_low_frequency_limit(const Parameters& p);

/// The paper's Eq. (1) asymptote, prefactor / omega^4 [m^2 s].
double eq1_asymptote(const Parameters& p, double omega);

/// The lowest omega [rad/s] at which C_x (rising as D / (pi omega^2) below v/a) and the
/// Eq. (1) asymptote both fit in a double, rounded up to three significant digits; 0 where
/// neither grows without bound. Above it both are exact to rounding at any omega.
double lowest_theory_omega(const Parameters& p);
/// The highest omega [rad/s] at which C_x (falling as a power of omega above every corner)
/// is still a normal double, rounded down to three significant digits; infinity where it
/// never leaves them.
double highest_theory_omega(const Parameters& p);
/// Throws InputError naming the first of `omegas` below lowest_theory_omega(p) or above
/// highest_theory_omega(p), and that bound.
void check_theory_omegas(const Parameters& p, const std::vector<double>& omegas);

/// C_x(omega) = sum over contacts j of S_f,j(omega) |G_0j(omega)|^2 [m^2 s] at each omega,
/// from a sparse complex solve per frequency over every block of the tree (O(blocks) for
/// chains of children; the flat model is the one-level tree). Throws InputError before any
/// work where the solve would need more than 80% of the machine's memory.
std::vector<double> exact_spectrum(const Parameters& p, const std::vector<double>& omegas);

/// The memory exact_spectrum's solve takes [bytes]: about 1.8 kB a block (17 GB for 10^7).
double exact_spectrum_bytes(const Parameters& p);

/// C_x(omega) prepared once for a parameter set and evaluated many times: the structure
/// lumped by level (block and mean block of each level, docs/numerics.md) makes each value
/// a (levels + 1)-square solve, 2x2 for the flat model, whatever the number of blocks.
class LumpedTheory {
 public:
  explicit LumpedTheory(const Parameters& p);
  double operator()(double omega) const;
  struct Impl;

 private:
  std::shared_ptr<const Impl> impl_;
};

/// The spectrum of xi of a time-stepped process [m^2 s]: the random forces held over each
/// step (a renewal taking effect at the next step) and xi read at the step ends,
/// so the forces enter sampled (their spectrum aliased) and the response is the exact
/// step's. Exact for the simulated sequence in first order, for |omega| <= pi/dt; tends
/// to C_x as omega dt -> 0 and differs from it by O((omega dt)^2): about +1.5% at
/// omega dt = 0.3 where C_x ~ omega^-4 (docs/numerics.md). The stepper applies renewals at
/// their own time, so its spectrum is C_x; this is the contrast a step-end renewal would give.
class SampledTheory {
 public:
  SampledTheory(const Parameters& p, double dt);
  double operator()(double omega) const;
  struct Impl;

 private:
  std::shared_ptr<const Impl> impl_;
};

/// The same C_x from the lumped structure (see LumpedTheory and docs/numerics.md): a small
/// solve per frequency, for the dense sampling that interval averages need.
std::vector<double> lumped_spectrum(const Parameters& p, const std::vector<double>& omegas);

/// The mean of C_x over each interval [low, high] of omega (uniform measure, as FFT bins
/// are), resolving features as narrow as the resonance at omega_c. A Welch estimate
/// averaged over a band of bins estimates this, not C_x at the band's centre.
std::vector<double> interval_averaged_spectrum(const Parameters& p,
                                               const std::vector<std::pair<double, double>>& intervals);

}  // namespace slidespec

namespace slidespec {

/// The block's long-time motion: mean speed and diffusion constant, from the quasi-static
/// block (dx/dt = v (1 - G(x) / (F_drive - F_kin)), G the total random force as a process
/// in sliding distance), which is exact below v/a and the block's own rates
/// (docs/model.md §7). Below v/a, C_x(omega) -> diffusion / (pi omega^2).
struct LongTimeMotion {
  double mean_speed;  ///< V [m/s]: v / <1/u>, u = 1 - G/(F_drive - F_kin), over distance
  double diffusion;   ///< D = lim Var x(t) / 2t [m^2/s]
};

enum class MotionTheory {
  first_order,   ///< V = v and D_1, the first-order theory's (renewal kind included)
  second_order,  ///< both with their O(eps^2) relative corrections, errors O(eps^4)
  quasi_static,  ///< exact for the quasi-static block, every order in eps
};

/// V and D of the chosen theory (with drive = spring V = v and D = 0 exactly, in every
/// theory: the load point sets the speed). second_order, flat model, e = eps^2 / 2:
/// V = v / (1 + e + e^2 (3 - 1.2/N)); D = D_1 (1 + e (4 - 2.6/N)) for poisson and
/// D_1 (1 + e (13/3 - 2.93/N)) for periodic renewal. quasi_static gives V = D = 0 at or
/// beyond the stall boundary and throws InputError for D with more than one touching level.
LongTimeMotion long_time_motion(const Parameters& p, MotionTheory theory);

/// C_x(omega) to second order in eps on one touching level (docs/model.md §7): the
/// block's response times the force spectrum seen in time, from the quasi-static block's
/// renewal times. Poisson renewal: a resolvent expansion in closed form. Periodic renewal:
/// the travel time's characteristic function, its Gaussian part whole (which fills the
/// first order's zeros and damps its ripple) and the rest to O(eps^2). The ratio to the
/// first order tends to D / D_1 (second order) as omega -> 0 and to V / v (bin-averaged,
/// for periodic renewal) above v/a. Throws InputError for several touching levels and for
/// drive = spring (not derived there).
class SecondOrderTheory {
 public:
  explicit SecondOrderTheory(const Parameters& p);
  double operator()(double omega) const;
  /// Second- over first-order C_x at omega (not finite at the zeros of a periodic
  /// renewal's first-order spectrum).
  double ratio(double omega) const;
  struct Impl;

 private:
  std::shared_ptr<const Impl> impl_;
};

/// C_x(omega) of the quasi-static block at every order in eps (docs/model.md §7.5): the
/// block's linear response times the force spectrum seen in time, the forces a Markov
/// process with generator v u(G) L (poisson renewal in distance, u = 1 - G / (F_drive -
/// F_kin)), its resolvent solved on Gauss-Legendre nodes of each contact's force. Holds
/// where the block's own rates are far above v/a. The ratio to the first order tends to the
/// exact quasi-static D / D_1 as omega -> 0 and to V / v above v/a. Throws InputError for
/// periodic renewal, several touching levels, drive = spring, and where the forces can stall.
class QuasiStaticTheory {
 public:
  explicit QuasiStaticTheory(const Parameters& p);
  double operator()(double omega) const;
  /// Quasi-static over first-order C_x at omega.
  double ratio(double omega) const;
  /// Nodes per contact's force (more for fewer contacts: 24 for N = 2, 4 for N = 30).
  int force_nodes() const;
  struct Impl;

 private:
  std::shared_ptr<const Impl> impl_;
};

}  // namespace slidespec

namespace slidespec {

/// The spectrum theories in the order slidespec prefers them.
enum class TheoryKind {
  second_order,  ///< SecondOrderTheory (docs/model.md §7.1-7.2)
  quasi_static,  ///< QuasiStaticTheory (docs/model.md §7.5), beyond the second order's limit
  first_order,   ///< exact_spectrum, LumpedTheory (docs/model.md §4)
  none,          ///< no theory meets the simulation here
};

/// Where each theory holds, in the coupling eps (Landmarks::coupling_eps): the largest eps at
/// which it met the simulation's spectra at 1% a point, 0.02..36 rad/s, for every N of the map
/// (2 to 30): at least 85% of the points within 2 standard errors and none beyond 4
/// (docs/model.md §7.4, tools/validity_map.py). Every limit of the program is one of these.
inline constexpr double kFirstOrderPoissonEpsMax = 0.05;
inline constexpr double kFirstOrderPeriodicEpsMax = 0.025;
inline constexpr double kSecondOrderPoissonEpsMax = 0.15;
inline constexpr double kSecondOrderPeriodicEpsMax = 0.1;
/// The quasi-static spectrum (poisson renewal) holds up to a fraction of the stall boundary
/// (eps / eps_stall, eps_stall = sqrt(2 / (3 N)) for the flat model), measured as the others:
/// for N = 2 to 0.35 (it misses the omega^-4 range by 1.5-2% at 0.43, though it holds again
/// from 0.52 on), from N = 3 to 0.95, the map's last grid eps; not at all for N = 1 (not
/// measured).
inline constexpr int kQuasiStaticContacts[] = {2, 3};
inline constexpr double kQuasiStaticStallFractionMax[] = {0.35, 0.95};
/// The limit for `contacts` contacts (0 where it is not measured).
double quasi_static_stall_fraction_max(double contacts);
/// drive = spring: the spring takes up the forces' part slower than omega_s = k_drive v /
/// (F_drive - F_kin), so the block's speed fluctuates with the rest only and the first order
/// holds far beyond its constant-force limit once omega_s is a few renewal rates v/a
/// (docs/model.md §9.1, measured as the others with omega_s at 0.2, 2 and 20 v/a). Poisson
/// renewal: from omega_s >= 2 v/a up to 0.95 of the stall boundary (the map's last eps) for
/// every N of the map from 2. Periodic renewal: from omega_s >= 20 v/a, up to the fractions
/// of the stall boundary below (N from 2, from 3, from 6; between grid values the smaller grid
/// N's; for N = 2 none beyond the constant-force limit: 82% within 2 stderr at 0.52).
/// Softer springs, and N = 1 (not measured), keep the constant-force limits.
inline constexpr double kSpringPoissonStiffnessMin = 2;    ///< omega_s / (v/a)
inline constexpr double kSpringPeriodicStiffnessMin = 20;  ///< omega_s / (v/a)
inline constexpr int kSpringFirstOrderContacts[] = {2, 3, 6};
inline constexpr double kSpringPoissonStallFractionMax[] = {0.95, 0.95, 0.95};
inline constexpr double kSpringPeriodicStallFractionMax[] = {0, 0.53, 0.95};
/// The spring's first-order limit in eps / eps_stall for `contacts` contacts at stiffness
/// omega_s / (v/a) (0 where only the constant-force limit holds).
double spring_first_order_stall_fraction_max(Renewal renewal, double contacts, double stiffness);
/// Beyond this SecondOrderTheory refuses periodic renewal: its ripple region (omega ~ 2 pi
/// v / a) goes wrong by tens of percent there.
inline constexpr double kSecondOrderPeriodicComputedEpsMax = 0.25;

/// The best theory that holds for `p`, and why no better one does ("" for the second order):
/// the second order inside its limit, else the quasi-static spectrum inside its own, else
/// the first order inside its own, else none.
struct TheoryChoice {
  TheoryKind kind = TheoryKind::none;
  std::string reason;
};
TheoryChoice best_theory(const Parameters& p);

/// Above this many renewal rates v/a (the resonance and the top sub-runs) the theories were
/// measured apart (tools/validity_map_high.tsv: 2% a point to 1e5 rad/s, N = 3, 6, 30): there
/// the second order holds for periodic renewal to this eps, beyond its limit over the band.
inline constexpr double kHighRenewalRates = 200;
inline constexpr double kSecondOrderPeriodicHighEpsMax = 0.2;
/// The best theory at one frequency [rad/s]: best_theory(p), and above kHighRenewalRates
/// v/a the second order where the high map supports it (periodic renewal, one touching
/// level, a constant force, eps up to kSecondOrderPeriodicHighEpsMax).
TheoryChoice best_theory_at(const Parameters& p, double omega);

/// "second_order", "quasi_static", "first_order" or "none", as outputs name it (theory_kind).
const char* theory_kind_name(TheoryKind kind);

/// C_x beyond first order as every output carries it beside the first order (a run's
/// theory2, theory's C_x2, Python's order=2): the quasi-static spectrum where best_theory
/// names it, else the second-order series. Throws InputError where the series is not
/// derived (several touching levels, drive = spring).
struct BeyondFirstOrder {
  std::function<double(double)> C_x;  ///< [m^2 s] at omega [rad/s]
  bool quasi_static = false;          ///< which of the two C_x is
};
BeyondFirstOrder theory_beyond_first_order(const Parameters& p);

/// Whether eps lies beyond the first order's measured limit, or the forces can stall the
/// block; under a spring, beyond the spring's limits (where best_theory names no first order).
bool outside_first_order(const Parameters& p);

/// The outputs that show landmarks (slidespec/landmarks.def), and when each shows one.
enum class LandmarkOutput { tsv, json, python };
enum class LandmarkShown { always, with_spring, never };

/// A row of slidespec/landmarks.def.
struct LandmarkRow {
  const char* key;
  const char* unit;  ///< "" for none or for a word
  LandmarkShown tsv, json, python;
  const char* doc;
};
/// Every row, in the table's order.
const std::vector<LandmarkRow>& landmark_table();

/// A landmark's value at a parameter set: a number, a yes/no or a word.
struct Landmark {
  const LandmarkRow* row;
  std::variant<double, bool, std::string> value;
  std::string note;  ///< a word's KEY_note row, where the table has one ("" else)
};
/// The landmarks `output` shows for `p`, in the table's order; only those are computed.
std::vector<Landmark> shown_landmarks(const Parameters& p, LandmarkOutput output);

}  // namespace slidespec
