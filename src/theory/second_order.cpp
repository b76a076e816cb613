// The second-order force spectrum of docs/model.md §7. Poisson renewal: in time, the
// renewals of the quasi-static block form a Markov process with generator v u(G) L, and a
// second-order resolvent expansion of its velocity spectrum gives Phi below. Periodic
// renewal (§7.2): the spectrum is the Fourier transform of the characteristic function of
// the travel time over a distance, whose cumulants are those of sums of box lengths; the
// Gaussian part is kept whole, the rest taken to O(eps^2).
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <initializer_list>
#include <optional>

#include "slidespec/theory.hpp"
#include "theory/quadrature.hpp"

namespace slidespec {

namespace {

using Complex = std::complex<double>;

// Periodic renewal, distances in units of a (x = r / a), one contact, its force's
// variance 1. Each function is a mean over the random phase of the renewal marks, in
// closed form (docs/model.md §7.2); beyond x = 2 all but the phase variance are linear.

// E sum of squared box lengths within [0, x]: the variance of the force's integral.
double box_squares(double x) { return x < 1 ? x * x - x * x * x / 3 : x - 1.0 / 3; }
// E sum of cubes and of fourth powers.
double box_cubes(double x) { return x < 1 ? x * x * x * (1 - x / 2) : x - 0.5; }
double box_fourths(double x) { return x < 1 ? x * x * x * x * (1 - 0.6 * x) : x - 0.6; }
// int int over [0, x]^2 of the probability that two contacts both keep their force.
double kept_pair_squares(double x) { return x < 1 ? x * x * (1 - x * (2.0 / 3 - x / 6)) : 2 * x / 3 - 1.0 / 6; }
// int_0^x ds (int_0^x R(|s - s'|) ds')^2, R = (1 - d)_+.
double kept_overlap_squares(double x) {
  if (x < 1) return x * x * x * (1 - x * (2.0 / 3 - 7 * x / 60));
  if (x < 2) return -1.0 / 30 + x * (-1.0 / 3 + x * (4.0 / 3 + x * (-2.0 / 3 + x * (1.0 / 6 - x / 60))));
  return x - 17.0 / 30;
}
// The fourth Bernoulli polynomial: the phase variance's periodic part is -B4 / 3.
double bernoulli4(double b) { return b * b * (b * (b - 2) + 1) - 1.0 / 30; }
// Var over the phase of the sum of squared box lengths: 1/90 - B4(x mod 1) / 3 beyond x = 1.
double box_squares_variance(double x) {
  if (x < 1) return x * x * x * x * x * (2.0 / 15 - x / 9);
  return 1.0 / 90 - bernoulli4(x - std::floor(x)) / 3;
}

// 16-point Gauss-Legendre nodes and weights on [-1, 1].
struct GaussLegendre {
  std::array<double, 16> x, w;
  GaussLegendre() {
    std::vector<double> nodes, weights;
    theory_detail::gauss_legendre_rule(16, nodes, weights);
    std::copy(nodes.begin(), nodes.end(), x.begin());
    std::copy(weights.begin(), weights.end(), w.begin());
  }
};

const GaussLegendre& gauss_legendre() {
  static const GaussLegendre rule;
  return rule;
}

// int_lo^hi f(x) dx over subintervals short enough in phase for 16 nodes.
template <typename F>
Complex integrate(F&& f, double lo, double hi, double phase_rate) {
  if (hi <= lo) return 0;
  const int pieces = 1 + static_cast<int>(phase_rate * (hi - lo) / 2.5);
  const GaussLegendre& rule = gauss_legendre();
  const double h = (hi - lo) / pieces;
  Complex sum = 0;
  for (int j = 0; j < pieces; ++j) {
    const double mid = lo + (j + 0.5) * h;
    for (int i = 0; i < 16; ++i) sum += rule.w[i] * f(mid + 0.5 * h * rule.x[i]);
  }
  return 0.5 * h * sum;
}

// Truncated power series in x - x0 with complex coefficients.
constexpr int kOrders = 32;
using Series = std::array<Complex, kOrders>;

Series polynomial(std::initializer_list<double> coefficients) {
  Series s{};
  int k = 0;
  for (double c : coefficients) s[k++] = c;
  return s;
}
// The same polynomial about x0 (coefficients of (x - x0)^k).
Series shifted(const Series& p, double x0) {
  Series out{};
  for (int n = kOrders - 1; n >= 0; --n) {  // Horner: out = out * (t + x0) + p[n]
    for (int k = kOrders - 1; k >= 1; --k) out[k] = out[k] * x0 + out[k - 1];
    out[0] = out[0] * x0 + p[n];
  }
  return out;
}
Series times(const Series& a, const Series& b) {
  Series out{};
  for (int i = 0; i < kOrders; ++i)
    for (int j = 0; i + j < kOrders; ++j) out[i + j] += a[i] * b[j];
  return out;
}
Series exp_of(const Series& f) {  // g = exp(f): (n + 1) g_{n+1} = sum_k (k + 1) f_{k+1} g_{n-k}
  Series g{};
  g[0] = std::exp(f[0]);
  for (int n = 0; n + 1 < kOrders; ++n) {
    Complex sum = 0;
    for (int k = 0; k <= n; ++k) sum += static_cast<double>(k + 1) * f[k + 1] * g[n - k];
    g[n + 1] = sum / static_cast<double>(n + 1);
  }
  return g;
}
Series linear(const Series& a, Complex ca, const Series& b, Complex cb) {
  Series out{};
  for (int k = 0; k < kOrders; ++k) out[k] = ca * a[k] + cb * b[k];
  return out;
}
// int_x0^inf e^{-p x} f(x) dx from x0's end alone: e^{-p x0} sum_k k! f_k / p^(k+1).
Complex endpoint_sum(const Series& f, Complex p) {
  Complex sum = 0, factor = 1.0 / p;
  for (int k = 0; k < kOrders; ++k) {
    sum += f[k] * factor;
    factor *= static_cast<double>(k + 1) / p;
  }
  return sum;
}

// The pieces below x = 1 as polynomials in x.
const Series& squares_below_one() {
  static const Series s = polynomial({0, 0, 1, -1.0 / 3});
  return s;
}

// The travel time over distance x a is T = (x a + X) / v with X the distance-integral of
// 1/u - 1; its characteristic function exp(i k c1 r - k^2 e W / 2) (1 + rest) to O(eps^2)
// beyond the Gaussian, k = omega / v. The returned J is int_0^inf of it over x, so that
// the force spectrum is (F_drive - F_kin)^2 V a / (pi v^2) Re J. Near x = 0 the Gaussian
// would give the local speed a Gaussian law, stalls included, whose spurious weight swamps
// the spectrum far above v/a; there the series is taken to O(eps^2) as it stands, and the
// Gaussian kept whole only from the first kink (x = 1) on, where it damps the ripple.
struct PeriodicSecondOrder {
  double e;        // N s2 / (F_drive - F_kin)^2 = eps^2 / 2
  double speedup;  // v / V - 1
  // Coefficients of the non-Gaussian rest (force variance 1, kurtosis = k4 / s2^2).
  double pairs_linear, pairs_squared, cubes_one, cubes_two, fourths;
  double kurtosis;

  PeriodicSecondOrder(double contacts, double kurtosis_ratio, double e_, double speedup_)
      : e(e_), speedup(speedup_), kurtosis(kurtosis_ratio) {
    const double n = contacts, e2 = e * e;
    // Var of int (G/D)^2 + 2 Cov(int G/D, int (G/D)^3), and the third and fourth cumulants.
    pairs_linear = e2 * (6 + (2 + 3 * kurtosis) / n);
    pairs_squared = 2 * e2 * (1 - 1 / n);
    cubes_one = e2 * (2 + kurtosis) / n;
    cubes_two = 2 * e2 * (1 - 1 / n);
    fourths = e2 / n;
  }

  Complex rest(double kappa, double x, double variance_of_squares) const {
    const double k2 = kappa * kappa;
    const double second = -0.5 * k2 * (pairs_linear * box_squares(x) + pairs_squared * kept_pair_squares(x));
    const double third = -0.5 * k2 * kappa * (cubes_one * box_cubes(x) + cubes_two * kept_overlap_squares(x));
    const double fourth = k2 * k2 / 24 * fourths * (kurtosis * box_fourths(x) + 3 * variance_of_squares);
    return Complex(second + fourth, third);
  }

  // rest below x = 1 as a polynomial in x.
  Series rest_below_one(double kappa) const {
    const double k2 = kappa * kappa;
    const Series squares = squares_below_one(), pair_squares = polynomial({0, 0, 1, -2.0 / 3, 1.0 / 6}),
                 cubes = polynomial({0, 0, 0, 1, -0.5}), fourths_ = polynomial({0, 0, 0, 0, 1, -0.6}),
                 overlaps = polynomial({0, 0, 0, 1, -2.0 / 3, 7.0 / 60}),
                 variance = polynomial({0, 0, 0, 0, 0, 2.0 / 15, -1.0 / 9});
    Series r{};
    for (int k = 0; k < kOrders; ++k)
      r[k] = Complex(-0.5 * k2 * (pairs_linear * squares[k].real() + pairs_squared * pair_squares[k].real()) +
                         k2 * k2 / 24 * fourths * (kurtosis * fourths_[k].real() + 3 * variance[k].real()),
                     -0.5 * k2 * kappa * (cubes_one * cubes[k].real() + cubes_two * overlaps[k].real()));
    return r;
  }

  // int_0^1 e^{i kappa x} F(x) dx far above kappa ~ 1 (see above): the O(eps^2) series from
  // x = 0, less the Gaussian-kept series from x = 1 (negligible once kappa e >= 1.5).
  Complex below_one_from_ends(double kappa) const {
    const Complex p(0, -kappa), ik(0, kappa);
    const Series squares = squares_below_one(), rest = rest_below_one(kappa);
    // O(eps^2): exp(i k c1 x - k^2 e W / 2) expanded, c1 = e + O(e^2).
    const Series x = polynomial({0, 1});
    const Series phase = linear(x, ik * speedup, squares, -0.5 * kappa * kappa * e);
    const Series ex = linear(x, ik * e, squares, -0.5 * kappa * kappa * e);  // its O(e) part
    Series plain = linear(phase, 1.0, times(ex, ex), 0.5);
    plain[0] += 1.0;
    Complex J = endpoint_sum(linear(plain, 1.0, rest, 1.0), p);
    if (kappa * e < 1.5) {
      const Series exponent = shifted(phase, 1.0);
      const Series gauss = exp_of(exponent);
      Series kept = times(gauss, shifted(rest, 1.0));
      for (int k = 0; k < kOrders; ++k) kept[k] += gauss[k];
      J -= std::exp(-p) * endpoint_sum(kept, p);
    }
    return J;
  }

  // Re J at kappa = omega a / v.
  double operator()(double kappa) const {
    const double phase_rate = kappa * (1 + speedup), damping = 0.5 * kappa * kappa * e;
    const auto integrand = [&](double x) {
      const Complex gauss = std::exp(Complex(-damping * box_squares(x), phase_rate * x));
      return gauss * (1.0 + rest(kappa, x, box_squares_variance(x)));
    };
    // Between kappa = 4 and 8 the two forms of [0, 1] are blended (docs/model.md §7.2).
    const double blend = std::clamp((kappa - kBlendFrom) / (kBlendTo - kBlendFrom), 0.0, 1.0);
    Complex J = 0;
    if (blend < 1) J += (1 - blend) * integrate(integrand, 0, 1, phase_rate);
    if (blend > 0) J += blend * below_one_from_ends(kappa);
    // Beyond W(x) = 72 / (kappa^2 e) the Gaussian factor is below e^-36.
    if (damping * box_squares(1) > 36) return J.real();
    double end = 2;
    if (damping * box_squares(2) > 36) end = 1.0 / 3 + 36 / damping;
    J += integrate(integrand, 1, end, phase_rate);
    if (end == 2) {
      // x >= 2: the Gaussian factor is exp(damping / 3 - q x), the rest linear in x plus the
      // periodic part of the phase variance, summed over periods.
      const Complex q(damping, -phase_rate);
      const Complex at2 = std::exp(damping / 3 - 2.0 * q);
      const Complex r2 = rest(kappa, 2, 1.0 / 90), slope = rest(kappa, 3, 1.0 / 90) - r2;
      J += at2 * ((1.0 + r2) / q + slope / (q * q));
      const double k4 = kappa * kappa * kappa * kappa;
      const Complex period = integrate(
          [&](double b) { return std::exp(-q * b) * (-k4 / 24 * fourths * bernoulli4(b)); }, 0, 1, phase_rate);
      J += at2 / (1.0 - std::exp(-q)) * period;
    }
    return J.real();
  }

  static constexpr double kBlendFrom = 4, kBlendTo = 8;
};

}  // namespace

struct SecondOrderTheory::Impl {
  LumpedTheory first_order;
  Renewal renewal;
  double contacts, s2, k4, rate, drive_excess2;
  // Periodic renewal: the block's response from a poisson twin, whose force spectrum has
  // no zeros (the response does not depend on the renewal kind).
  Parameters twin;
  std::optional<LumpedTheory> twin_theory;
  std::optional<PeriodicSecondOrder> periodic;
  double mean_speed = 0, level = 1;

  explicit Impl(const Parameters& p) : first_order(p), renewal(p.renewal), twin(p) {
    const int touching = theory_detail::single_touching_level(p, "the second-order theory");
    level = touching;
    contacts = static_cast<double>(p.blocks(touching));
    s2 = p.random_force_variance(touching);
    k4 = -1.2 * s2 * s2;  // a uniform force's fourth cumulant
    rate = p.renewal_rate(touching);
    drive_excess2 = (p.F_drive - p.F_kin) * (p.F_drive - p.F_kin);
    if (renewal == Renewal::periodic) {
      const double eps = landmarks(p).coupling_eps;
      if (eps > kSecondOrderPeriodicComputedEpsMax) {
        char message[160];
        std::snprintf(
            message, sizeof message,
            "eps: the second-order theory of periodic renewal is computed to eps %.2f (here %.3f; docs/model.md §7.2)",
            kSecondOrderPeriodicComputedEpsMax, eps);
        throw InputError(message);
      }
      twin.renewal = Renewal::poisson;
      twin_theory.emplace(twin);
      mean_speed = long_time_motion(p, MotionTheory::second_order).mean_speed;
      periodic.emplace(contacts, k4 / (s2 * s2), contacts * s2 / drive_excess2, p.v / mean_speed - 1);
    }
  }

  double poisson_ratio(double omega) const {
    const double n = contacts, S = n * s2, lambda = rate, d2 = drive_excess2;
    const Complex z1 = Complex(lambda, -omega), z2 = Complex(2 * lambda, -omega);  // z + lambda, z + 2 lambda
    // One renewing contact (g^2 - s2 carried once), two (g_i g_j), and the time weight 1/u.
    const double one = n * (2 * s2 * s2 + k4), two = n * (n - 1) * s2 * s2;
    const Complex phi = (S + (2 * S * S + n * k4) / d2) / z1 + lambda / d2 * (one / (z1 * z1) + 2 * two / (z1 * z2)) +
                        lambda * lambda / d2 * (one / (z1 * z1 * z1) + 4 * two / (z1 * z1 * z2));
    const double e = S / d2;
    return (phi / (1 + e)).real() / (S / z1).real();
  }

  // C_F to second order, periodic renewal [N^2 s].
  double periodic_force_spectrum(double omega) const {
    const double v = twin.v, a = v / rate;
    return drive_excess2 * mean_speed * a / (M_PI * v * v) * (*periodic)(omega * a / v);
  }

  double value(double omega) const {
    if (renewal == Renewal::poisson) return first_order(omega) * poisson_ratio(omega);
    const double response =
        (*twin_theory)(omega) / (contacts * random_force_spectrum(twin, static_cast<int>(level), omega));
    return response * periodic_force_spectrum(omega);
  }
};

namespace {
// Checked before any of the expansion is built.
const Parameters& driven_by_force(const Parameters& p) {
  if (p.drive == Drive::spring)
    throw InputError(
        "order: the second-order theory is derived for a constant drive force; drive=spring has the first order only");
  return p;
}
}  // namespace

SecondOrderTheory::SecondOrderTheory(const Parameters& p) : impl_(std::make_shared<const Impl>(driven_by_force(p))) {}

double SecondOrderTheory::operator()(double omega) const { return impl_->value(omega); }

double SecondOrderTheory::ratio(double omega) const {
  if (impl_->renewal == Renewal::poisson) return impl_->poisson_ratio(omega);
  return impl_->value(omega) / impl_->first_order(omega);
}

}  // namespace slidespec
