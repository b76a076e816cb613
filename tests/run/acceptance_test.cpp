// The acceptance criterion of `slidespec run` against the exact theory, on every case of
// docs/model.md §4 and on parameter sets that are not cases. Built twice: the short variant
// (narrower band, 10% precision) runs in the default suite; SLIDESPEC_LONG_ACCEPTANCE
// builds the full band at the default 5% (ctest label "long").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <ostream>

#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"

using namespace slidespec;

namespace {

struct Setting {
  const char* name;
  const char* case_name;
  std::vector<const char*> changes;
  double omega_min;  // periodic renewal: away from the zeros of its force spectrum
};

// What ctest lists for the instance (instead of its bytes).
void PrintTo(const Setting& s, std::ostream* os) { *os << s.name; }

constexpr std::uint64_t kSeed = 20261123;

RunRequest request_for(const Setting& s) {
  RunRequest r;
#ifdef SLIDESPEC_LONG_ACCEPTANCE
  r.omega_min = std::max(0.1, s.omega_min);
  r.omega_max = 1e5;
  r.precision = 0.05;
#else
  r.omega_min = std::max(1.0, s.omega_min);
  r.omega_max = 1e4;
  r.precision = 0.1;
#endif
  r.seed = kSeed;
  return r;
}

/// The smallest k with P(Binomial(n, p) > k) <= 1e-3.
[[maybe_unused]] int binomial_bound(int n, double p) {
  double tail = 1, term = std::pow(1 - p, n);  // term = P(X = k)
  for (int k = 0; k <= n; ++k) {
    tail -= term;
    if (tail <= 1e-3) return k;
    term *= p / (1 - p) * (n - k) / (k + 1);
  }
  return n;
}

class Acceptance : public ::testing::TestWithParam<Setting> {};

TEST_P(Acceptance, DeviationsFromTheoryAreStandardNormal) {
  const Setting& s = GetParam();
  ParameterBuilder builder(s.case_name);
  for (const char* change : s.changes) builder.set(change);
  const Parameters p = builder.build();
  // The simulation is the full model, the first-order theory differs from it by terms of
  // order eps^2 (the mean speed by eps^2/2 exactly), which the error bars (0.3..1% at most
  // points, well below the target, since the lowest point of each sub-band sets the work)
  // resolve. Where the second-order theory applies (poisson, one touching level) the points
  // must scatter about it as N(0, 1). Elsewhere, where eps^2 reaches 1%, each point must lie
  // within 3 eps^2 of the first-order theory, up to 3 standard errors, instead.
  const double eps = landmarks(p).coupling_eps;
#ifdef SLIDESPEC_LONG_ACCEPTANCE
  // Three independent runs pooled: the points of a sub-band share its realizations, so one
  // run's counts scatter more than a binomial's; 147 points judge the rates more surely.
  const std::uint64_t seeds[] = {kSeed, kSeed + 1, kSeed + 2};
#else
  const std::uint64_t seeds[] = {kSeed};
#endif
  int n = 0, within_two = 0, beyond_three = 0;
  bool second_order_resolved = false;
  double worst = 0;
  for (std::uint64_t seed : seeds) {
    RunRequest request = request_for(s);
    request.seed = seed;
    const RunResult result = run_spectrum(p, request);
    ASSERT_TRUE(result.complete);
    EXPECT_TRUE(result.stationary) << result.stationarity;
    const bool second_order = result.theory2_note.empty();
    second_order_resolved = !second_order && eps * eps >= 0.01;
    for (const RunPoint& point : result.points) {
      const double theory = second_order ? point.theory2 : point.theory;
      const double z = (point.C_x - theory) / point.standard_error;
      ++n;
      within_two += std::fabs(z) <= 2;
      beyond_three += std::fabs(z) > 3;
      worst = std::max(worst, std::fabs(point.C_x / theory - 1));
      if (second_order_resolved) {
        EXPECT_LE(std::fabs(point.C_x - point.theory), 3 * eps * eps * point.theory + 3 * point.standard_error)
            << s.name << " omega " << point.omega;
      }
    }
    EXPECT_LE(result.reached_precision, request.precision) << s.name;
    // The measured mean speed: v / (1 + eps^2/2) to second order (docs/model.md §4.1); the
    // load point's v exactly when driven through a spring (§9).
    const double speed = p.drive == Drive::spring ? p.v : p.v / (1 + 0.5 * eps * eps);
    EXPECT_NEAR(result.mean_speed, speed, 4 * result.mean_speed_error + 1e-3 * p.v) << s.name;
  }
#ifdef SLIDESPEC_LONG_ACCEPTANCE
  // The acceptance criterion on the full band (3 x 49 points): at least 85% within 2
  // standard errors, at most one point in 50 beyond 3.
  const int most_outside_two = n - static_cast<int>(std::ceil(0.85 * n));
  const int most_beyond_three = 1 + n / 50;
#else
  // The short variant has fewer points (33), where "85% within 2" would fail honest error
  // bars one time in 15: its bounds are the counts that standard normal deviations exceed
  // only once in a thousand runs (binomial tails).
  const int most_outside_two = binomial_bound(n, 0.0455);
  const int most_beyond_three = binomial_bound(n, 0.0027);
#endif
  if (!second_order_resolved) {
    EXPECT_LE(n - within_two, most_outside_two) << s.name;
    EXPECT_LE(beyond_three, most_beyond_three) << s.name;
  }
  // No point far off: every error bar is within the target, so honest ones put a point
  // beyond four targets from the theory about once in 5000 runs of 33 points.
  EXPECT_LT(worst, 4 * request_for(s).precision) << s.name;
}

// Below v/a the periodic force spectrum, T s2/(2 pi) sinc^2(omega T/2), is about half the
// Poisson Lorentzian s2 lambda / (pi (lambda^2 + omega^2)) of the same rate: a run that
// renewed on Poisson marks when periodic ones were asked would sit ~70% above the theory.
TEST(Acceptance, PeriodicRenewalBelowTheRenewalRate) {
  const Parameters p = ParameterBuilder("reference").set("renewal=periodic").build();
  const Parameters poisson = ParameterBuilder("reference").build();
  RunRequest r;
  r.omega_min = 0.2;
  r.omega_max = 0.4;  // below v/a = 0.5 rad/s
  r.realizations = 24;
  r.seed = 20261123;
  const RunResult result = run_spectrum(p, r);
  ASSERT_EQ(result.points.size(), 3u);
  const double eps = landmarks(p).coupling_eps;
  for (const RunPoint& point : result.points) {
    // Within 3 standard errors, plus the second-order terms (order eps^2, docs/model.md).
    EXPECT_LE(std::fabs(point.C_x - point.theory), eps * eps * point.theory + 3 * point.standard_error)
        << "omega " << point.omega;
    // The test can tell: the Poisson theory lies many standard errors away.
    const double lorentzian = exact_spectrum(poisson, {point.omega})[0];
    EXPECT_GT(std::fabs(lorentzian - point.theory), 10 * point.standard_error) << "omega " << point.omega;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, Acceptance,
    ::testing::Values(
        Setting{"reference", "reference", {}, 0}, Setting{"fast", "fast", {}, 0},
        Setting{"short_renewal", "short-renewal", {}, 0}, Setting{"many_contacts", "many-contacts", {}, 0},
        Setting{"weak_noise", "weak-noise", {}, 0}, Setting{"medium_noise", "medium-noise", {}, 0},
        Setting{"concrete_fit", "concrete-fit", {}, 0}, Setting{"ring_N12", "reference", {"chain=ring", "N=12"}, 0},
        Setting{"k1_zero", "reference", {"k1=0"}, 0},
        Setting{"other_forces", "reference", {"F_drive=20", "F_kin=8", "alpha=0.7"}, 0},
        Setting{"periodic", "reference", {"renewal=periodic"}, 100},
        // Driven through a spring (docs/model.md §9): omega_s = 1 rad/s inside the band.
        Setting{"spring_open", "reference", {"N=12", "alpha=0.5", "drive=spring", "k_drive=1e4"}, 0},
        Setting{"spring_ring_periodic",
                "reference",
                {"N=12", "chain=ring", "renewal=periodic", "drive=spring", "k_drive=1e4"},
                100},
        // Trees kept small: every contact renews, and the tests' time is renewals.
        Setting{"tree_two_touching_levels", "hierarchical", {"N=10", "N_2=3"}, 0},
        Setting{"tree_lowest_touching_ring", "hierarchical", {"N=10", "N_2=4", "touching=2", "chain_2=ring"}, 0},
        Setting{
            "tree_three_levels", "hierarchical", {"levels=3", "N=4", "N_2=3", "N_3=3", "a_3=1e-4", "touching=1,3"}, 0}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace
