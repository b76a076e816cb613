#include "slidespec/theory.hpp"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <complex>

#include "model/linear_structure.hpp"

namespace slidespec {

std::vector<double> log_spaced_omegas(double omega_min, double omega_max, int points_per_decade) {
  if (!(omega_min > 0) || !(omega_max > omega_min) || !std::isfinite(omega_max))
    throw InputError("omega range: need 0 < omega-min < omega-max (finite)");
  if (points_per_decade < 1) throw InputError("points: need at least 1 point per decade");
  const double decades = std::log10(omega_max / omega_min);
  // Round so that 0.1..1e5 at 8 per decade gives exactly 49 points, both ends included.
  const long steps = std::lround(std::floor(decades * points_per_decade + 1e-9));
  std::vector<double> omegas;
  omegas.reserve(static_cast<size_t>(steps) + 1);
  for (long k = 0; k <= steps; ++k)
    omegas.push_back(omega_min * std::pow(10.0, static_cast<double>(k) / points_per_decade));
  return omegas;
}

double random_force_spectrum(const Parameters& p, double omega) {
  const double s2 = p.random_force_variance();
  if (p.renewal == Renewal::poisson) {
    const double lambda = p.renewal_rate();
    return s2 * lambda / (M_PI * (lambda * lambda + omega * omega));
  }
  const double T = p.a / p.v;  // renewal period
  const double half = 0.5 * omega * T;
  const double sinc = half == 0.0 ? 1.0 : std::sin(half) / half;
  return s2 * T / (2.0 * M_PI) * sinc * sinc;
}

double eq1_asymptote(const Parameters& p, double omega) {
  return landmarks(p).eq1_prefactor / (omega * omega * omega * omega);
}

std::vector<double> exact_spectrum(const Parameters& p, const std::vector<double>& omegas) {
  const model::LinearStructure s = model::flat_structure(p);
  using Complex = std::complex<double>;
  using SparseC = Eigen::SparseMatrix<Complex>;
  const SparseC K = s.stiffness.cast<Complex>();
  const SparseC M = s.mass.cast<Complex>();
  const SparseC D = s.damping.cast<Complex>();
  Eigen::SparseLU<SparseC> solver;
  bool analyzed = false;
  Eigen::VectorXcd unit_block = Eigen::VectorXcd::Zero(s.coordinates());
  unit_block(0) = 1.0;

  std::vector<double> spectrum;
  spectrum.reserve(omegas.size());
  for (const double omega : omegas) {
    // Dynamic stiffness Z = K - omega^2 M - i omega D; Z is symmetric, so the block's
    // row of G = Z^-1 is its column: one solve gives every G_0i.
    const SparseC Z = K - (omega * omega) * M - Complex(0.0, omega) * D;
    if (!analyzed) {
      solver.analyzePattern(Z);
      analyzed = true;
    }
    solver.factorize(Z);
    const Eigen::VectorXcd G0 = solver.solve(unit_block);
    double total = 0.0;
    for (const model::Contact& c : s.contacts) total += std::norm(G0(c.coordinate));
    spectrum.push_back(random_force_spectrum(p, omega) * total);
  }
  return spectrum;
}

std::vector<double> lumped_spectrum(const Parameters& p, const std::vector<double>& omegas) {
  const model::LumpedStructure lumped = model::lumped_flat_structure(p);
  std::vector<int> contacts_in_class(lumped.mass.rows(), 0);
  for (int c : lumped.class_of_contact) ++contacts_in_class[c];
  std::vector<double> spectrum;
  spectrum.reserve(omegas.size());
  for (const double omega : omegas) {
    const Eigen::MatrixXcd Z = lumped.stiffness.cast<std::complex<double>>() -
                               (omega * omega) * lumped.mass.cast<std::complex<double>>() -
                               std::complex<double>(0.0, omega) * lumped.damping.cast<std::complex<double>>();
    // A unit force on one contact is a unit class-sum force on its lumped coordinate.
    const Eigen::VectorXcd G0 = Z.partialPivLu().solve(Eigen::VectorXcd::Unit(Z.rows(), 0));
    double total = 0.0;
    for (int c = 1; c < Z.rows(); ++c) total += contacts_in_class[c] * std::norm(G0(c));
    spectrum.push_back(random_force_spectrum(p, omega) * total);
  }
  return spectrum;
}

std::vector<double> interval_averaged_spectrum(const Parameters& p,
                                               const std::vector<std::pair<double, double>>& intervals) {
  // Midpoint rule, with a spacing well below the resonance's half width (the block's
  // damping rate, about N m eta0 / M) so the peak's area is caught wherever it falls.
  const double half_width = std::max(p.N * p.m * p.eta0 / p.M, 1e-3 * landmarks(p).omega_c);
  std::vector<double> averages;
  for (const auto& [low, high] : intervals) {
    if (!(high > low)) {
      averages.push_back(lumped_spectrum(p, {low})[0]);
      continue;
    }
    const int samples = static_cast<int>(std::clamp((high - low) / (0.1 * half_width), 64.0, 20000.0));
    std::vector<double> omegas(samples);
    for (int k = 0; k < samples; ++k) omegas[k] = low + (high - low) * (k + 0.5) / samples;
    const std::vector<double> values = lumped_spectrum(p, omegas);
    double sum = 0.0;
    for (double value : values) sum += value;
    averages.push_back(sum / samples);
  }
  return averages;
}

}  // namespace slidespec
