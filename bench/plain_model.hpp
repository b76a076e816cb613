// The plain baseline of the benchmarks: the same model written the obvious way, one
// realization at a time, every miniblock integrated individually, no SIMD, random numbers
// from std::mt19937_64. It is what the stepper's speed is measured against, not a second
// oracle: its scheme (below) is first-order in dt where the stepper is exact.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "slidespec/parameters.hpp"

namespace slidespec::bench {

/// Semi-implicit Euler in comoving coordinates (docs/model.md §1): each miniblock's own
/// damping m (eta0 + eta1) is taken implicitly, because eta1 dt ~ 300 at dt = 1e-5 s and
/// any explicit treatment of it blows up; springs, coupling to the block and the block
/// itself are explicit (omega dt <= 0.32, well inside the stable range).
class PlainModel {
 public:
  PlainModel(const Parameters& p, double dt, std::uint64_t seed)
      : p_(p), dt_(dt), rng_(seed), offset_(p.N, 0.0), velocity_(p.N, 0.0), force_(p.N, 0.0), mark_(p.N, 0.0) {
    implicit_damping_ = 1.0 / (1.0 + dt * (p.eta0 + p.eta1));
    force_scale_ = p.alpha * p.friction_per_miniblock();
    for (int i = 0; i < p.N; ++i) {
      force_[i] = force_scale_ * (uniform_(rng_) - 0.5);
      mark_[i] = next_spacing() * (p.renewal == Renewal::periodic ? uniform_(rng_) : 1.0);
    }
  }

  /// Advances `steps` steps; returns xi at the end [m].
  double advance(std::int64_t steps) {
    const int N = p_.N;
    const bool ring = p_.chain == ChainEnds::ring;
    for (std::int64_t s = 0; s < steps; ++s) {
      // Miniblock i: offset from its mean place (relative to the block), velocity relative to v.
      double offset_sum = 0, relative_velocity_sum = 0;
      for (int i = 0; i < N; ++i) {
        const double left = i > 0 ? offset_[i - 1] : (ring ? offset_[N - 1] : offset_[i]);
        const double right = i + 1 < N ? offset_[i + 1] : (ring ? offset_[0] : offset_[i]);
        const double spring = p_.k1 * (left + right - 2 * offset_[i]) - p_.k0 * offset_[i] - force_[i];
        velocity_[i] = (velocity_[i] + dt_ * (spring / p_.m + p_.eta0 * block_velocity_)) * implicit_damping_;
        offset_sum += offset_[i];
        relative_velocity_sum += velocity_[i] - block_velocity_;
      }
      block_velocity_ += dt_ / p_.M * (p_.k0 * offset_sum + p_.m * p_.eta0 * relative_velocity_sum);
      for (int i = 0; i < N; ++i) offset_[i] += dt_ * (velocity_[i] - block_velocity_);
      xi_ += dt_ * block_velocity_;
      ++step_;

      // Renewal on the sliding distance: every miniblock checks its own mark.
      const double x = p_.v * dt_ * static_cast<double>(step_) + xi_;
      for (int i = 0; i < N; ++i)
        while (x >= mark_[i]) {
          force_[i] = force_scale_ * (uniform_(rng_) - 0.5);
          mark_[i] += next_spacing();
        }
    }
    return xi_;
  }

 private:
  double next_spacing() { return p_.renewal == Renewal::periodic ? p_.a : -p_.a * std::log1p(-uniform_(rng_)); }

  Parameters p_;
  double dt_, implicit_damping_ = 0, force_scale_ = 0;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::vector<double> offset_, velocity_, force_, mark_;
  double block_velocity_ = 0, xi_ = 0;
  std::int64_t step_ = 0;
};

}  // namespace slidespec::bench
