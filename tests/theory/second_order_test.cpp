// The second-order spectrum (docs/model.md §7): its limits against the long-time
// motion derived independently (moments in distance, not the resolvent in time), its
// reduction to first order, and (label long) simulated spectra at eps 0.2-0.3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <string>

#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"
#include "theory_cases.hpp"

using namespace slidespec;

namespace {

Parameters periodic(int N, double eps) {
  Parameters p = poisson(N, eps);
  p.renewal = Renewal::periodic;
  return p;
}

}  // namespace

TEST(SecondOrderTheory, LowFrequencyLimitIsTheSecondOrderDiffusion) {
  // Both are D / D_1 = 1 + e c + O(e^2), e = eps^2 / 2, from the moments in distance (c =
  // 4 - 2.6/N poisson, 13/3 - 2.93/N periodic): compare c. The periodic theory comes from
  // the travel time's cumulants (docs/model.md §7.2), not a resolvent; its O(e^2) remainder
  // needs the smaller eps to stay below 1e-3.
  for (const auto& [make, eps] : {std::pair{&poisson, 0.01}, std::pair{&periodic, 0.003}})
    for (int N : {3, 6, 30}) {
      const Parameters p = make(N, eps);
      const double e = 0.5 * eps * eps;
      const LongTimeMotion first = long_time_motion(p, MotionTheory::first_order);
      const LongTimeMotion second = long_time_motion(p, MotionTheory::second_order);
      const double omega = 1e-6 * p.v / p.a;
      EXPECT_NEAR((SecondOrderTheory(p).ratio(omega) - 1) / e, (second.diffusion / first.diffusion - 1) / e, 1e-3)
          << N << " eps " << eps;
    }
}

TEST(SecondOrderTheory, AboveTheRenewalRateTheForceSpectrumFollowsTheMeanSpeed) {
  // Jumps arrive at the rate N V / a, so the white jump spectrum scales as V / v.
  for (int N : {3, 6, 30}) {
    const Parameters p = poisson(N, 0.2);
    const double e = 0.5 * 0.2 * 0.2;
    EXPECT_NEAR(SecondOrderTheory(p).ratio(1e4 * p.v / p.a), 1 / (1 + e), 1e-6) << N;
  }
}

TEST(SecondOrderTheory, ReducesToFirstOrderAsAlphaSquared) {
  for (double omega : {0.05, 0.5, 5.0}) {
    const Parameters p = poisson(6, 0.02);
    Parameters half = p;
    half.alpha /= 2;
    const double full_difference = SecondOrderTheory(p).ratio(omega) - 1;
    EXPECT_NEAR(full_difference / (SecondOrderTheory(half).ratio(omega) - 1), 4, 0.01) << omega;
    EXPECT_NEAR(SecondOrderTheory(p)(omega), LumpedTheory(p)(omega) * (1 + full_difference),
                1e-12 * LumpedTheory(p)(omega));
  }
}

TEST(SecondOrderTheory, RefusesWhatItDoesNotCover) {
  EXPECT_THROW(SecondOrderTheory(periodic(6, 0.27)), InputError);
  EXPECT_NO_THROW(SecondOrderTheory(periodic(6, 0.25)));
  EXPECT_THROW(SecondOrderTheory(ParameterBuilder("hierarchical").build()), InputError);
}

TEST(SecondOrderTheory, PeriodicAboveTheRenewalRateFollowsTheMeanSpeed) {
  // Where cos(omega a / v) = 0 the first order equals its ripple-free mean, and the jumps'
  // white spectrum at rate N V / a is V / v of it; the travel time's spread has damped
  // the ripple of the second order by then.
  for (int N : {3, 6, 30}) {
    const Parameters p = periodic(N, 0.2);
    const double V = long_time_motion(p, MotionTheory::second_order).mean_speed;
    for (double periods : {200.0, 5000.0}) {
      const double omega = (2 * M_PI * periods + M_PI / 2) * p.v / p.a;
      EXPECT_NEAR(SecondOrderTheory(p).ratio(omega), V / p.v, 2e-4) << N << " " << periods;
    }
  }
}

TEST(SecondOrderTheory, PeriodicReducesToFirstOrderAsAlphaSquared) {
  for (double omega : {0.05, 0.5, 1.0, 5.0}) {
    const Parameters p = periodic(6, 0.02);
    Parameters half = p;
    half.alpha /= 2;
    EXPECT_NEAR((SecondOrderTheory(p).ratio(omega) - 1) / (SecondOrderTheory(half).ratio(omega) - 1), 4, 0.02) << omega;
  }
}

// A run's second-order column against its own simulation where the first order is resolved
// wrong: every point within 4 standard errors of `theory2` (the second-order theory through
// the estimator's bins, computed apart from the stepper), and at least `first_misses` points
// beyond 4 standard errors of the first-order `theory`.
// Returns the largest |C_x / theory - 1| of the first and the second order.
std::pair<double, double> expect_second_order_holds(const Parameters& p, const RunRequest& request,
                                                    int first_misses_at_least, bool within_errors = true) {
  const RunResult run = run_spectrum(p, request);
  EXPECT_TRUE(run.complete);
  EXPECT_TRUE(run.theory2_note.empty()) << run.theory2_note;
  int first_misses = 0;
  double worst2 = 0, worst1 = 0;
  for (const RunPoint& point : run.points) {
    if (within_errors) {
      EXPECT_NEAR(point.C_x, point.theory2, 4 * point.standard_error)
          << point.omega << " eps " << landmarks(p).coupling_eps;
    }
    first_misses += std::fabs(point.C_x - point.theory) > 4 * point.standard_error;
    worst2 = std::max(worst2, std::fabs(point.C_x / point.theory2 - 1));
    worst1 = std::max(worst1, std::fabs(point.C_x / point.theory - 1));
  }
  EXPECT_GE(first_misses, first_misses_at_least) << landmarks(p).coupling_eps;
  std::printf("eps %.3f: largest |C_x/theory - 1| first order %.4f, second order %.4f; first-order misses %d of %zu\n",
              landmarks(p).coupling_eps, worst1, worst2, first_misses, run.points.size());
  return {worst1, worst2};
}

// Short: N = 6, eps = 0.25, 0.1 .. 10 rad/s at 2.5%: below v/a the second order lies 11%
// above the first, 4 standard errors and more.
TEST(SecondOrderTheory, MatchesASimulatedSpectrumWhereTheFirstOrderDoesNot) {
  const RunRequest request = band_request(0.1, 10, 0.025, 17);
  expect_second_order_holds(poisson(6, 0.25), request, 2);
}

// Periodic renewal, N = 6, eps = 0.1: 0.05 .. 50 rad/s at 1% a point. The first order is
// off by up to 15% around the zeros of its force spectrum and by 2.5% below v/a.
TEST(SecondOrderTheory, PeriodicMatchesASimulatedSpectrumWhereTheFirstOrderDoesNot) {
  const RunRequest request = band_request(0.05, 50, 0.01, 23);
  expect_second_order_holds(periodic(6, 0.1), request, 4);
}

#ifdef SLIDESPEC_LONG_LONG_TIME
// Simulated spectra from 0.05 to 50 rad/s at about 0.8% per point: open chains at eps 0.1,
// 0.2 and 0.3, a ring at 0.2 and a tree (three miniblocks carrying two touching
// microcontacts each: eps = alpha_2 / 6 = 0.2).
TEST(SecondOrderTheoryLong, MatchesSimulatedSpectra) {
  Parameters ring = poisson(8, 0.2);
  ring.chain = ChainEnds::ring;
  const Parameters tree =
      ParameterBuilder("reference").set("levels=2").set("N=3").set("N_2=2").set("a_2=1e-3").set("alpha_2=1.2").build();
  const RunRequest request = band_request(0.05, 50, 0.008);
  expect_second_order_holds(poisson(6, 0.1), request, 0);
  for (const Parameters& p : {poisson(6, 0.2), ring, tree}) expect_second_order_holds(p, request, 3);
  // At eps = 0.3 the O(eps^4) terms are resolved too: the second order is only closer.
  const auto [first, second] = expect_second_order_holds(poisson(6, 0.3), request, 3, false);
  EXPECT_LT(second, 0.5 * first);
  // Periodic renewal: a ring at eps 0.1 within the errors; from 0.15 on the O(eps^4) terms
  // are resolved in the bin holding the first zero of the first order's force spectrum, and
  // from 0.2 below v/a too (docs/model.md §7.2), but the second order stays far closer.
  Parameters periodic_ring = periodic(8, 0.1);
  periodic_ring.chain = ChainEnds::ring;
  expect_second_order_holds(periodic_ring, request, 3);
  periodic_ring.alpha *= 1.5;
  for (const Parameters& p : {periodic_ring, periodic(6, 0.2), periodic(6, 0.25)}) {
    const auto [first_p, second_p] = expect_second_order_holds(p, request, 3, false);
    EXPECT_LT(second_p, 0.4 * first_p) << landmarks(p).coupling_eps;
  }
}
#endif
