// Which spectrum theory holds where: the measured limits of docs/model.md §7.4.
#include <cmath>
#include <cstdio>
#include <iterator>
#include <utility>

#include "slidespec/theory.hpp"
#include "util/numbers.hpp"

namespace slidespec {

namespace {

std::string eps_text(double eps) { return util::short_number(eps); }

// With one touching level: the largest resistance of its forces, all at once, over
// F_drive - F_kin (1 at the stall boundary, where it equals eps / eps_stall); 0 with several.
// Returns it with the number of touching contacts.
std::pair<double, double> stall_fraction(const Parameters& p) {
  int touching = 0;
  for (int level = 1; level <= p.levels; ++level)
    if (p.touches(level)) {
      if (touching != 0) return {0, 0};
      touching = level;
    }
  const double contacts = static_cast<double>(p.blocks(touching));
  return {contacts * std::sqrt(3 * p.random_force_variance(touching)) / (p.F_drive - p.F_kin), contacts};
}

// Whether x lies inside a measured limit. The limits are the map's grid values, which it
// keeps to 4 digits (0.95 of the stall boundary is eps 0.3167 for N = 6, 0.9501 of it).
bool inside(double x, double limit) { return x <= limit * (1 + 1e-3); }

// A limit measured at grid values of N, taken between them from the smaller grid N.
template <std::size_t n>
double limit_by_contacts(double contacts, const int (&grid)[n], const double (&limits)[n]) {
  double limit = 0;
  for (std::size_t k = 0; k < n; ++k)
    if (contacts >= grid[k]) limit = limits[k];
  return limit;
}

}  // namespace

double quasi_static_stall_fraction_max(double contacts) {
  return limit_by_contacts(contacts, kQuasiStaticContacts, kQuasiStaticStallFractionMax);
}

double spring_first_order_stall_fraction_max(Renewal renewal, double contacts, double stiffness) {
  if (renewal == Renewal::poisson)
    return stiffness >= kSpringPoissonStiffnessMin
               ? limit_by_contacts(contacts, kSpringFirstOrderContacts, kSpringPoissonStallFractionMax)
               : 0;
  return stiffness >= kSpringPeriodicStiffnessMin
             ? limit_by_contacts(contacts, kSpringFirstOrderContacts, kSpringPeriodicStallFractionMax)
             : 0;
}

const char* theory_kind_name(TheoryKind kind) {
  switch (kind) {
    case TheoryKind::second_order:
      return "second_order";
    case TheoryKind::quasi_static:
      return "quasi_static";
    case TheoryKind::first_order:
      return "first_order";
    case TheoryKind::none:
      break;
  }
  return "none";
}

TheoryChoice best_theory(const Parameters& p) {
  const Landmarks l = landmarks(p);
  if (l.forces_can_stall && p.drive == Drive::spring)
    return {TheoryKind::none,
            "alpha F_kin >= 2 (F_drive - F_kin): a constant force would stall the block; the spring keeps it "
            "sliding at v, intermittently, over times long enough for it to take up its range of stretch "
            "(docs/model.md §8), and no theory is expected to hold (docs/model.md §9)"};
  if (l.forces_can_stall)
    return {TheoryKind::none,
            "alpha F_kin >= 2 (F_drive - F_kin): the random forces can stall the block (docs/model.md §8)"};
  const bool poisson = p.renewal == Renewal::poisson;
  const double first_limit = poisson ? kFirstOrderPoissonEpsMax : kFirstOrderPeriodicEpsMax;
  const double second_limit = poisson ? kSecondOrderPoissonEpsMax : kSecondOrderPeriodicEpsMax;
  const auto [near_stall, contacts] = stall_fraction(p);
  if (p.drive == Drive::spring) {
    // The spring's first-order limits are measured for one touching level.
    const double stiffness = l.omega_s / l.renewal_rate;
    const double spring_limit =
        near_stall > 0 ? spring_first_order_stall_fraction_max(p.renewal, contacts, stiffness) : 0;
    const char* beyond_first = "no theory beyond the first order is derived for a spring (docs/model.md §9.1)";
    if ((near_stall > 0 && inside(near_stall, spring_limit)) || inside(l.coupling_eps, first_limit))
      return {TheoryKind::first_order, beyond_first};
    char why[400];
    std::snprintf(
        why, sizeof why,
        "eps = %.3g, omega_s = %.3g v/a: under a spring the first order holds to eps %.3g, and to %.3g of the "
        "stall boundary from omega_s = %.3g v/a (%s renewal; here %.3g of it); %s",
        l.coupling_eps, stiffness, first_limit,
        spring_first_order_stall_fraction_max(p.renewal, std::fmax(contacts, 2), INFINITY),
        poisson ? kSpringPoissonStiffnessMin : kSpringPeriodicStiffnessMin, poisson ? "poisson" : "periodic",
        near_stall, beyond_first);
    return {TheoryKind::none, why};
  }
  std::string why_not_second;
  try {
    SecondOrderTheory{p};
    if (inside(l.coupling_eps, second_limit)) return {TheoryKind::second_order, ""};
    why_not_second = "the second order holds to eps " + eps_text(second_limit) + " for " +
                     (poisson ? "poisson" : "periodic") + " renewal";
  } catch (const InputError& e) {
    why_not_second = e.what();
  }
  // The quasi-static spectrum: poisson renewal, one touching level, a constant force, and
  // not too near the stall, where the block's time is spent ever nearer standstill.
  const double quasi_static_limit = quasi_static_stall_fraction_max(contacts);
  if (poisson && near_stall > 0 && inside(near_stall, quasi_static_limit))
    return {TheoryKind::quasi_static, why_not_second};
  if (poisson && near_stall > 0)
    why_not_second += ", the quasi-static spectrum to " + eps_text(quasi_static_limit) + " of the stall boundary for " +
                      eps_text(contacts) + " contacts (here " + eps_text(near_stall) + ")";
  if (inside(l.coupling_eps, first_limit)) return {TheoryKind::first_order, why_not_second};
  return {TheoryKind::none, "eps = " + eps_text(l.coupling_eps) + ": " + why_not_second + ", the first order to " +
                                eps_text(first_limit) + " (docs/model.md §7.4)"};
}

TheoryChoice best_theory_at(const Parameters& p, double omega) {
  TheoryChoice band = best_theory(p);
  if (band.kind == TheoryKind::second_order || band.kind == TheoryKind::quasi_static) return band;
  const Landmarks l = landmarks(p);
  if (omega < kHighRenewalRates * l.renewal_rate || p.renewal != Renewal::periodic || p.drive != Drive::force ||
      l.forces_can_stall || !inside(l.coupling_eps, kSecondOrderPeriodicHighEpsMax))
    return band;
  try {
    SecondOrderTheory{p};
  } catch (const InputError&) {
    return band;
  }
  return {TheoryKind::second_order, ""};
}

}  // namespace slidespec
