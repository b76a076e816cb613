// The quasi-static spectrum (docs/model.md §7.5): against the O(eps^2) series where both
// hold, the exact long-time motion at both ends of the spectrum, and (short here, more
// behind the label long) simulated spectra where the series fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"
#include "theory_cases.hpp"

using namespace slidespec;

namespace {

double stall_eps(int N) { return std::sqrt(2.0 / (3.0 * N)); }

}  // namespace

TEST(QuasiStaticTheory, AgreesWithTheSecondOrderToOrderEpsToTheFourth) {
  // Both ratios to the first order are 1 + O(eps^2) with the same eps^2 term; their
  // difference is O(eps^4): it falls 16-fold when eps halves.
  for (int N : {2, 6, 30})
    for (double omega : {0.01, 0.3, 1.0, 3.0, 30.0}) {
      const auto gap = [&](double eps) {
        const Parameters p = poisson(N, eps);
        return QuasiStaticTheory(p).ratio(omega) - SecondOrderTheory(p).ratio(omega);
      };
      const double wide = gap(0.08), narrow = gap(0.04);
      EXPECT_LT(std::fabs(wide), 2e-3) << N << " " << omega;
      EXPECT_NEAR(wide / narrow, 16, 1.5) << N << " " << omega;
    }
}

TEST(QuasiStaticTheory, LowFrequencyLimitIsTheExactQuasiStaticDiffusion) {
  // omega -> 0: C_x -> D / (pi omega^2) with the exact D of docs/model.md §7, derived in
  // distance (an integral over Laplace variables), not from the resolvent in time.
  for (int N : {2, 3, 4, 6, 12, 30})
    for (double fraction : {0.3, 0.6, 0.95}) {
      const Parameters p = poisson(N, fraction * stall_eps(N));
      const double exact = long_time_motion(p, MotionTheory::quasi_static).diffusion /
                           long_time_motion(p, MotionTheory::first_order).diffusion;
      EXPECT_NEAR(QuasiStaticTheory(p).ratio(1e-5), exact, 2e-3 * exact) << N << " " << fraction;
    }
}

TEST(QuasiStaticTheory, HighFrequencyLimitIsTheExactMeanSpeed) {
  // Far above v/a the force spectrum is the jumps' white spectrum, proportional to their
  // rate N V / a: the ratio is V / v.
  for (int N : {2, 3, 6, 30})
    for (double fraction : {0.3, 0.95}) {
      const Parameters p = poisson(N, fraction * stall_eps(N));
      const double exact = long_time_motion(p, MotionTheory::quasi_static).mean_speed / p.v;
      EXPECT_NEAR(QuasiStaticTheory(p).ratio(1e4), exact, 1e-4) << N << " " << fraction;
    }
}

TEST(QuasiStaticTheory, IsTheFirstOrderTimesItsRatio) {
  const Parameters p = poisson(3, 0.3);
  const QuasiStaticTheory theory(p);
  const LumpedTheory first(p);
  for (double omega : {0.1, 1.0, 100.0}) EXPECT_DOUBLE_EQ(theory(omega), first(omega) * theory.ratio(omega));
  EXPECT_EQ(theory.force_nodes(), 24);
  EXPECT_EQ(QuasiStaticTheory(poisson(30, 0.1)).force_nodes(), 4);
}

TEST(QuasiStaticTheory, RefusesWhatItDoesNotCover) {
  Parameters periodic = poisson(3, 0.2);
  periodic.renewal = Renewal::periodic;
  EXPECT_THROW(QuasiStaticTheory{periodic}, InputError);
  EXPECT_THROW(QuasiStaticTheory{poisson(3, 1.01 * stall_eps(3))}, InputError);
  Parameters spring = poisson(3, 0.2);
  spring.drive = Drive::spring;
  spring.k_drive = 1e4;
  EXPECT_THROW(QuasiStaticTheory{spring}, InputError);
}

namespace {
// Every point of a run within 4 standard errors of the quasi-static theory (the run's
// first-order column, through the estimator's bins, times the ratio at the point's omega)
// and at least 75% within 2 (the map's criterion is 85% over two samples of 14 points; one
// sample of 14 at 1-2% a point lies about 0.5 stderr high on average, docs/model.md §7.5);
// the second order misses at least `second_misses` points by 4.
void expect_quasi_static_holds(const Parameters& p, const RunRequest& request, int second_misses_at_least) {
  const RunResult run = run_spectrum(p, request);
  ASSERT_TRUE(run.complete);
  const QuasiStaticTheory theory(p);
  const SecondOrderTheory second(p);
  int within2 = 0, misses2 = 0;
  double worst = 0, worst2 = 0;
  for (const RunPoint& point : run.points) {
    const double expected = point.theory * theory.ratio(point.omega);
    const double z = (point.C_x - expected) / point.standard_error;
    EXPECT_LE(std::fabs(z), 4) << point.omega << " eps " << landmarks(p).coupling_eps;
    within2 += std::fabs(z) <= 2;
    worst = std::max(worst, std::fabs(z));
    const double z2 = (point.C_x - point.theory * second.ratio(point.omega)) / point.standard_error;
    misses2 += std::fabs(z2) > 4;
    worst2 = std::max(worst2, std::fabs(z2));
  }
  EXPECT_GE(within2, 0.75 * static_cast<double>(run.points.size()));
  EXPECT_GE(misses2, second_misses_at_least);
  std::printf("N %d eps %.3f: worst deviation quasi-static %.1f, second order %.1f stderr; %d of %zu within 2\n", p.N,
              landmarks(p).coupling_eps, worst, worst2, within2, run.points.size());
}
}  // namespace

// Short: N = 3, eps = 0.3 (0.64 of the stall), 0.02 .. 36 rad/s at 2% a point.
TEST(QuasiStaticTheory, MatchesASimulatedSpectrumWhereTheSecondOrderDoesNot) {
  const RunRequest request = band_request(0.02, 36, 0.02, 29);
  expect_quasi_static_holds(poisson(3, 0.3), request, 2);
}

#ifdef SLIDESPEC_LONG_LONG_TIME
// At 1% a point, N = 2, 4, 6, 12 at 0.52-0.89 of the stall boundary (inside the limits but for
// N = 2, whose limit is 0.35 for a failure at 0.43; it holds from 0.52 on, docs/model.md §7.5).
TEST(QuasiStaticTheoryLong, MatchesSimulatedSpectra) {
  const RunRequest request = band_request(0.02, 36, 0.01, 37);
  expect_quasi_static_holds(poisson(2, 0.3), request, 1);
  expect_quasi_static_holds(poisson(4, 0.3), request, 2);
  expect_quasi_static_holds(poisson(6, 0.25), request, 2);
  expect_quasi_static_holds(poisson(12, 0.2), request, 0);
}
#endif
