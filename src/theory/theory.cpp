#include "slidespec/theory.hpp"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <unistd.h>

#include "model/linear_structure.hpp"
#include "util/numbers.hpp"

namespace slidespec {

namespace {
// Beyond these a table is no longer a spectrum one reads, and the work grows with the count.
constexpr int kMostPointsPerDecade = 1000;
constexpr long kMostPoints = 100000;
}  // namespace

void check_theory_omegas(const Parameters& p, const std::vector<double>& omegas) {
  const double lowest = lowest_theory_omega(p);
  char message[200];
  for (const double omega : omegas)
    if (omega < lowest) {
      std::snprintf(message, sizeof message,
                    "omega = %.3g rad/s: below %.3g rad/s, the lowest at which C_x and C_eq1 fit in a double", omega,
                    lowest);
      throw InputError(message);
    }
  const double highest_asked = omegas.empty() ? 0 : *std::max_element(omegas.begin(), omegas.end());
  if (LumpedTheory(p)(highest_asked) >= std::numeric_limits<double>::min()) return;
  const double highest = highest_theory_omega(p);
  // Below the doubles at every omega: no frequency to name. With no random force at any
  // touching level (alpha = 0) there is no fluctuation at all.
  bool noise = false;
  for (int l = 1; l <= p.levels; ++l) noise = noise || (p.touches(l) && p.level(l).alpha > 0);
  if (highest == 0 && p.F_kin == 0)
    throw InputError(
        "parameter F_kin: 0 gives no random force (its size is alpha F_kin), so C_x is zero at every "
        "omega and there is no spectrum to compute");
  if (highest == 0)
    throw InputError(noise ? "C_x lies below the smallest double at every omega: no spectrum to compute"
                           : "alpha: 0 gives no random force, so C_x is zero at every omega and there is no spectrum "
                             "to compute");
  for (const double omega : omegas)
    if (omega > highest) {
      std::snprintf(message, sizeof message,
                    "omega = %.3g rad/s: above %.3g rad/s, the highest at which C_x is above the smallest double "
                    "(%.3g m^2 s)",
                    omega, highest, std::numeric_limits<double>::min());
      throw InputError(message);
    }
}

double highest_theory_omega(const Parameters& p) {
  const LumpedTheory C_x(p);
  const double smallest = std::numeric_limits<double>::min();
  // Above every corner C_x falls as a power of omega (omega^-8 for the flat model), so the
  // place it leaves the normal doubles is one crossing, found by bisection in log omega.
  double log_low = 0, log_high = std::log(std::numeric_limits<double>::max());
  if (C_x(std::exp(log_high)) >= smallest) return std::numeric_limits<double>::infinity();
  if (!(C_x(1.0) >= smallest)) return 0;
  while (log_high - log_low > 1e-9) {
    const double log_middle = 0.5 * (log_low + log_high);
    (C_x(std::exp(log_middle)) >= smallest ? log_low : log_high) = log_middle;
  }
  // Down to three significant digits, so that the value a message names is itself valid.
  const double highest = std::exp(log_low);
  const double unit = std::pow(10.0, std::floor(std::log10(highest)) - 2);
  return std::floor(highest / unit) * unit;
}

std::vector<double> log_spaced_omegas(double omega_min, double omega_max, int points_per_decade) {
  if (!(omega_min > 0) || !(omega_max > omega_min) || !std::isfinite(omega_max))
    throw InputError("{omega_max} " + util::format_number(omega_max) + " must be finite and above {omega_min} " +
                     util::format_number(omega_min) + ", which must be above 0");
  if (points_per_decade < 1 || points_per_decade > kMostPointsPerDecade)
    throw InputError("{points}: need 1 to " + std::to_string(kMostPointsPerDecade) + " points per decade (got " +
                     std::to_string(points_per_decade) + ")");
  const double decades = std::log10(omega_max / omega_min);
  if (!(decades * points_per_decade < kMostPoints))
    throw InputError("{points}: {omega_min} to {omega_max} at " + std::to_string(points_per_decade) +
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
  const double prefactor = landmarks(p).eq1_prefactor;
  const double omega4 = omega * omega * omega * omega;
  // Below about 1e-77 rad/s omega^4 is subnormal (a few bits) or zero: divide step by step.
  if (omega4 < std::numeric_limits<double>::min()) return prefactor / omega / omega / omega / omega;
  return prefactor / omega4;
}

double lowest_theory_omega(const Parameters& p) {
  const Landmarks l = landmarks(p);
  // C_x -> D / (pi omega^2) below every corner; C_eq1 = prefactor / omega^4. In logarithms,
  // so that the thresholds themselves neither underflow nor overflow.
  const double log_largest = std::log(std::numeric_limits<double>::max());
  double log_lowest = -INFINITY;
  if (l.diffusion > 0) log_lowest = 0.5 * (std::log(l.diffusion / M_PI) - log_largest);
  if (l.eq1_prefactor > 0) log_lowest = std::max(log_lowest, 0.25 * (std::log(l.eq1_prefactor) - log_largest));
  if (!std::isfinite(log_lowest)) return 0;
  // Up to three significant digits, so that the value a message names is itself valid.
  const double lowest = std::exp(log_lowest) * (1 + 1e-9);
  const double unit = std::pow(10.0, std::floor(std::log10(lowest)) - 2);
  return std::ceil(lowest / unit) * unit;
}

namespace {
using Complex = std::complex<double>;
using SparseC = Eigen::SparseMatrix<Complex>;

/// Z = K - omega^2 M - i omega D factorized and solved for the block's column of G = Z^-1.
class BlockResponse {
 public:
  BlockResponse(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M,
                const Eigen::SparseMatrix<double>& D)
      : K_(K.cast<Complex>()), M_(M.cast<Complex>()), D_(D.cast<Complex>()) {}

  /// Z^-1 times `right`; empty when Z cannot be factorized.
  Eigen::VectorXcd solve(double omega, const Eigen::VectorXcd& right) {
    const SparseC Z = K_ - (omega * omega) * M_ - Complex(0.0, omega) * D_;
    if (!analyzed_) {
      solver_.analyzePattern(Z);
      analyzed_ = true;
    }
    solver_.factorize(Z);
    if (solver_.info() != Eigen::Success) return {};
    return solver_.solve(right);
  }

 private:
  SparseC K_, M_, D_;
  Eigen::SparseLU<SparseC> solver_;
  bool analyzed_ = false;
};

/// The structure in coordinates y_0 = q_0 (the block), y_j = q_j - q_0: q = T y. Below the
/// slowest internal corner every coordinate moves with the block; in q the solve then
/// cancels (det Z ~ omega D_total from terms of order K^2, exact only to eps K / (omega
/// D_total)); in y the translation is a coordinate of its own and nothing cancels. The
/// springs are relative, so K's column sums vanish but for a spring to the ground: sums
/// within rounding of their terms are that rounding and set to zero.
struct TranslationFrame {
  Eigen::SparseMatrix<double> K, M, D;
};

TranslationFrame translation_frame(const model::LinearStructure& s) {
  const int n = s.coordinates();
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < n; ++j) {
    entries.emplace_back(j, 0, 1.0);
    if (j > 0) entries.emplace_back(j, j, 1.0);
  }
  Eigen::SparseMatrix<double> T(n, n);
  T.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SparseMatrix<double> Tt = T.transpose();
  TranslationFrame frame{Tt * s.stiffness * T, Tt * s.mass * T, Tt * s.damping * T};
  const double rounding = 16.0 * n * std::numeric_limits<double>::epsilon();
  Eigen::VectorXd column_scale = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < s.stiffness.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(s.stiffness, k); it; ++it)
      column_scale(it.col()) += std::fabs(it.value());
  for (int k = 0; k < frame.K.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(frame.K, k); it; ++it) {
      if (it.row() != 0 && it.col() != 0) continue;
      const double scale = it.row() == 0 && it.col() == 0 ? column_scale.sum() : column_scale(it.row() + it.col());
      if (std::fabs(it.value()) <= rounding * scale) it.valueRef() = 0.0;
    }
  return frame;
}

// Below a thousandth of the corner the direct solve would cancel to eps K_00 / (omega
// D_total) (2e-13 there) and the frame's translation outweighs the rest 1000 to 1; above
// it the direct solve is exact to rounding.
constexpr double kTranslationShare = 1e-3;

/// Where the internal springs outweigh the damping forces at omega on every coordinate
/// (omega D_jj < K_jj), the block's translation dominates the response.
double translation_corner(const model::LinearStructure& s) {
  double corner = INFINITY;
  const Eigen::VectorXd K = Eigen::VectorXd(s.stiffness.diagonal()), D = Eigen::VectorXd(s.damping.diagonal());
  for (int j = 1; j < s.coordinates(); ++j)
    if (D(j) > 0) corner = std::min(corner, K(j) / D(j));
  return corner;
}
}  // namespace

namespace {
double tree_blocks(const Parameters& p) {
  double blocks = 0;
  for (int l = 1; l <= p.levels; ++l) blocks += static_cast<double>(p.blocks(l));
  return blocks;
}
}  // namespace

double exact_spectrum_bytes(const Parameters& p) {
  // Measured: 1.84 GB peak at 10^6 blocks, 17.2 GB at 10^7 (the sparse LU and its fill).
  constexpr double kBytesPerBlock = 1.9e3;
  return kBytesPerBlock * tree_blocks(p);
}

std::vector<double> exact_spectrum(const Parameters& p, const std::vector<double>& omegas) {
  const double machine = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  if (machine > 0 && exact_spectrum_bytes(p) > 0.8 * machine) {
    char message[300];
    std::snprintf(message, sizeof message,
                  "parameter N: the exact theory solves the full structure of its %.3g blocks, about %.3g GB, more "
                  "than 80%% of this machine's %.3g GB; give fewer blocks",
                  tree_blocks(p), exact_spectrum_bytes(p) / 1e9, machine / 1e9);
    throw InputError(message);
  }
  const model::LinearStructure s = model::tree_structure(p);
  const std::vector<int> level_of = model::level_of_coordinates(p);
  BlockResponse direct(s.stiffness, s.mass, s.damping);
  const TranslationFrame frame = translation_frame(s);
  BlockResponse translating(frame.K, frame.M, frame.D);
  const double corner = translation_corner(s);
  const Eigen::VectorXcd unit_block = Eigen::VectorXcd::Unit(s.coordinates(), 0);

  std::vector<double> spectrum;
  spectrum.reserve(omegas.size());
  for (const double omega : omegas) {
    // G_0j times `scale`: omega G_0j in the translation frame, where G_0j alone can
    // exceed a double while C_x does not. Z is symmetric, so the block's row of G is its
    // column (and T^T e_0 = e_0): one solve gives every G_0j.
    Eigen::VectorXcd G0;
    double scale = 1.0;
    if (omega < kTranslationShare * corner) {
      const Eigen::VectorXcd y = translating.solve(omega, omega * unit_block);
      // G_0j = y_0 + y_j: kept where y_j does not cancel y_0 (the translation dominates).
      if (y.size() > 0 && (y.tail(y.size() - 1).cwiseAbs().maxCoeff() <= 0.5 * std::abs(y(0)) || y.size() == 1)) {
        G0 = y.array() + y(0);
        G0(0) = y(0);
        scale = omega;
      }
    }
    if (G0.size() == 0) G0 = direct.solve(omega, unit_block);
    // A singular or non-finite Z (extreme parameters) leaves the factors unusable.
    if (G0.size() == 0)
      throw InputError("parameters: the dynamic stiffness at omega = " + std::to_string(omega) +
                       " cannot be factorized (parameters too extreme)");
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
    spectrum.push_back(total / scale / scale);
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
