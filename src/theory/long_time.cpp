// Mean speed and diffusion constant of the quasi-static block (docs/model.md §7):
// exactly, from a Laplace representation of 1/u, and as the O(eps^2) series, from the
// moments of the total random force up to the fourth.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "slidespec/theory.hpp"

namespace slidespec {

namespace {

// Probability that a contact with mean renewal distance a keeps its force over distance s
// is R(s): exp(-s/a) (poisson) or (1 - s/a)_+ (periodic with random phase). These are the
// integrals over s >= 0 of R_a and of R_a R_b.
double integral_of_keep(Renewal renewal, double a) { return renewal == Renewal::poisson ? a : a / 2; }

double integral_of_keep_both(Renewal renewal, double a, double b) {
  if (renewal == Renewal::poisson) return a * b / (a + b);
  const double shorter = std::min(a, b), longer = std::max(a, b);
  return shorter / 2 - shorter * shorter / (6 * longer);
}

// <1/u> over distance, exactly: 1/u = integral over t > 0 of exp(-t u), and a uniform force
// on [-b, b] Delta has E exp(t g / Delta) = sinh(t b) / (t b), so <1/u> = integral of
// exp(-t) prod_j sinh(t b_j) / (t b_j) dt, finite below the stall (sum_j b_j < 1).
double mean_inverse_speed(const std::vector<double>& contacts, const std::vector<double>& half_widths) {
  double reach = 0;
  for (std::size_t j = 0; j < contacts.size(); ++j) reach += contacts[j] * half_widths[j];
  if (!(reach < 1)) return std::numeric_limits<double>::infinity();  // the forces can stall the block
  const auto log_integrand = [&](double t) {
    double sum = -t;
    for (std::size_t j = 0; j < contacts.size(); ++j) {
      const double y = t * half_widths[j];
      // log(sinh(y) / y), without overflow and exact near y = 0.
      const double log_ratio = y < 1e-4 ? y * y / 6 : y + std::log(-std::expm1(-2 * y) / (2 * y));
      sum += contacts[j] * log_ratio;
    }
    return sum;
  };
  // Simpson's rule in log t from 1e-9 (the integrand is 1 there) to 60 decay lengths
  // exp(-(1 - reach) t): even steps in log t resolve both ends, near the stall too.
  const double first = std::log(1e-9), last = std::log(60 / (1 - reach));
  const int panels = 4000;
  const double h = (last - first) / panels;
  double sum = 1e-9;  // the integral up to the first point
  for (int k = 0; k <= panels; ++k) {
    const double weight = (k == 0 || k == panels) ? 1 : (k % 2 ? 4 : 2);
    const double t = std::exp(first + k * h);
    sum += weight * t * std::exp(log_integrand(t)) * h / 3;
  }
  return sum;
}

// Var over distance of the time to slide it, per unit distance, for one touching level
// (n contacts of renewal distance a, each force uniform on [-b, b] Delta): D_T v^2 =
// integral over s > 0 of Cov(1/u(0), 1/u(s)). With 1/u = integral of exp(-t u) dt and each
// contact keeping its force over s with probability R(s), this is the double integral over
// t1, t2 of exp(-t1 - t2) sum_k C(n, k) c_k (phi12 - phi1 phi2)^k (phi1 phi2)^(n-k), phi the
// uniform's E exp(t g / Delta), c_k a / k (poisson: R^k integrates so) or a / (k + 1) (periodic).
double quasi_static_time_diffusion(double n, double b, double a, Renewal renewal) {
  const double reach = n * b;
  const auto log_phi = [&](double t) {
    const double y = t * b;
    return y < 1e-4 ? y * y / 6 : y + std::log(-std::expm1(-2 * y) / (2 * y));
  };
  const int contacts = static_cast<int>(n);
  // Simpson's rule in log t from 1e-5 (the integrand vanishes as t1 t2 there) to 60 decay
  // lengths exp(-(1 - reach) t): even steps in log t resolve both ends near the stall.
  const double first = std::log(1e-5), last = std::log(60 / (1 - reach));
  const int panels = 400;
  const double h = (last - first) / panels;
  std::vector<double> t(panels + 1), weight(panels + 1);
  for (int i = 0; i <= panels; ++i) {
    t[static_cast<std::size_t>(i)] = std::exp(first + i * h);
    weight[static_cast<std::size_t>(i)] =
        t[static_cast<std::size_t>(i)] * ((i == 0 || i == panels) ? 1 : (i % 2 ? 4 : 2));
  }
  double sum = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    for (std::size_t j = 0; j < t.size(); ++j) {
      const double t1 = t[i], t2 = t[j];
      const double log_both = log_phi(t1) + log_phi(t2);
      const double log_excess = log_both + std::log(std::expm1(log_phi(t1 + t2) - log_both));
      double terms = 0, log_binomial = 0;
      for (int k = 1; k <= contacts; ++k) {
        log_binomial += std::log((n - k + 1) / k);
        const double c = renewal == Renewal::poisson ? 1.0 / k : 1.0 / (k + 1);
        const double term = c * std::exp(log_binomial + k * log_excess + (n - k) * log_both - t1 - t2);
        terms += term;
        if (term < 1e-17 * terms) break;  // the terms fall fast once past their peak
      }
      sum += weight[i] * weight[j] * terms;
    }
  }
  return a * sum * h * h / 9;
}

}  // namespace

LongTimeMotion long_time_motion(const Parameters& p, MotionTheory theory) {
  // The load point sets the speed and the spring's stretch stays bounded, in every theory.
  if (p.drive == Drive::spring) return {p.v, 0.0};
  const double drive_excess = p.F_drive - p.F_kin;
  const double d2 = drive_excess * drive_excess;
  struct Group {
    double contacts, s2, a;
  };
  std::vector<Group> groups;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) groups.push_back({static_cast<double>(p.blocks(l)), p.random_force_variance(l), p.level(l).a});

  // Cov over distance of 1/u(0), 1/u(s), u = 1 - G/Delta, integrated over s >= 0:
  // first / Delta^2 + second / Delta^4. Given the set K of contacts kept from 0 to s, with
  // A = sum over K (variance V_A, fourth cumulant k_A) and S the total variance, the Delta^-4
  // part is 2 Cov(G0, Gs^3) + Cov(G0^2, Gs^2) = 6 S V_A + 2 V_A^2 + 3 k_A.
  double total_variance = 0, fourth_cumulant = 0, first = 0, kept_cumulant = 0, kept_variance_squared = 0;
  for (const Group& g : groups) {
    // A uniform force has fourth cumulant -6/5 of its variance squared.
    const double k4 = -1.2 * g.s2 * g.s2;
    const double i1 = integral_of_keep(p.renewal, g.a);
    total_variance += g.contacts * g.s2;
    fourth_cumulant += g.contacts * k4;
    first += g.contacts * g.s2 * i1;
    kept_cumulant += g.contacts * k4 * i1;
    // E V_A^2 = (sum s2 R)^2 + sum s2^2 R (1 - R), integrated.
    kept_variance_squared += g.contacts * g.s2 * g.s2 * (i1 - integral_of_keep_both(p.renewal, g.a, g.a));
    for (const Group& h : groups)
      kept_variance_squared += g.contacts * h.contacts * g.s2 * h.s2 * integral_of_keep_both(p.renewal, g.a, h.a);
  }
  const double diffusion_1 = p.v * first / d2;
  if (theory == MotionTheory::first_order) return {p.v, diffusion_1};

  if (theory == MotionTheory::second_order) {
    const double e = total_variance / d2;  // eps^2 / 2
    const double inverse_speed = 1 + e + (3 * total_variance * total_variance + fourth_cumulant) / (d2 * d2);
    const double second = 6 * total_variance * first + 2 * kept_variance_squared + 3 * kept_cumulant;
    // D = V^3 D_T with D_T = (first/Delta^2 + second/Delta^4) / v^2, kept to relative O(e).
    return {p.v / inverse_speed, diffusion_1 * (1 + second / (first * d2) - 3 * e)};
  }

  std::vector<double> contacts, half_widths;
  for (const Group& g : groups) {
    contacts.push_back(g.contacts);
    half_widths.push_back(std::sqrt(3 * g.s2) / drive_excess);  // b Delta = alpha f_kin / 2
  }
  const double inverse_speed = mean_inverse_speed(contacts, half_widths);
  if (!std::isfinite(inverse_speed)) return {0, 0};
  if (groups.size() != 1)
    throw InputError("touching: the quasi-static diffusion is computed for one touching level only");
  const double speed = p.v / inverse_speed;
  const double time_diffusion =
      quasi_static_time_diffusion(contacts[0], half_widths[0], groups[0].a, p.renewal) / (p.v * p.v);
  return {speed, speed * speed * speed * time_diffusion};
}

}  // namespace slidespec
