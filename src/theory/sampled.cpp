// The first-order spectrum of the time-discretized process the stepper computes.
#include <Eigen/Dense>
#include <cmath>
#include <complex>

#include "model/linear_structure.hpp"
#include "slidespec/theory.hpp"
#include "model/exact_step.hpp"

namespace slidespec {

struct SampledTheory::Impl {
  Parameters params;
  double dt = 0;
  Eigen::MatrixXcd transition;  // z_{n+1} = transition z_n + forcing g_n
  Eigen::MatrixXcd forcing;
  Eigen::RowVectorXcd increment;  // xi_{n+1} - xi_n = increment z_n + increment_forcing g_n
  Eigen::RowVectorXcd increment_forcing;
  std::vector<double> contacts_per_input;  // independent forces summed into each input

  /// Spectrum of one force of input class `level` sampled every dt [N^2 s]: (dt / 2 pi)
  /// times the discrete-time Fourier transform of its sampled autocovariance.
  double sampled_force_spectrum(int level, double omega) const {
    const double s2 = params.random_force_variance(level);
    const double theta = omega * dt;
    if (params.renewal == Renewal::poisson) {
      // R(tau) = s2 exp(-lambda |tau|): a geometric series in q = exp(-lambda dt).
      const double q = std::exp(-params.renewal_rate(level) * dt);
      return dt / (2 * M_PI) * s2 * (1 - q * q) / (1 - 2 * q * std::cos(theta) + q * q);
    }
    // Periodic renewal, random phase: R(tau) = s2 (1 - |tau|/T)_+ with r = T/dt steps. The
    // sampled triangle is a mixture of the Fejer kernels of half widths K and K+1
    // (K = floor r), which matches it at every integer lag and is stable as theta -> 0.
    const double r = params.level(level).a / params.v / dt;
    const double K = std::floor(r);
    const double weight_K = K * (K + 1 - r) / r;
    auto fejer = [&](double width) {
      if (width == 0) return 0.0;
      const double s = std::sin(0.5 * theta);
      if (std::fabs(s) < 1e-300) return width;
      const double top = std::sin(0.5 * width * theta);
      return top * top / (width * s * s);
    };
    return dt / (2 * M_PI) * s2 * (weight_K * fejer(K) + (1 - weight_K) * fejer(K + 1));
  }
};

SampledTheory::SampledTheory(const Parameters& p, double dt) {
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("time step: dt must be a positive number");
  const model::LumpedStructure lumped = model::lumped_tree_structure(p);
  const model::ExactStep step = model::exact_step(lumped, dt, {p.drive == Drive::spring, p.renewal_rate()});
  auto impl = std::make_shared<Impl>();
  impl->params = p;
  impl->dt = dt;
  const int D = step.dimension, K = step.inputs;
  impl->transition.resize(D, D);
  impl->forcing.resize(D, K);
  impl->increment.resize(D);
  impl->increment_forcing.resize(K);
  for (int i = 0; i < D; ++i) {
    for (int j = 0; j < D; ++j) impl->transition(i, j) = step.transition[i * D + j];
    for (int k = 0; k < K; ++k) impl->forcing(i, k) = step.forcing[i * K + k];
    impl->increment(i) = step.increment[i];
  }
  for (int k = 0; k < K; ++k) impl->increment_forcing(k) = step.increment_forcing[k];
  impl->contacts_per_input.assign(K, 0.0);
  for (int c : lumped.class_of_contact) impl->contacts_per_input[c - 1] += 1;
  impl_ = std::move(impl);
}

double SampledTheory::operator()(double omega) const {
  const Impl& s = *impl_;
  const double theta = omega * s.dt;
  const std::complex<double> z = std::polar(1.0, theta);
  // Transfer from each input's force sequence to the increments of xi.
  const Eigen::MatrixXcd resolvent_forcing =
      (z * Eigen::MatrixXcd::Identity(s.transition.rows(), s.transition.cols()) - s.transition)
          .partialPivLu()
          .solve(s.forcing);
  const Eigen::RowVectorXcd transfer = s.increment * resolvent_forcing + s.increment_forcing;
  // Input class k is level k + 1; each level's forces have their own spectrum.
  double increments = 0;
  for (int k = 0; k < transfer.size(); ++k)
    if (s.contacts_per_input[k] > 0)
      increments += s.contacts_per_input[k] * std::norm(transfer(k)) * s.sampled_force_spectrum(k + 1, omega);
  // xi from its increments: |1 - e^{-i theta}|^2 = 4 sin^2(theta/2).
  const double half = std::sin(0.5 * theta);
  return increments / (4 * half * half);
}

}  // namespace slidespec
