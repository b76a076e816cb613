#include "slidespec/theory.hpp"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

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

LumpedTheory::LumpedTheory(const Parameters& p) : params_(p) {
  const model::LumpedStructure lumped = model::lumped_flat_structure(p);
  if (lumped.mass.rows() != 2) throw std::logic_error("LumpedTheory: expected block and one class");
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      mass_[i][j] = lumped.mass(i, j);
      damping_[i][j] = lumped.damping(i, j);
      stiffness_[i][j] = lumped.stiffness(i, j);
    }
  contacts_ = static_cast<double>(lumped.class_of_contact.size());
}

double LumpedTheory::operator()(double omega) const {
  using Complex = std::complex<double>;
  Complex Z[2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      Z[i][j] = stiffness_[i][j] - omega * omega * mass_[i][j] - Complex(0.0, omega) * damping_[i][j];
  // A unit force on one contact is a unit class-sum force on the mean miniblock:
  // G_01 = -Z_01 / det Z for the 2x2 system.
  const Complex G01 = -Z[0][1] / (Z[0][0] * Z[1][1] - Z[0][1] * Z[1][0]);
  return random_force_spectrum(params_, omega) * contacts_ * std::norm(G01);
}

std::vector<double> lumped_spectrum(const Parameters& p, const std::vector<double>& omegas) {
  const LumpedTheory theory(p);
  std::vector<double> spectrum;
  spectrum.reserve(omegas.size());
  for (const double omega : omegas) spectrum.push_back(theory(omega));
  return spectrum;
}

std::vector<double> interval_averaged_spectrum(const Parameters& p,
                                               const std::vector<std::pair<double, double>>& intervals) {
  // Midpoint rule, with a spacing well below the resonance's half width (the block's
  // damping rate, about N m eta0 / M) so the peak's area is caught wherever it falls.
  const double half_width = std::max(p.N * p.m * p.eta0 / p.M, 1e-3 * landmarks(p).omega_c);
  const LumpedTheory theory(p);
  std::vector<double> averages;
  for (const auto& [low, high] : intervals) {
    if (!(high > low)) {
      averages.push_back(theory(low));
      continue;
    }
    const int samples = static_cast<int>(std::clamp((high - low) / (0.1 * half_width), 64.0, 20000.0));
    double sum = 0.0;
    for (int k = 0; k < samples; ++k) sum += theory(low + (high - low) * (k + 0.5) / samples);
    averages.push_back(sum / samples);
  }
  return averages;
}

}  // namespace slidespec
