// Driven through a spring (docs/model.md §9), the simulation against the exact theory and
// against an independent dense solve of the full structure with the spring added
// (tests/model/flat_model.hpp, not the stepper's matrices), and its mean speed against the
// load point's v. Built twice: the short variant (0.01..10 rad/s about omega_s = 1 at 10%)
// runs in the default suite; SLIDESPEC_LONG_SPRING builds open and ring chains, poisson and
// periodic renewal, weak and moderate noise over 0.01..1e5 rad/s at 5% (ctest label "long").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "../model/flat_model.hpp"
#include "slidespec/run.hpp"
#include "run/session.hpp"
#include "slidespec/theory.hpp"

using namespace slidespec;

namespace {

struct SpringCase {
  const char* name;
  std::vector<const char*> changes;
};

void PrintTo(const SpringCase& c, std::ostream* os) { *os << c.name; }

Parameters spring_parameters(const SpringCase& c) {
  // N = 12, k_drive = 1e4 N/m: omega_s = k_drive v / (F_drive - F_kin) = 1 rad/s and the
  // resonance at sqrt(N k0 + k_drive) = 361 rad/s, both inside the band.
  ParameterBuilder builder;
  builder.set("N=12").set("drive=spring").set("k_drive=1e4");
  for (const char* change : c.changes) builder.set(change);
  return builder.build();
}

RunRequest spring_request() {
  RunRequest r;
#ifdef SLIDESPEC_LONG_SPRING
  r.omega_min = 0.01;
  r.omega_max = 1e5;
  r.precision = 0.05;
#else
  r.omega_min = 0.01;
  r.omega_max = 10;
  r.precision = 0.1;
#endif
  r.seed = 20261126;
  return r;
}

struct Deviations {
  int points = 0, within_two = 0, beyond_four = 0;
  double worst_z = 0;
  double worst_independent = 0;  // largest |exact / dense - 1| over every bin of every point
};

/// z = (C_x - theory) / stderr per point, with the theory the run reports (the exact
/// theory seen through the estimator's bins and window); and that exact theory against
/// the dense solve at every bin the points average.
Deviations deviations(const Parameters& p, const RunResult& result) {
  Deviations d;
  for (const RunPoint& point : result.points) {
    const double z = (point.C_x - point.theory) / point.standard_error;
    ++d.points;
    d.within_two += std::fabs(z) <= 2;
    d.beyond_four += std::fabs(z) > 4;
    d.worst_z = std::max(d.worst_z, std::fabs(z));
    if (std::fabs(z) > 4)
      std::printf("[ spring ] |z| > 4 at omega = %.4g rad/s: C_x / theory = %.4f\n", point.omega,
                  point.C_x / point.theory);
    const std::vector<double> omegas = point.bins.omegas();
    const std::vector<double> exact = exact_spectrum(p, omegas);
    for (std::size_t k = 0; k < omegas.size(); ++k) {
      const double dense = as_written::flat_model_spectrum(p, omegas[k]);
      if (dense > 0) d.worst_independent = std::max(d.worst_independent, std::fabs(exact[k] / dense - 1));
    }
  }
  return d;
}

#ifndef SLIDESPEC_LONG_SPRING
// Below omega_s C_x is flat: a step set by a sub-band far below it (or by the renewals)
// would alias the spectrum about omega_s into the band. The planner serves omega_s too;
// a constant force's plan is the band's top (and the renewals) alone.
TEST(SpringPlan, TimeStepsServeOmegaSWhereTheSpectrumHasStoppedRising) {
  const Parameters p = spring_parameters({"open", {}});
  const Parameters force = ParameterBuilder().set("N=12").build();
  RunRequest r;
  r.omega_min = 1e-3;
  r.omega_max = 1e3;
  const double omega_s = landmarks(p).omega_s;
  const std::vector<SubBand> spring_plan = plan_sub_bands(p, r), force_plan = plan_sub_bands(force, r);
  ASSERT_EQ(spring_plan.size(), force_plan.size());
  for (std::size_t b = 0; b < spring_plan.size(); ++b) {
    const SubBand &s = spring_plan[b], &f = force_plan[b];
    EXPECT_LE(s.dt * std::max(s.omega_high, omega_s), 0.3 * (1 + 1e-12)) << b;
    const double renewal_cap = 16 / (force.N * force.renewal_rate());
    EXPECT_EQ(f.dt, std::min(0.3 / f.omega_high, renewal_cap)) << b;
    if (s.omega_high >= omega_s) {
      EXPECT_EQ(s.dt, f.dt) << b;
    }
  }
}

// docs/model.md §8-9: §8's stall example (a constant force stalls the block for good) under
// a spring slides on: the run is complete and stationary, at v within 2%, neighbouring
// sub-bands join, and the outputs say that no theory is expected to hold (intermittent
// sliding) instead of presenting the first order as if it did.
TEST(SpringStall, AConstantForceStallCaseSlidesAtVUnderASpring) {
  const Parameters p = ParameterBuilder()
                           .set("N=7")
                           .set("F_drive=8")
                           .set("F_kin=6")
                           .set("a=3e-4")
                           .set("drive=spring")
                           .set("k_drive=1e4")
                           .build();
  ASSERT_TRUE(landmarks(p).forces_can_stall);
  RunRequest r;
  r.omega_min = 0.1;
  r.omega_max = 1e3;
  r.realizations = 16;
  r.seed = 20261126;
  const RunResult result = run_spectrum(p, r);
  EXPECT_TRUE(result.complete);
  EXPECT_TRUE(result.stationary) << result.stationarity;
  ASSERT_GE(result.sub_bands.size(), 4u);
  for (std::size_t b = 0; b + 1 < result.sub_bands.size(); ++b) EXPECT_EQ(run_detail::band_break(result, b), "") << b;
  EXPECT_NEAR(result.mean_speed / p.v, 1.0, 0.02);
  EXPECT_LE(std::fabs(result.mean_speed - p.v), 4 * result.mean_speed_error);
  EXPECT_EQ(result.theory_kind, TheoryKind::none);
  EXPECT_NE(result.theory_kind_note.find("intermittently"), std::string::npos) << result.theory_kind_note;
  std::printf("[ stall  ] mean speed (V - v)/v = %+.2e +- %.1e, %zu sub-bands joined\n", result.mean_speed / p.v - 1,
              result.mean_speed_error / p.v, result.sub_bands.size());
}
#endif

class SpringRun : public ::testing::TestWithParam<SpringCase> {};

TEST_P(SpringRun, AgreesWithTheIndependentTheoryAndSlidesAtV) {
  const SpringCase& c = GetParam();
  const Parameters p = spring_parameters(c);
  const Landmarks l = landmarks(p);
  const RunRequest request = spring_request();
  ASSERT_GT(l.omega_s, request.omega_min);
  ASSERT_LT(l.omega_s, request.omega_max);
  const RunResult result = run_spectrum(p, request);
  ASSERT_TRUE(result.complete) << c.name;
  EXPECT_TRUE(result.stationary) << c.name << ": " << result.stationarity;
  const Deviations d = deviations(p, result);
  EXPECT_LE(d.worst_independent, 1e-6) << c.name;
  EXPECT_GE(d.within_two, 0.85 * d.points) << c.name;
  EXPECT_EQ(d.beyond_four, 0) << c.name << " (largest |z| " << d.worst_z << ")";
  // The load point's v exactly: no eps^2 deficit under a spring (docs/model.md §9).
  const double speed_z = (result.mean_speed - p.v) / result.mean_speed_error;
  EXPECT_LE(std::fabs(speed_z), 4) << c.name;
  std::printf(
      "[ spring ] %-24s %3d points: %.1f%% within 2 stderr, largest |z| %.2f, %d beyond 4; theory/dense - 1 "
      "<= %.1e; mean speed (V - v)/v = %+.2e +- %.1e (%.2f stderr); %.0f s\n",
      c.name, d.points, 100.0 * d.within_two / d.points, d.worst_z, d.beyond_four, d.worst_independent,
      result.mean_speed / p.v - 1, result.mean_speed_error / p.v, speed_z, result.wall_seconds);
}

#ifdef SLIDESPEC_LONG_SPRING
// Weak noise alpha = 0.1 (eps = 0.012); moderate noise at the first order's measured limit
// for each renewal (docs/model.md §7.4): alpha = 0.4 for poisson (eps = 0.047 <= 0.05),
// 0.2 for periodic (eps = 0.024 <= 0.025).
INSTANTIATE_TEST_SUITE_P(
    Long, SpringRun,
    ::testing::Values(SpringCase{"open_poisson_weak", {"chain=open", "renewal=poisson", "alpha=0.1"}},
                      SpringCase{"open_poisson_moderate", {"chain=open", "renewal=poisson", "alpha=0.4"}},
                      SpringCase{"open_periodic_weak", {"chain=open", "renewal=periodic", "alpha=0.1"}},
                      SpringCase{"open_periodic_moderate", {"chain=open", "renewal=periodic", "alpha=0.2"}},
                      SpringCase{"ring_poisson_weak", {"chain=ring", "renewal=poisson", "alpha=0.1"}},
                      SpringCase{"ring_poisson_moderate", {"chain=ring", "renewal=poisson", "alpha=0.4"}},
                      SpringCase{"ring_periodic_weak", {"chain=ring", "renewal=periodic", "alpha=0.1"}},
                      SpringCase{"ring_periodic_moderate", {"chain=ring", "renewal=periodic", "alpha=0.2"}}),
    [](const ::testing::TestParamInfo<SpringCase>& param) { return std::string(param.param.name); });
#else
INSTANTIATE_TEST_SUITE_P(Short, SpringRun,
                         ::testing::Values(SpringCase{"open_poisson_moderate", {"chain=open", "alpha=0.4"}}),
                         [](const ::testing::TestParamInfo<SpringCase>& param) {
                           return std::string(param.param.name);
                         });
#endif

}  // namespace
