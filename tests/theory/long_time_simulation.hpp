// Simulations the long-time motion is checked against: the quasi-static block followed
// mark by mark in sliding distance (exact to every order in eps, independent of the
// theory's integrals), and the full model's stepper. Shared by the tests and the map
// (long_time_map.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "slidespec/stepper.hpp"
#include "slidespec/theory.hpp"

namespace long_time_test {

using namespace slidespec;

struct Estimate {
  double value, error;  // mean and standard error over independent chunks
};

inline Estimate mean_and_error(const std::vector<double>& x) {
  const double n = static_cast<double>(x.size());
  double mean = 0, sum2 = 0;
  for (double v : x) mean += v / n;
  for (double v : x) sum2 += (v - mean) * (v - mean);
  return {mean, std::sqrt(sum2 / (n - 1) / n)};
}

struct Motion {
  Estimate mean_speed, diffusion;
};

// dx/dt = v (1 - G(x) / (F_drive - F_kin)) followed mark by mark in distance: the time to
// slide each block of length L is a sum of (distance / speed) pieces. With T_b the block
// times, V = L / <T_b> and D = V^3 D_T, D_T = (Var T_b + 2 Cov(T_b, T_b+1)) / 2L exactly
// once L is a few renewal distances (the forces forget in one a).
inline Motion simulate_quasi_static(const Parameters& p, int chunks, int blocks_per_chunk, std::uint64_t seed) {
  struct Contact {
    double a, half_width, force, next_mark;
  };
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Contact> contacts;
  double longest = 0;
  for (int l = 1; l <= p.levels; ++l) {
    if (!p.touches(l)) continue;
    const double half_width = p.level(l).alpha * p.friction_per_miniblock() / 2;
    for (long long j = 0; j < p.blocks(l); ++j) contacts.push_back({p.level(l).a, half_width, 0, 0});
    longest = std::max(longest, p.level(l).a);
  }
  const bool poisson = p.renewal == Renewal::poisson;
  const auto fresh_force = [&](const Contact& c) { return c.half_width * (2 * unit(rng) - 1); };
  const auto next_gap = [&](const Contact& c) { return poisson ? -c.a * std::log(1 - unit(rng)) : c.a; };
  double G = 0;
  for (Contact& c : contacts) {
    c.force = fresh_force(c);
    c.next_mark = poisson ? next_gap(c) : c.a * unit(rng);  // stationary: memoryless / random phase
    G += c.force;
  }
  const double drive_excess = p.F_drive - p.F_kin;
  const double L = 8 * longest;
  double s = 0;
  std::vector<double> speeds, diffusions;
  for (int chunk = 0; chunk < chunks; ++chunk) {
    std::vector<double> times(static_cast<std::size_t>(blocks_per_chunk));
    for (double& T : times) {
      const double end = s + L;
      T = 0;
      for (;;) {
        Contact* first = &contacts[0];
        for (Contact& c : contacts)
          if (c.next_mark < first->next_mark) first = &c;
        const double stop = std::min(first->next_mark, end);
        T += (stop - s) / (p.v * (1 - G / drive_excess));
        s = stop;
        if (stop == end) break;
        G -= first->force;
        first->force = fresh_force(*first);
        G += first->force;
        first->next_mark += next_gap(*first);
      }
    }
    const double n = static_cast<double>(times.size());
    double mean = 0;
    for (double T : times) mean += T / n;
    double var = 0, cov = 0;
    for (std::size_t b = 0; b < times.size(); ++b) {
      var += (times[b] - mean) * (times[b] - mean) / n;
      if (b + 1 < times.size()) cov += (times[b] - mean) * (times[b + 1] - mean) / (n - 1);
    }
    const double V = L / mean;
    speeds.push_back(V);
    diffusions.push_back(V * V * V * (var + 2 * cov) / (2 * L));
  }
  return {mean_and_error(speeds), mean_and_error(diffusions)};
}

// The full model: V and D from xi(warm-up + duration) - xi(warm-up) of many independent
// realizations. The warm-up lets the forces reach their time-stationary law: a run starts
// from the distance-stationary one, which slides faster (the block has not yet lingered
// where the forces resist), by about e v a / v in distance.
// The stepper applies a renewal at the end of its step: keep (jump rate) dt at a few per
// cent, or V comes out high (+0.1% for 0.3 jumps per step at eps 0.27, measured).
inline Motion simulate_full(const Parameters& p, int realizations, double warm_up, double duration, double dt = 1e-2) {
  StepperConfig config;
  config.dt = dt;
  config.seed = 17;
  const auto warm_up_steps = static_cast<std::int64_t>(warm_up / config.dt);
  const auto steps = warm_up_steps + static_cast<std::int64_t>(duration / config.dt);
  std::vector<double> xi(static_cast<std::size_t>(realizations), 0.0);
  const auto make_sink = [&](std::uint64_t first, int count) -> IncrementSink {
    auto done = std::make_shared<std::int64_t>(0);
    return [&xi, first, count, done, warm_up_steps](const double* data, std::size_t chunk) {
      for (std::size_t step = 0; step < chunk; ++step, ++*done)
        if (*done >= warm_up_steps)
          for (int k = 0; k < count; ++k)
            xi[first + static_cast<std::size_t>(k)] +=
                data[step * static_cast<std::size_t>(count) + static_cast<std::size_t>(k)];
    };
  };
  run_batches(p, config, 0, static_cast<std::uint64_t>(realizations), steps, 0, 64, make_sink,
              [](std::size_t, std::vector<RealizationSummary>) {});
  const Estimate mean_xi = mean_and_error(xi);
  double var = 0;
  for (double x : xi) var += (x - mean_xi.value) * (x - mean_xi.value) / (realizations - 1);
  // Var xi(T) = 2 D (T - c tau) for T >> tau = a/v: c = 1 (poisson) or 1/3 (periodic) to
  // first order, which is enough for a correction of a few per cent.
  double longest = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) longest = std::max(longest, p.level(l).a);
  const double tau = longest / p.v;
  const double effective = duration - (p.renewal == Renewal::poisson ? 1.0 : 1.0 / 3) * tau;
  // Var of a sample variance of near-Gaussian data: 2 var^2 / (n - 1).
  return {{p.v + mean_xi.value / duration, mean_xi.error / duration},
          {var / (2 * effective), var / (2 * effective) * std::sqrt(2.0 / (realizations - 1))}};
}

inline Parameters flat(int N, double eps, const char* renewal) {
  // eps = alpha F_kin / ((F_drive - F_kin) sqrt(6 N)), F_kin = F_drive - F_kin = 5 here.
  return ParameterBuilder("reference")
      .set("N", std::to_string(N))
      .set("alpha", std::to_string(eps * std::sqrt(6.0 * N)))
      .set("renewal", renewal)
      .build();
}

inline Parameters tree(double alpha_2) {
  // Three miniblocks, each carrying two touching microcontacts (renewal distance a_2 = a,
  // so that 1e-2 s steps hold few renewals).
  return ParameterBuilder("reference")
      .set("levels=2")
      .set("N=3")
      .set("N_2=2")
      .set("a_2=1e-3")
      .set("alpha_2", std::to_string(alpha_2))
      .build();
}

}  // namespace long_time_test
