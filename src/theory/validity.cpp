// Which spectrum theory holds where: the measured limits of docs/model.md §7.4.
#include <cmath>
#include <cstdio>
#include <iterator>
#include <utility>

#include "slidespec/theory.hpp"

namespace slidespec {

namespace {

std::string eps_text(double eps) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", eps);
  return text;
}

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

}  // namespace

double quasi_static_stall_fraction_max(double contacts) {
  double limit = 0;
  for (std::size_t k = 0; k < std::size(kQuasiStaticContacts); ++k)
    if (contacts >= kQuasiStaticContacts[k]) limit = kQuasiStaticStallFractionMax[k];
  return limit;
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
            "sliding at v, intermittently, and no theory is expected to hold (docs/model.md §9)"};
  if (l.forces_can_stall)
    return {TheoryKind::none,
            "alpha F_kin >= 2 (F_drive - F_kin): the random forces can stall the block (docs/model.md §8)"};
  const bool poisson = p.renewal == Renewal::poisson;
  const double first_limit = poisson ? kFirstOrderPoissonEpsMax : kFirstOrderPeriodicEpsMax;
  const double second_limit = poisson ? kSecondOrderPoissonEpsMax : kSecondOrderPeriodicEpsMax;
  std::string why_not_second;
  try {
    SecondOrderTheory{p};
    if (l.coupling_eps <= second_limit) return {TheoryKind::second_order, ""};
    why_not_second = "the second order holds to eps " + eps_text(second_limit) + " for " +
                     (poisson ? "poisson" : "periodic") + " renewal";
  } catch (const InputError& e) {
    why_not_second = e.what();
  }
  // The quasi-static spectrum: poisson renewal, one touching level, a constant force, and
  // not too near the stall, where the block's time is spent ever nearer standstill.
  const auto [near_stall, contacts] = stall_fraction(p);
  const double quasi_static_limit = quasi_static_stall_fraction_max(contacts);
  if (poisson && p.drive == Drive::force && near_stall > 0 && near_stall <= quasi_static_limit)
    return {TheoryKind::quasi_static, why_not_second};
  if (poisson && p.drive == Drive::force && near_stall > 0)
    why_not_second += ", the quasi-static spectrum to " + eps_text(quasi_static_limit) + " of the stall boundary for " +
                      eps_text(contacts) + " contacts (here " + eps_text(near_stall) + ")";
  if (l.coupling_eps <= first_limit) return {TheoryKind::first_order, why_not_second};
  return {TheoryKind::none, "eps = " + eps_text(l.coupling_eps) + ": " + why_not_second + ", the first order to " +
                                eps_text(first_limit) + " (docs/model.md §7.4)"};
}

}  // namespace slidespec
