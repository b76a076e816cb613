// What the stepper tests record of a batch: every increment and the summaries.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "slidespec/stepper.hpp"

namespace slidespec::stepper_test {

struct Trajectories {
  std::vector<double> increments;         // [step][realization]
  std::vector<double> shadow_increments;  // the same for the shadow (StepperConfig::shadow)
  std::vector<RealizationSummary> summaries;
};

inline Trajectories simulate(const Parameters& p, StepperConfig config, std::uint64_t first, int count,
                             std::int64_t steps) {
  Stepper stepper(p, config, first, count);
  Trajectories t;
  stepper.advance(
      steps,
      [&](const double* data, std::size_t n) { t.increments.insert(t.increments.end(), data, data + n * count); },
      [&](const double* data, std::size_t n) {
        t.shadow_increments.insert(t.shadow_increments.end(), data, data + n * count);
      });
  t.summaries = stepper.summaries();
  return t;
}

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Lane k of every SIMD path equals the scalar run of realization k, bit for bit, for
/// realization counts around the lane width so that padded lanes are exercised too.
inline void expect_every_path_matches_scalar(const Parameters& p, StepperConfig config, std::int64_t steps,
                                             const std::string& label) {
  for (SimdPath path : available_simd_paths()) {
    const int w = lane_width(path);
    for (int count : {1, w - 1, w + 1, 3 * w + 2}) {
      if (count < 1) continue;
      config.simd = SimdPath::scalar;
      const Trajectories scalar = simulate(p, config, 5, count, steps);
      config.simd = path;
      const Trajectories simd = simulate(p, config, 5, count, steps);
      ASSERT_EQ(scalar.increments.size(), simd.increments.size());
      size_t differing = 0;
      for (size_t i = 0; i < scalar.increments.size(); ++i)
        differing += !same_bits(scalar.increments[i], simd.increments[i]);
      EXPECT_EQ(scalar.shadow_increments.size(), config.shadow ? scalar.increments.size() : 0u);
      for (size_t i = 0; i < scalar.shadow_increments.size(); ++i)
        differing += !same_bits(scalar.shadow_increments[i], simd.shadow_increments[i]);
      EXPECT_EQ(differing, 0u) << to_string(path) << " count " << count << " " << label;
      for (int k = 0; k < count; ++k) {
        EXPECT_TRUE(same_bits(scalar.summaries[k].xi_end, simd.summaries[k].xi_end));
        EXPECT_TRUE(same_bits(scalar.summaries[k].mean_offset, simd.summaries[k].mean_offset));
        EXPECT_TRUE(same_bits(scalar.summaries[k].jump_energy, simd.summaries[k].jump_energy));
        EXPECT_EQ(scalar.summaries[k].renewals, simd.summaries[k].renewals);
        EXPECT_GT(scalar.summaries[k].renewals, 100u);  // the renewal path is exercised
      }
    }
  }
}

/// Realization 6 run inside a batch of 11 and alone: the same increments, bit for bit.
inline void expect_realization_independent_of_batch(const Parameters& p, const StepperConfig& config,
                                                    std::int64_t steps) {
  const Trajectories wide = simulate(p, config, 0, 11, steps);
  const Trajectories alone = simulate(p, config, 6, 1, steps);
  for (std::size_t s = 0; s < static_cast<std::size_t>(steps); ++s)
    ASSERT_TRUE(same_bits(wide.increments[s * 11 + 6], alone.increments[s])) << "step " << s;
}

}  // namespace slidespec::stepper_test
