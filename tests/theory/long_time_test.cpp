// The long-time motion of the second-order theory (docs/model.md §7) against an
// independent simulation of the quasi-static block in sliding distance, which is exact to
// every order in eps, and against the full model's stepper.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "long_time_simulation.hpp"
#include "slidespec/theory.hpp"

using namespace slidespec;
using namespace long_time_test;

// The O(eps^2) coefficients, independent of the exact integral: the flat model's closed
// forms (docs/model.md §7) from the general expression, and the exact result's
// departure from them shrinking as eps^4 (D) and eps^6 (V).
TEST(LongTimeMotion, SecondOrderIsTheExactResultsSeries) {
  for (const char* renewal : {"poisson", "periodic"})
    for (int N : {3, 6, 30}) {
      const Parameters p = flat(N, 0.1, renewal);
      const double e = 0.5 * std::pow(landmarks(p).coupling_eps, 2);
      const LongTimeMotion first = long_time_motion(p, MotionTheory::first_order);
      const LongTimeMotion second = long_time_motion(p, MotionTheory::second_order);
      const double D_coefficient = std::string(renewal) == "poisson" ? 4 - 2.6 / N : 13.0 / 3 - (1.6 + 4.0 / 3) / N;
      EXPECT_NEAR(second.diffusion / first.diffusion, 1 + e * D_coefficient, 1e-12);
      EXPECT_NEAR(second.mean_speed / p.v, 1 / (1 + e + e * e * (3 - 1.2 / N)), 1e-12);
      EXPECT_EQ(first.mean_speed, p.v);
      EXPECT_NEAR(first.diffusion / landmarks(p).diffusion, 1.0, 1e-12);

      double departure_D[2], departure_V[2];
      for (int k = 0; k < 2; ++k) {
        const Parameters q = flat(N, k == 0 ? 0.05 : 0.1, renewal);
        const LongTimeMotion exact = long_time_motion(q, MotionTheory::quasi_static);
        const LongTimeMotion series = long_time_motion(q, MotionTheory::second_order);
        departure_D[k] = exact.diffusion / series.diffusion - 1;
        departure_V[k] = exact.mean_speed / series.mean_speed - 1;
      }
      EXPECT_NEAR(departure_D[1] / departure_D[0], 16, 2) << renewal << " N=" << N;
      EXPECT_NEAR(departure_V[1] / departure_V[0], 64, 8) << renewal << " N=" << N;
    }
}

// As alpha -> 0 the exact result becomes the first-order theory, the relative difference
// falling as alpha^2.
TEST(LongTimeMotion, ReducesToFirstOrderAsAlphaSquared) {
  for (const Parameters& p : {flat(6, 0.02, "poisson"), flat(4, 0.02, "periodic")}) {
    Parameters half = p;
    half.alpha /= 2;
    const auto difference = [](const Parameters& q) {
      return long_time_motion(q, MotionTheory::quasi_static).diffusion /
                 long_time_motion(q, MotionTheory::first_order).diffusion -
             1;
    };
    EXPECT_NEAR(difference(p) / difference(half), 4, 0.02);
    EXPECT_NEAR(1 - long_time_motion(p, MotionTheory::quasi_static).mean_speed / p.v, 0.5 * 0.02 * 0.02, 1e-6);
  }
}

TEST(LongTimeMotion, RefusesWhatItCannotCompute) {
  EXPECT_THROW(long_time_motion(ParameterBuilder("hierarchical").build(), MotionTheory::quasi_static), InputError);
  const LongTimeMotion stalled = long_time_motion(flat(6, 0.34, "poisson"), MotionTheory::quasi_static);
  EXPECT_EQ(stalled.mean_speed, 0);
}

// The exact (all orders) V and D against the quasi-static block simulated mark by mark,
// up to eps = 0.3 where the O(eps^2) series is 4-7% off in D: open and periodic, a tree.
TEST(LongTimeMotion, QuasiStaticMatchesDistanceDomainSimulation) {
  const std::vector<Parameters> sets = {flat(3, 0.3, "poisson"), flat(6, 0.25, "periodic"), tree(1.6)};
  std::uint64_t seed = 1;
  for (const Parameters& p : sets) {
    const Motion simulated = simulate_quasi_static(p, 16, 20000, seed++);
    const LongTimeMotion exact = long_time_motion(p, MotionTheory::quasi_static);
    const LongTimeMotion series = long_time_motion(p, MotionTheory::second_order);
    const double eps = landmarks(p).coupling_eps;
    EXPECT_GT(eps, 0.2);
    EXPECT_NEAR(simulated.mean_speed.value, exact.mean_speed, 4 * simulated.mean_speed.error) << eps;
    EXPECT_NEAR(simulated.diffusion.value, exact.diffusion, 4 * simulated.diffusion.error) << eps;
    // The check has teeth: the series' O(eps^4) error is resolved.
    EXPECT_GT(std::fabs(simulated.diffusion.value - series.diffusion), 4 * simulated.diffusion.error) << eps;
  }
}

// The full model (block inertia, springs, miniblocks) against the exact quasi-static
// result: below the block's own rates its long-time motion is the quasi-static block's.
// Mean speed to 0.1% where the first order's v / (1 + eps^2 / 2) is 0.6% off; D where the
// first order is 23% off.
TEST(LongTimeMotion, FullModelMovesAsTheQuasiStaticBlock) {
  const Parameters p = flat(6, 0.3, "poisson");
  const Motion simulated = simulate_full(p, 24576, 20, 200);
  const LongTimeMotion exact = long_time_motion(p, MotionTheory::quasi_static);
  const LongTimeMotion first = long_time_motion(p, MotionTheory::first_order);
  EXPECT_NEAR(simulated.mean_speed.value, exact.mean_speed, 4 * simulated.mean_speed.error);
  EXPECT_LT(4 * simulated.mean_speed.error, 0.001 * exact.mean_speed);
  const double e = 0.5 * std::pow(landmarks(p).coupling_eps, 2);
  EXPECT_GT(std::fabs(simulated.mean_speed.value - p.v / (1 + e)), 4 * simulated.mean_speed.error);
  EXPECT_NEAR(simulated.diffusion.value, exact.diffusion, 4 * simulated.diffusion.error);
  EXPECT_GT(std::fabs(simulated.diffusion.value - first.diffusion), 4 * simulated.diffusion.error);
}

#ifdef SLIDESPEC_LONG_LONG_TIME
// The same at 0.6% in D on three more sets: a ring with periodic renewal, a tree, and
// twelve miniblocks; the first order is excluded on each, the series where eps^4 shows.
TEST(LongTimeMotionLong, FullModelMovesAsTheQuasiStaticBlock) {
  Parameters ring = flat(6, 0.25, "periodic");
  ring.chain = ChainEnds::ring;
  const std::vector<std::pair<Parameters, double>> sets = {
      {ring, 1e-2}, {tree(1.6), 1e-2}, {flat(12, 0.2, "poisson"), 5e-3}};
  for (const auto& [p, dt] : sets) {
    const Motion simulated = simulate_full(p, 65536, 20, 200, dt);
    const LongTimeMotion exact = long_time_motion(p, MotionTheory::quasi_static);
    const LongTimeMotion first = long_time_motion(p, MotionTheory::first_order);
    const double eps = landmarks(p).coupling_eps;
    EXPECT_NEAR(simulated.mean_speed.value, exact.mean_speed, 4 * simulated.mean_speed.error) << eps;
    EXPECT_NEAR(simulated.diffusion.value, exact.diffusion, 4 * simulated.diffusion.error) << eps;
    EXPECT_GT(std::fabs(simulated.diffusion.value - first.diffusion), 4 * simulated.diffusion.error) << eps;
  }
}
#endif
