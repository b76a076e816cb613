// The exact first-order (linear-response) spectrum of docs/model.md §4.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "slidespec/parameters.hpp"

namespace slidespec {

/// Points evenly spaced in log omega from omega_min to omega_max inclusive (when
/// the span is a whole number of steps), `points_per_decade` per decade [rad/s].
std::vector<double> log_spaced_omegas(double omega_min, double omega_max, int points_per_decade);

/// Spectrum of one miniblock's random force S_f(omega) [N^2 s], two-sided, angular.
double random_force_spectrum(const Parameters& p, double omega);
/// The same for one contact of touching level `level` (its own a, alpha; rate v / a).
double random_force_spectrum(const Parameters& p, int level, double omega);

/// The paper's Eq. (1) asymptote, prefactor / omega^4 [m^2 s].
double eq1_asymptote(const Parameters& p, double omega);

/// C_x(omega) = sum over contacts j of S_f,j(omega) |G_0j(omega)|^2 [m^2 s] at each omega,
/// from a sparse complex solve per frequency over every block of the tree (O(blocks) for
/// chains of children; the flat model is the one-level tree).
std::vector<double> exact_spectrum(const Parameters& p, const std::vector<double>& omegas);

/// C_x(omega) prepared once for a parameter set and evaluated many times: the structure
/// lumped by level (block and mean block of each level, docs/numerics.md) makes each value
/// a (levels + 1)-square solve, 2x2 for the flat model, whatever the number of blocks.
class LumpedTheory {
 public:
  explicit LumpedTheory(const Parameters& p);
  double operator()(double omega) const;
  struct Impl;

 private:
  std::shared_ptr<const Impl> impl_;
};

/// The spectrum of xi as the stepper samples it every dt [m^2 s]: the random forces held
/// over each step (a renewal takes effect at the next step) and xi read at the step ends,
/// so the forces enter sampled (their spectrum aliased) and the response is the exact
/// step's. Exact for the simulated sequence in first order, for |omega| <= pi/dt; tends
/// to C_x as omega dt -> 0 and differs from it by O((omega dt)^2): about +1.5% at
/// omega dt = 0.3 where C_x ~ omega^-4 (docs/numerics.md).
class SampledTheory {
 public:
  SampledTheory(const Parameters& p, double dt);
  double operator()(double omega) const;
  struct Impl;

 private:
  std::shared_ptr<const Impl> impl_;
};

/// The same C_x from the lumped structure (see LumpedTheory and docs/numerics.md): a small
/// solve per frequency, for the dense sampling that interval averages need.
std::vector<double> lumped_spectrum(const Parameters& p, const std::vector<double>& omegas);

/// The mean of C_x over each interval [low, high] of omega (uniform measure, as FFT bins
/// are), resolving features as narrow as the resonance at omega_c. A Welch estimate
/// averaged over a band of bins estimates this, not C_x at the band's centre.
std::vector<double> interval_averaged_spectrum(const Parameters& p,
                                               const std::vector<std::pair<double, double>>& intervals);

}  // namespace slidespec
