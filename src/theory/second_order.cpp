// The second-order force spectrum of docs/model.md §7: in time, the poisson
// renewals of the quasi-static block form a Markov process with generator v u(G) L, and a
// second-order resolvent expansion of its velocity spectrum gives Phi below.
#include <complex>

#include "slidespec/theory.hpp"

namespace slidespec {

namespace {

int touching_level(const Parameters& p) {
  int found = 0;
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) {
      if (found != 0) throw InputError("touching: the second-order theory needs one touching level");
      found = l;
    }
  return found;
}

}  // namespace

SecondOrderTheory::SecondOrderTheory(const Parameters& p) : first_order_(p) {
  if (p.renewal != Renewal::poisson) throw InputError("renewal: the second-order theory needs renewal=poisson");
  const int level = touching_level(p);
  contacts_ = static_cast<double>(p.blocks(level));
  s2_ = p.random_force_variance(level);
  k4_ = -1.2 * s2_ * s2_;  // a uniform force's fourth cumulant
  rate_ = p.renewal_rate(level);
  drive_excess2_ = (p.F_drive - p.F_kin) * (p.F_drive - p.F_kin);
}

double SecondOrderTheory::ratio(double omega) const {
  using Complex = std::complex<double>;
  const double n = contacts_, s2 = s2_, S = n * s2, lambda = rate_, d2 = drive_excess2_;
  const Complex z1 = Complex(lambda, -omega), z2 = Complex(2 * lambda, -omega);  // z + lambda, z + 2 lambda
  // One renewing contact (g^2 - s2 carried once), two (g_i g_j), and the time weight 1/u.
  const double one = n * (2 * s2 * s2 + k4_), two = n * (n - 1) * s2 * s2;
  const Complex phi = (S + (2 * S * S + n * k4_) / d2) / z1 + lambda / d2 * (one / (z1 * z1) + 2 * two / (z1 * z2)) +
                      lambda * lambda / d2 * (one / (z1 * z1 * z1) + 4 * two / (z1 * z1 * z2));
  const double e = S / d2;
  return (phi / (1 + e)).real() / (S / z1).real();
}

}  // namespace slidespec
