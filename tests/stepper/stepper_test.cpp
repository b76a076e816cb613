#include "slidespec/stepper.hpp"
#include "slidespec/theory.hpp"
#include "trajectories.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <numeric>

#include "model/linear_structure.hpp"

using namespace slidespec;

namespace {

using stepper_test::same_bits;
using stepper_test::simulate;
using stepper_test::Trajectories;

struct MeanAndError {
  double mean, standard_error, variance;
};
MeanAndError statistics(const std::vector<double>& x) {
  const double n = static_cast<double>(x.size());
  const double mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
  double sum2 = 0;
  for (double v : x) sum2 += (v - mean) * (v - mean);
  const double variance = sum2 / (n - 1);
  return {mean, std::sqrt(variance / n), variance};
}

}  // namespace

// Renewals take effect at their own time inside a step, so the sampled trajectory is the
// continuous model's whatever the step: halving dt must reproduce xi at the common times,
// up to the crossing times' cubic (error ~ (omega dt)^4 for the motions in the step) and
// the response table's Taylor term. A renewal applied at the end of its step instead moves
// xi by about the force jump times a step's response, ~1e-2 of xi here.
TEST(Stepper, TrajectoryDoesNotDependOnTheTimeStep) {
  for (const char* renewal : {"renewal=poisson", "renewal=periodic"}) {
    const Parameters p = ParameterBuilder().set(renewal).set("a=1e-7").build();  // 30 renewals per step
    StepperConfig config;
    config.dt = 2e-4;
    config.seed = 5;
    const Trajectories coarse = simulate(p, config, 0, 3, 500);
    config.dt = 1e-4;
    const Trajectories fine = simulate(p, config, 0, 3, 1000);
    double worst = 0, scale = 0;
    for (int k = 0; k < 3; ++k) {
      double xi_coarse = 0, xi_fine = 0;
      for (int n = 0; n < 500; ++n) {
        xi_coarse += coarse.increments[n * 3 + k];
        xi_fine += fine.increments[(2 * n) * 3 + k] + fine.increments[(2 * n + 1) * 3 + k];
        worst = std::max(worst, std::fabs(xi_coarse - xi_fine));
        scale = std::max(scale, std::fabs(xi_coarse));
      }
      EXPECT_EQ(coarse.summaries[k].renewals, fine.summaries[k].renewals) << renewal;
    }
    EXPECT_LT(worst, 1e-6 * scale) << renewal << ": largest difference " << worst << " m of " << scale;
  }
}

TEST(Stepper, EverySimdPathMatchesTheScalarPathBitwise) {
  for (const char* renewal : {"renewal=poisson", "renewal=periodic"})
    for (const char* drive : {"drive=force", "drive=spring"}) {
      ParameterBuilder builder;
      builder.set(renewal).set(drive).set("a=1e-5");  // many renewals
      if (std::string(drive) == "drive=spring") builder.set("k_drive=1e4");
      StepperConfig config;
      config.seed = 7;
      // 0.15 renewals per lane and step: lanes step apart (the scalar path in lockstep);
      // 0.015: lockstep on every path.
      for (const auto& [dt, steps] : {std::pair{1e-4, 3000}, std::pair{1e-5, 20000}}) {
        config.dt = dt;
        stepper_test::expect_every_path_matches_scalar(
            builder.build(), config, steps, std::string(renewal) + " " + drive + " dt " + std::to_string(dt));
      }
    }
}

// The warm-up runs the same kernel at its own step before the first, and the shadow the same
// kernel crossing at v t: the SIMD lanes of both must still be the scalar realizations' and
// shadows', bit for bit, on both renewal kinds and drives.
TEST(Stepper, AWarmedUpRealizationIsTheSameOnEverySimdPath) {
  for (const char* renewal : {"renewal=poisson", "renewal=periodic"})
    for (const char* drive : {"drive=force", "drive=spring"}) {
      ParameterBuilder builder;
      builder.set(renewal).set(drive).set("a=1e-5");
      if (std::string(drive) == "drive=spring") builder.set("k_drive=1e4");
      StepperConfig config;
      config.seed = 7;
      config.dt = 1e-4;
      config.warm_up = 0.1;  // 5000 renewal times a/v
      config.warm_up_dt = 3e-3;
      config.shadow = true;
      stepper_test::expect_every_path_matches_scalar(builder.build(), config, 1500,
                                                     std::string(renewal) + " " + drive + " warmed up");
    }
}

// A stop that can be asked for splits the steps into pieces timed as they run (the warm-up's
// too): every path must keep its bits, whatever the pieces. A stop asked for is heard.
TEST(Stepper, StepsInPiecesKeepEveryBitAndHearAStop) {
  for (const char* drive : {"drive=force", "drive=spring"}) {
    ParameterBuilder builder;
    builder.set(drive).set("a=1e-5");
    if (std::string(drive) == "drive=spring") builder.set("k_drive=1e4");
    const Parameters p = builder.build();
    StepperConfig config;
    config.seed = 11;
    config.dt = 1e-4;
    config.warm_up = 0.1;
    config.warm_up_dt = 3e-3;
    config.shadow = true;
    for (SimdPath path : available_simd_paths()) {
      config.simd = path;
      config.stop = nullptr;
      const stepper_test::Trajectories whole = stepper_test::simulate(p, config, 3, 9, 20000);
      std::atomic<bool> stop{false};
      config.stop = &stop;
      const stepper_test::Trajectories pieces = stepper_test::simulate(p, config, 3, 9, 20000);
      ASSERT_EQ(whole.increments.size(), pieces.increments.size());
      ASSERT_EQ(whole.shadow_increments.size(), pieces.shadow_increments.size());
      std::size_t differing = 0;
      for (std::size_t i = 0; i < whole.increments.size(); ++i)
        differing += !stepper_test::same_bits(whole.increments[i], pieces.increments[i]) +
                     !stepper_test::same_bits(whole.shadow_increments[i], pieces.shadow_increments[i]);
      EXPECT_EQ(differing, 0u) << to_string(path) << " " << drive;
      for (int k = 0; k < 9; ++k) {
        EXPECT_TRUE(stepper_test::same_bits(whole.summaries[k].xi_end, pieces.summaries[k].xi_end));
        EXPECT_EQ(whole.summaries[k].renewals, pieces.summaries[k].renewals);
      }
      stop = true;
      EXPECT_THROW(stepper_test::simulate(p, config, 3, 9, 20000), StepperStopped);
    }
  }
}

// After a warm-up the realization continues where it left the block: the summaries count
// from there (its renewals at v/a per contact over the measured time only), and the first
// increments are the warmed state's, not the start's.
TEST(Stepper, AWarmUpIsOutsideTheSummariesButMovesTheStart) {
  const Parameters p = ParameterBuilder().set("a=1e-5").build();
  StepperConfig config;
  config.dt = 1e-4;
  config.seed = 3;
  const Trajectories cold = simulate(p, config, 0, 16, 1000);
  config.warm_up = 0.5;
  config.warm_up_dt = 1e-3;
  const Trajectories warm = simulate(p, config, 0, 16, 1000);
  double renewals = 0, expected = 0;
  for (int k = 0; k < 16; ++k) {
    renewals += static_cast<double>(warm.summaries[k].renewals);
    expected += p.N * p.v * warm.summaries[k].duration / p.a;
    EXPECT_DOUBLE_EQ(warm.summaries[k].duration, 1000 * config.dt);
  }
  // 30 contacts x 5 renewals in 0.1 s x 16: Poisson counts, 4 standard deviations.
  EXPECT_NEAR(renewals, expected, 4 * std::sqrt(expected));
  std::size_t same = 0;
  for (std::size_t i = 0; i < cold.increments.size(); ++i) same += same_bits(cold.increments[i], warm.increments[i]);
  EXPECT_EQ(same, 0u);
}

// A warm-up tells its progress step by step, before any increment, with a stop or without
// (pieces or whole chunks): near the stall one warm-up can take minutes, and its progress
// line must move. Each realization's warm-up steps are told once, the shadow's not again.
TEST(Stepper, AWarmUpTellsItsProgressBeforeTheFirstIncrements) {
  const Parameters p = ParameterBuilder().set("a=1e-5").build();
  for (const bool stoppable : {false, true}) {
    StepperConfig config;
    config.dt = 1e-4;
    config.seed = 3;
    config.warm_up = 0.5;
    config.warm_up_dt = 1e-3;
    config.shadow = true;
    std::atomic<bool> stop{false};
    if (stoppable) config.stop = &stop;
    std::int64_t told = 0, told_before_increments = -1;
    int calls = 0;
    config.warm_up_progress = [&](std::int64_t realization_steps) {
      told += realization_steps;
      ++calls;
    };
    Stepper stepper(p, config, 0, 5);
    stepper.advance(100, [&](const double*, std::size_t) {
      if (told_before_increments < 0) told_before_increments = told;
    });
    EXPECT_EQ(told_before_increments, 5 * 500) << stoppable;
    EXPECT_EQ(told, 5 * 500) << stoppable;
    EXPECT_GE(calls, 1);
  }
}

TEST(Stepper, ARealizationDoesNotDependOnItsBatch) {
  const Parameters p = ParameterBuilder().set("a=1e-5").build();
  StepperConfig config;
  config.dt = 1e-4;
  stepper_test::expect_realization_independent_of_batch(p, config, 2000);
}

TEST(Stepper, ResultsDoNotDependOnTheThreadCount) {
  const Parameters p = ParameterBuilder().set("a=1e-5").set("drive=spring").set("k_drive=1e4").build();
  StepperConfig config;
  config.dt = 1e-4;
  auto run = [&](int threads) {
    std::vector<RealizationSummary> all(40);
    run_batches(p, config, 0, 40, 2000, threads, 8, {}, [&](std::size_t, std::vector<RealizationSummary> s) {
      for (const auto& r : s) all[r.realization] = r;
    });
    return all;
  };
  const auto one = run(1), two = run(2);
  for (size_t k = 0; k < one.size(); ++k) {
    EXPECT_TRUE(same_bits(one[k].xi_end, two[k].xi_end)) << k;
    EXPECT_EQ(one[k].renewals, two[k].renewals);
  }
}

TEST(Stepper, IncrementsAddUpToXi) {
  const Parameters p = ParameterBuilder().build();
  StepperConfig config;
  config.dt = 1e-3;
  const Trajectories t = simulate(p, config, 0, 3, 5000);
  for (int k = 0; k < 3; ++k) {
    double sum = 0;
    for (size_t s = 0; s < 5000; ++s) sum += t.increments[s * 3 + k];
    EXPECT_DOUBLE_EQ(sum, t.summaries[k].xi_end);
  }
}

// Statistical checks over many independent realizations: tolerances are 4 standard
// errors of the estimate (a false alarm about once in 16000 runs).
class StepperStatistics : public ::testing::TestWithParam<const char*> {
 protected:
  static constexpr int realizations = 2048;
  static constexpr double duration = 100.0;  // s: 50 renewal times of each miniblock
  std::vector<RealizationSummary> run(const Parameters& p) {
    StepperConfig config;
    config.dt = 1e-2;  // exact discretization: a coarse step loses nothing for these checks
    config.seed = 2024;
    std::vector<RealizationSummary> all(realizations);
    run_batches(p, config, 0, realizations, static_cast<std::int64_t>(duration / config.dt), 0, 64, {},
                [&](std::size_t, std::vector<RealizationSummary> s) {
                  for (const auto& r : s) all[r.realization] = r;
                });
    return all;
  }
};

TEST_P(StepperStatistics, MeanSlidingSpeedIsV) {
  const Parameters p = ParameterBuilder(GetParam()).build();
  std::vector<double> speed;
  for (const auto& r : run(p)) speed.push_back(p.v + r.xi_end / r.duration);
  const auto s = statistics(speed);
  // To first order the mean speed is v. Renewal in distance adds a second-order shift:
  // the block lingers where the forces resist, so the time-averaged speed is the harmonic
  // mean of v (1 + s) over distance, s = -sum f_i / (F_drive - F_kin), Var s = eps^2 / 2:
  // v / (1 + eps^2 / 2) to that order (-0.28% in the reference case).
  const double half_eps2 = 0.5 * std::pow(landmarks(p).coupling_eps, 2);
  EXPECT_NEAR(s.mean, p.v / (1 + half_eps2), 4 * s.standard_error);
  EXPECT_LT(s.standard_error, 0.001 * p.v);  // the check has teeth: 0.1% of v resolved
}

TEST_P(StepperStatistics, VarianceOfXiGrowsAsTwoDt) {
  const Parameters p = ParameterBuilder(GetParam()).build();
  std::vector<double> xi;
  for (const auto& r : run(p)) xi.push_back(r.xi_end);
  const auto s = statistics(xi);
  // Forces correlated over tau = a/v: Var xi(T) = 2 D (T - tau (1 - exp(-T/tau))).
  const double tau = p.a / p.v;
  const double expected = 2 * landmarks(p).diffusion * (duration - tau * (1 - std::exp(-duration / tau)));
  // Relative standard error of a sample variance of near-Gaussian data: sqrt(2/(n-1)).
  EXPECT_NEAR(s.variance / expected, 1.0, 4 * std::sqrt(2.0 / (realizations - 1)));
}

TEST_P(StepperStatistics, MiniblocksStayAtTheirMeanOffset) {
  const Parameters p = ParameterBuilder(GetParam()).build();
  std::vector<double> offsets;
  for (const auto& r : run(p)) offsets.push_back(r.mean_offset);
  const auto s = statistics(offsets);
  EXPECT_NEAR(s.mean, 0.0, 4 * s.standard_error);
  // The fluctuation about u_bar is far below u_bar itself.
  EXPECT_LT(std::fabs(s.mean), 1e-3 * std::fabs(p.mean_miniblock_offset()));
}

TEST_P(StepperStatistics, RenewalsHappenAtRateVOverA) {
  const Parameters p = ParameterBuilder(GetParam()).build();
  double renewals = 0, expected = 0;
  for (const auto& r : run(p)) {
    renewals += static_cast<double>(r.renewals);
    expected += p.N * (p.v * r.duration + r.xi_end) / p.a;  // marks passed per distance slid
  }
  // Poisson marks: the count is Poisson; periodic marks: at most one per miniblock off.
  const double tolerance = p.renewal == Renewal::poisson ? 4 * std::sqrt(expected) : double(p.N) * realizations / 2;
  EXPECT_NEAR(renewals, expected, tolerance);
  EXPECT_NEAR(renewals / (p.N * realizations * duration * p.renewal_rate()), 1.0, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Cases, StepperStatistics, ::testing::Values("reference", "fast", "weak-noise"));

// docs/model.md §9: tied to the load point the block's xi is stationary. Between two late
// times T and 2T, far apart against the memory of the forces (a/v) and of the spring
// (1/omega_s), xi(2T) - xi(T) has twice the stationary variance, the integral of C_x over
// all omega; its mean is 0: the block keeps to the load point's speed v.
TEST(SpringStepper, StretchFluctuatesWithTheTheorysVarianceAndTheBlockKeepsSpeedV) {
  for (const char* k_drive : {"1e3", "1e4"}) {
    const Parameters p = ParameterBuilder().set("N=12").set("drive=spring").set("k_drive", k_drive).build();
    StepperConfig config;
    config.dt = 1e-2;
    config.seed = 99;
    const int realizations = 2048;
    const std::int64_t steps = 10000;  // 100 s: 50 renewal times, 10 times 1/omega_s or more
    Stepper stepper(p, config, 0, realizations);
    stepper.advance(steps, {});
    const std::vector<RealizationSummary> at_T = stepper.summaries();
    stepper.advance(steps, {});
    const std::vector<RealizationSummary> at_2T = stepper.summaries();
    std::vector<double> change;
    for (int k = 0; k < realizations; ++k) change.push_back(at_2T[k].xi_end - at_T[k].xi_end);

    const LumpedTheory theory(p);
    double variance = 0;  // 2 int_0^inf C_x domega, midpoints on a fine log grid
    const double omega_low = 1e-6, omega_high = 1e6;
    const int points = 200000;
    const double step = std::log(omega_high / omega_low) / points;
    for (int k = 0; k < points; ++k) {
      const double omega = omega_low * std::exp((k + 0.5) * step);
      variance += 2 * theory(omega) * omega * step;
    }
    const auto s = statistics(change);
    // Relative standard error of a sample variance of near-Gaussian data: sqrt(2/(n-1)).
    EXPECT_NEAR(s.variance / (2 * variance), 1.0, 4 * std::sqrt(2.0 / (realizations - 1))) << k_drive;
    EXPECT_NEAR(s.mean, 0.0, 4 * s.standard_error) << k_drive;
  }
}
