#include "slidespec/theory.hpp"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "model/linear_structure.hpp"

namespace slidespec {

namespace {
// Beyond these a table is no longer a spectrum one reads, and the work grows with the count.
constexpr int kMostPointsPerDecade = 1000;
constexpr long kMostPoints = 100000;
}  // namespace

std::vector<double> log_spaced_omegas(double omega_min, double omega_max, int points_per_decade) {
  if (!(omega_min > 0) || !(omega_max > omega_min) || !std::isfinite(omega_max))
    throw InputError("omega range: need 0 < omega-min < omega-max (finite)");
  if (points_per_decade < 1 || points_per_decade > kMostPointsPerDecade)
    throw InputError("points: need 1 to " + std::to_string(kMostPointsPerDecade) + " points per decade (got " +
                     std::to_string(points_per_decade) + ")");
  const double decades = std::log10(omega_max / omega_min);
  if (!(decades * points_per_decade < kMostPoints))
    throw InputError("points: omega-min to omega-max at " + std::to_string(points_per_decade) +
                     " per decade is more than " + std::to_string(kMostPoints) + " points");
  // Round so that 0.1..1e5 at 8 per decade gives exactly 49 points, both ends included.
  const long steps = std::lround(std::floor(decades * points_per_decade + 1e-9));
  std::vector<double> omegas;
  omegas.reserve(static_cast<size_t>(steps) + 1);
  for (long k = 0; k <= steps; ++k)
    omegas.push_back(omega_min * std::pow(10.0, static_cast<double>(k) / points_per_decade));
  return omegas;
}

double random_force_spectrum(const Parameters& p, double omega) { return random_force_spectrum(p, 1, omega); }

double random_force_spectrum(const Parameters& p, int level, double omega) {
  const double s2 = p.random_force_variance(level);
  if (p.renewal == Renewal::poisson) {
    const double lambda = p.renewal_rate(level);
    return s2 * lambda / (M_PI * (lambda * lambda + omega * omega));
  }
  const double T = p.level(level).a / p.v;  // renewal period
  const double half = 0.5 * omega * T;
  const double sinc = half == 0.0 ? 1.0 : std::sin(half) / half;
  return s2 * T / (2.0 * M_PI) * sinc * sinc;
}

double eq1_asymptote(const Parameters& p, double omega) {
  return landmarks(p).eq1_prefactor / (omega * omega * omega * omega);
}

std::vector<double> exact_spectrum(const Parameters& p, const std::vector<double>& omegas) {
  const model::LinearStructure s = model::tree_structure(p);
  const std::vector<int> level_of = model::level_of_coordinates(p);
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
    // A singular or non-finite Z (extreme parameters) leaves the factors unusable.
    if (solver.info() != Eigen::Success)
      throw InputError("parameters: the dynamic stiffness at omega = " + std::to_string(omega) +
                       " cannot be factorized (parameters too extreme)");
    const Eigen::VectorXcd G0 = solver.solve(unit_block);
    if (!G0.allFinite())
      throw InputError("parameters: the response at omega = " + std::to_string(omega) + " is not finite");
    // The contacts of a level share one force spectrum: sum their responses first.
    std::vector<double> per_level(static_cast<std::size_t>(p.levels) + 1, 0.0);
    for (const model::Contact& c : s.contacts)
      per_level[static_cast<std::size_t>(level_of[static_cast<std::size_t>(c.coordinate)])] +=
          std::norm(G0(c.coordinate));
    double total = 0.0;
    for (int l = 1; l <= p.levels; ++l)
      if (p.touches(l)) total += random_force_spectrum(p, l, omega) * per_level[static_cast<std::size_t>(l)];
    spectrum.push_back(total);
  }
  return spectrum;
}

struct LumpedTheory::Impl {
  Parameters params;
  Eigen::MatrixXd mass, damping, stiffness;
  std::vector<double> contacts_per_level;  // index = lumped coordinate = level
};

LumpedTheory::LumpedTheory(const Parameters& p) {
  const model::LumpedStructure lumped = model::lumped_tree_structure(p);
  auto impl = std::make_shared<Impl>();
  impl->params = p;
  impl->mass = lumped.mass;
  impl->damping = lumped.damping;
  impl->stiffness = lumped.stiffness;
  impl->contacts_per_level.assign(static_cast<std::size_t>(lumped.mass.rows()), 0.0);
  for (int c : lumped.class_of_contact) impl->contacts_per_level[static_cast<std::size_t>(c)] += 1;
  impl_ = std::move(impl);
}

double LumpedTheory::operator()(double omega) const {
  using Complex = std::complex<double>;
  const Impl& s = *impl_;
  const Eigen::MatrixXcd Z = s.stiffness.cast<Complex>() - (omega * omega) * s.mass.cast<Complex>() -
                             Complex(0.0, omega) * s.damping.cast<Complex>();
  // A force on the block moves every block of a level alike, so G_0j (= G_j0, Z being
  // symmetric) is the same for all contacts j of a level: the lumped response to e_0.
  Eigen::VectorXcd G0(Z.rows());
  if (Z.rows() == 2) {
    G0(1) = -Z(0, 1) / (Z(0, 0) * Z(1, 1) - Z(0, 1) * Z(1, 0));
  } else {
    G0 = Z.partialPivLu().solve(Eigen::VectorXcd::Unit(Z.rows(), 0));
  }
  double total = 0.0;
  for (Eigen::Index l = 1; l < Z.rows(); ++l) {
    const double contacts = s.contacts_per_level[static_cast<std::size_t>(l)];
    if (contacts > 0)
      total += random_force_spectrum(s.params, static_cast<int>(l), omega) * contacts * std::norm(G0(l));
  }
  return total;
}

double spring_low_frequency_limit(const Parameters& p) {
  if (p.drive != Drive::spring) throw InputError("C_x(0): only a block held by a spring (drive=spring) has one");
  return LumpedTheory(p)(0.0);
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
