// Which theory holds where (docs/model.md §7.4): the eps limits are the ones the measured
// validity map (tools/validity_map.tsv) supports, and best_theory names the best theory
// inside them, none outside.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

#include "slidespec/theory.hpp"

using namespace slidespec;

namespace {

Parameters flat(int N, double eps, Renewal renewal) {
  // eps = alpha F_kin / ((F_drive - F_kin) sqrt(6 N)) with F_kin = F_drive - F_kin = 5.
  Parameters p = ParameterBuilder("reference").set("N", std::to_string(N)).build();
  p.alpha = eps * std::sqrt(6.0 * N);
  p.renewal = renewal;
  return p;
}

/// A landmark's number as a run's JSON shows it.
double shown(const Parameters& p, const std::string& key) {
  for (const Landmark& mark : shown_landmarks(p, LandmarkOutput::json))
    if (mark.row->key == key) return std::get<double>(mark.value);
  ADD_FAILURE() << key << " is not shown";
  return NAN;
}

// Over all points of the map's runs at one (renewal, N, eps), open and ring pooled (the same
// process, two seeds): the criterion, >= 85% within 2 standard errors, none beyond 4.
struct Pooled {
  int points = 0;
  // Points within 2 standard errors and the largest deviation in standard errors (NaN: not
  // computed): first order, second order, quasi-static.
  double within_two[3] = {0, 0, 0};
  double worst[3] = {0, 0, 0};
  bool holds(int order) const {
    return std::isfinite(worst[order]) && worst[order] <= 4 && within_two[order] >= 0.85 * points;
  }
};

using Key = std::tuple<std::string, int, double, double>;  // renewal, N, eps, k_drive (0: a constant force)

std::map<Key, Pooled> read_map(const std::string& file = "validity_map.tsv", const std::string& range = "all") {
  std::ifstream in(std::string(SLIDESPEC_SOURCE_DIR) + "/tools/" + file);
  std::string line;
  std::getline(in, line);
  std::map<Key, Pooled> map;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string x; std::getline(fields, x, '\t');) f.push_back(x);
    if (f.size() < 22 || f[5] != range) continue;
    Pooled& p = map[{f[0], std::stoi(f[2]), std::stod(f[3]), std::stod(f[21])}];
    const int points = std::stoi(f[6]);
    p.points += points;
    for (int order = 0; order < 3; ++order) {
      const int worst_column[] = {7, 10, 17}, within_column[] = {9, 12, 19};
      const double worst = std::stod(f[worst_column[order]]), within = std::stod(f[within_column[order]]);
      p.worst[order] = std::isnan(worst) || std::isnan(p.worst[order]) ? NAN : std::fmax(p.worst[order], worst);
      p.within_two[order] += within * points;
    }
  }
  return map;
}

}  // namespace

// Each limit is a grid eps at which the theory holds for every N of the map, with every
// smaller eps holding too, and at the next grid eps it fails for some N: the limits are
// neither looser nor tighter than the measurement.
TEST(TheoryValidity, LimitsAreTheMeasuredOnes) {
  const std::map<Key, Pooled> map = read_map();
  ASSERT_GT(map.size(), 90u) << "tools/validity_map.tsv is missing or short";
  struct Limit {
    const char* renewal;
    int order;
    double eps_max;
  };
  for (const Limit& limit :
       {Limit{"poisson", 0, kFirstOrderPoissonEpsMax}, Limit{"periodic", 0, kFirstOrderPeriodicEpsMax},
        Limit{"poisson", 1, kSecondOrderPoissonEpsMax}, Limit{"periodic", 1, kSecondOrderPeriodicEpsMax}}) {
    const std::string what = std::string(limit.renewal) + (limit.order ? " second order" : " first order");
    bool limit_on_grid = false;
    double next = INFINITY;
    for (const auto& [key, pooled] : map) {
      const auto& [renewal, N, eps, k_drive] = key;
      if (renewal != limit.renewal || k_drive != 0) continue;
      if (eps <= limit.eps_max + 1e-9) {
        limit_on_grid |= std::fabs(eps - limit.eps_max) < 1e-9;
        EXPECT_TRUE(pooled.holds(limit.order)) << what << " fails at N = " << N << ", eps = " << eps;
      } else {
        next = std::fmin(next, eps);
      }
    }
    EXPECT_TRUE(limit_on_grid) << what << ": " << limit.eps_max << " is not an eps of the map";
    bool fails_next = false;
    for (const auto& [key, pooled] : map)
      if (std::get<0>(key) == limit.renewal && std::get<2>(key) == next && std::get<3>(key) == 0)
        fails_next |= !pooled.holds(limit.order);
    EXPECT_TRUE(fails_next) << what << " holds for every N at eps " << next << ", beyond its limit " << limit.eps_max;
  }
}

// The quasi-static spectrum's limits (a fraction of the stall boundary per range of N): it
// holds at every poisson eps of the map up to its N's limit, and for each limit below the
// map's last eps it fails at the next grid eps for some N that has that limit.
TEST(TheoryValidity, QuasiStaticLimitsAreTheMeasuredOnes) {
  const std::map<Key, Pooled> map = read_map();
  std::map<double, bool> fails_next;  // by limit
  for (int N : {2, 3, 4, 6, 12, 30}) {
    const double stall = std::sqrt(2.0 / (3.0 * N)), limit = quasi_static_stall_fraction_max(N);
    double next = INFINITY;
    int inside = 0;
    for (const auto& [key, pooled] : map) {
      const auto& [renewal, n, eps, k_drive] = key;
      if (renewal != "poisson" || n != N || k_drive != 0) continue;
      if (eps <= limit * stall + 1e-9) {
        ++inside;
        EXPECT_TRUE(pooled.holds(2)) << "quasi-static fails at N = " << N << ", eps = " << eps;
      } else {
        next = std::fmin(next, eps);
      }
    }
    EXPECT_GE(inside, 3) << N;
    fails_next[limit] |= !std::isfinite(next) || !map.at({"poisson", N, next, 0.0}).holds(2);
  }
  for (const auto& [limit, fails] : fails_next)
    EXPECT_TRUE(fails) << "the quasi-static spectrum holds beyond " << limit << " of the stall for every N with it";
}

// Point by point above 200 v/a (the map to 1e5 rad/s, tools/validity_map_high.tsv): at every
// grid point of the map the theory best_theory_at names there meets the simulation (>= 85%
// within 2 standard errors, none beyond 4), and the periodic second order's limit there is a
// grid eps beyond which it fails (or is not computed) for some N.
TEST(TheoryValidity, PointClaimsAboveTheResonanceAreTheMeasuredOnes) {
  const std::map<Key, Pooled> map = read_map("validity_map_high.tsv", "high");
  ASSERT_GT(map.size(), 40u) << "tools/validity_map_high.tsv is missing or short";
  const double high = 1e3 * kHighRenewalRates * 0.5;  // the map's v/a is 0.5 rad/s
  int claimed = 0, periodic_second = 0;
  double next = INFINITY;
  for (const auto& [key, pooled] : map) {
    const auto& [renewal, N, eps, k_drive] = key;
    if (k_drive != 0) continue;
    const Parameters p = flat(N, eps, renewal == "periodic" ? Renewal::periodic : Renewal::poisson);
    const TheoryKind kind = best_theory_at(p, high).kind;
    const int order = kind == TheoryKind::first_order    ? 0
                      : kind == TheoryKind::second_order ? 1
                      : kind == TheoryKind::quasi_static ? 2
                                                         : -1;
    if (order >= 0) {
      ++claimed;
      EXPECT_TRUE(pooled.holds(order)) << renewal << " N = " << N << " eps = " << eps << ": " << theory_kind_name(kind)
                                       << " claimed above 200 v/a";
    }
    if (renewal == "periodic" && eps <= kSecondOrderPeriodicHighEpsMax + 1e-9) {
      periodic_second += kind == TheoryKind::second_order;
      EXPECT_EQ(kind, TheoryKind::second_order) << N << " " << eps;
    }
    if (renewal == "periodic" && eps > kSecondOrderPeriodicHighEpsMax + 1e-9) next = std::fmin(next, eps);
  }
  EXPECT_GT(claimed, 30);
  EXPECT_GT(periodic_second, 10);
  bool fails_next = false;
  for (const auto& [key, pooled] : map)
    if (std::get<0>(key) == "periodic" && std::get<2>(key) == next && std::get<3>(key) == 0)
      fails_next |= !pooled.holds(1);
  EXPECT_TRUE(fails_next) << "the periodic second order holds above 200 v/a for every N at eps " << next;
  // Below 200 v/a the band's claim stands.
  const Parameters periodic = flat(6, 0.15, Renewal::periodic);
  EXPECT_EQ(best_theory_at(periodic, 10 * 0.5).kind, best_theory(periodic).kind);
  EXPECT_EQ(best_theory(periodic).kind, TheoryKind::none);
}

TEST(TheoryValidity, TheSecondOrderInsideItsLimitsNothingOutside) {
  const TheoryChoice reference = best_theory(ParameterBuilder("reference").build());  // eps 0.075
  EXPECT_EQ(reference.kind, TheoryKind::second_order);
  EXPECT_EQ(reference.reason, "");
  EXPECT_STREQ(theory_kind_name(reference.kind), "second_order");
  // Poisson N = 6 at eps 0.2: the second order misses a quarter of the points (docs/model.md
  // §7.4), the quasi-static spectrum holds (§7.5).
  const TheoryChoice quasi = best_theory(flat(6, 0.2, Renewal::poisson));
  EXPECT_EQ(quasi.kind, TheoryKind::quasi_static);
  EXPECT_NE(quasi.reason.find("the second order holds to eps 0.15"), std::string::npos) << quasi.reason;
  EXPECT_STREQ(theory_kind_name(quasi.kind), "quasi_static");
  // Nearer the stall than the quasi-static spectrum's limit: none.
  const TheoryChoice beyond = best_theory(flat(2, 0.3, Renewal::poisson));  // 0.52 of the stall
  EXPECT_EQ(beyond.kind, TheoryKind::none);
  EXPECT_NE(beyond.reason.find("the quasi-static spectrum to"), std::string::npos) << beyond.reason;
  EXPECT_STREQ(theory_kind_name(beyond.kind), "none");
  // Periodic renewal holds to a smaller eps than poisson: eps 0.12 is inside one, not the other.
  EXPECT_EQ(best_theory(flat(4, 0.12, Renewal::poisson)).kind, TheoryKind::second_order);
  EXPECT_EQ(best_theory(flat(4, 0.12, Renewal::periodic)).kind, TheoryKind::none);
  // Stalling forces: no theory, whatever else.
  const TheoryChoice stall = best_theory(flat(6, 0.34, Renewal::poisson));
  EXPECT_EQ(stall.kind, TheoryKind::none);
  EXPECT_NE(stall.reason.find("stall"), std::string::npos) << stall.reason;
}

// Where the second order cannot be computed (two touching levels), the first order holds
// within its own, smaller limit.
TEST(TheoryValidity, TheFirstOrderWhereTheSecondIsNotComputed) {
  // Both levels' noise scaled by one factor scales eps by it. Few contacts (2 miniblocks of 2
  // microblocks, all touching) keep the stall (docs/model.md §8) far beyond the limit.
  const auto tree = [](double factor) {
    const Parameters base = ParameterBuilder("hierarchical").set("touching=1,2").build();
    return ParameterBuilder("hierarchical")
        .set("touching=1,2")
        .set("N=2")
        .set("N_2=2")
        .set("alpha", std::to_string(base.level(1).alpha * factor))
        .set("alpha_2", std::to_string(base.level(2).alpha * factor))
        .build();
  };
  const double eps = landmarks(tree(1)).coupling_eps;
  ASSERT_FALSE(landmarks(tree(3 * kFirstOrderPoissonEpsMax / eps)).forces_can_stall);
  const Parameters inside = tree(0.8 * kFirstOrderPoissonEpsMax / eps);
  ASSERT_THROW(SecondOrderTheory{inside}, InputError);
  ASSERT_NEAR(landmarks(inside).coupling_eps, 0.8 * kFirstOrderPoissonEpsMax, 1e-6);
  const TheoryChoice first = best_theory(inside);
  EXPECT_EQ(first.kind, TheoryKind::first_order);
  EXPECT_NE(first.reason.find("touching"), std::string::npos) << first.reason;
  EXPECT_STREQ(theory_kind_name(first.kind), "first_order");
  const TheoryChoice none = best_theory(tree(1.2 * kFirstOrderPoissonEpsMax / eps));
  EXPECT_EQ(none.kind, TheoryKind::none);
  EXPECT_NE(none.reason.find("the first order to 0.05"), std::string::npos) << none.reason;
}

namespace {

Parameters on_map(const Key& key) {
  const auto& [renewal, N, eps, k_drive] = key;
  Parameters p = flat(N, eps, renewal == "poisson" ? Renewal::poisson : Renewal::periodic);
  if (k_drive > 0) {
    p.drive = Drive::spring;
    p.k_drive = k_drive;
  }
  return p;
}

}  // namespace

// The criterion at every point of the map, constant force and spring alike: the theory
// best_theory reports holds there (>= 85% of the points within 2 standard errors, none beyond
// 4), or it reports none.
TEST(TheoryValidity, EveryPointOfTheMapReportsATheoryThatHoldsThereOrNone) {
  const std::map<Key, Pooled> map = read_map();
  int springs = 0, reported = 0;
  for (const auto& [key, pooled] : map) {
    const TheoryKind kind = best_theory(on_map(key)).kind;
    springs += std::get<3>(key) > 0;
    if (kind == TheoryKind::none) continue;
    ++reported;
    const int column = kind == TheoryKind::first_order ? 0 : kind == TheoryKind::second_order ? 1 : 2;
    EXPECT_TRUE(pooled.holds(column)) << std::get<0>(key) << " N = " << std::get<1>(key)
                                      << ", eps = " << std::get<2>(key) << ", k_drive = " << std::get<3>(key) << ": "
                                      << theory_kind_name(kind) << " is reported, worst " << pooled.worst[column]
                                      << " stderr, " << pooled.within_two[column] << " of " << pooled.points
                                      << " within 2";
  }
  EXPECT_GE(springs, 60) << "the map's spring points are missing";
  EXPECT_GE(reported, 90);
}

// Under a spring the first order's limits are the measured ones: at and above the stiffness
// limit it holds at every point up to its fraction of the stall; at the grid stiffness below
// the limit it fails at some point beyond the constant-force eps limit, and (periodic renewal,
// 2..5 contacts) at the stiffness limit it fails at some point beyond its fraction.
TEST(TheoryValidity, SpringLimitsAreTheMeasuredOnes) {
  const std::map<Key, Pooled> map = read_map();
  for (const Renewal renewal : {Renewal::poisson, Renewal::periodic}) {
    const bool poisson = renewal == Renewal::poisson;
    const double stiffness_min = poisson ? kSpringPoissonStiffnessMin : kSpringPeriodicStiffnessMin;
    const double first_limit = poisson ? kFirstOrderPoissonEpsMax : kFirstOrderPeriodicEpsMax;
    bool softer_fails = false, few_contacts_fail = poisson;
    int inside = 0;
    for (const auto& [key, pooled] : map) {
      const auto& [name, N, eps, k_drive] = key;
      if (name != (poisson ? "poisson" : "periodic") || k_drive == 0) continue;
      const Landmarks l = landmarks(on_map(key));
      const double stiffness = l.omega_s / l.renewal_rate, near_stall = eps / std::sqrt(2.0 / (3.0 * N));
      const double limit = spring_first_order_stall_fraction_max(renewal, N, stiffness);
      if (stiffness >= stiffness_min && near_stall <= limit + 1e-9) {
        ++inside;
        EXPECT_TRUE(pooled.holds(0)) << name << " N = " << N << ", eps = " << eps << ", k_drive = " << k_drive;
      }
      if (std::fabs(stiffness - stiffness_min / 10) < 1e-6 && eps > first_limit) softer_fails |= !pooled.holds(0);
      if (std::fabs(stiffness - stiffness_min) < 1e-6 && N < 6 && near_stall > limit)
        few_contacts_fail |= !pooled.holds(0);
    }
    EXPECT_GE(inside, 5) << "omega_s " << stiffness_min << " v/a";
    EXPECT_TRUE(softer_fails) << "the first order holds under springs softer than omega_s = " << stiffness_min
                              << " v/a";
    EXPECT_TRUE(few_contacts_fail) << "the periodic spring limit for 2..5 contacts is looser than measured";
  }
  // A spring reports the first order where the map shows it holding, none where it fails.
  Parameters stiff = flat(3, 0.4478, Renewal::poisson);  // 0.95 of the stall
  stiff.drive = Drive::spring;
  stiff.k_drive = 1e4;  // omega_s = 2 v/a
  EXPECT_EQ(best_theory(stiff).kind, TheoryKind::first_order);
  stiff.k_drive = 1e3;  // omega_s = 0.2 v/a
  const TheoryChoice soft = best_theory(stiff);
  EXPECT_EQ(soft.kind, TheoryKind::none);
  EXPECT_NE(soft.reason.find("omega_s = 0.2 v/a"), std::string::npos) << soft.reason;
}

// Each contact's random force is uniform over alpha f_kin about its mean, so the contacts can
// hold at most half of that, summed, against the drive's excess F_drive - F_kin: at that
// share 1 a constant force can stall the block (docs/model.md §8).
TEST(TheoryValidity, TheStallFractionIsTheShareOfTheDriveTheRandomForcesCanHold) {
  // The reference case: F_kin = F_drive - F_kin = 5 N, so the share is alpha / 2.
  for (const char* alpha : {"0.25", "1", "1.99", "2", "2.01", "3"}) {
    const Parameters p = ParameterBuilder("reference").set("alpha", alpha).build();
    EXPECT_DOUBLE_EQ(shown(p, "stall_fraction"), std::stod(alpha) / 2) << alpha;
    EXPECT_EQ(landmarks(p).forces_can_stall, std::stod(alpha) >= 2) << alpha;
  }
  // 2 miniblocks of 3 microblocks, both levels touching: 8 contacts share F_kin.
  const Parameters tree = ParameterBuilder("hierarchical")
                              .set("touching=1,2")
                              .set("N=2")
                              .set("N_2=3")
                              .set("alpha=0.4")
                              .set("alpha_2=0.7")
                              .build();
  const double f_kin = tree.F_kin / 8;
  EXPECT_DOUBLE_EQ(shown(tree, "stall_fraction"),
                   (2 * 0.4 * f_kin / 2 + 6 * 0.7 * f_kin / 2) / (tree.F_drive - tree.F_kin));
}
