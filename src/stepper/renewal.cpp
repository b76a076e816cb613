#include "stepper/renewal.hpp"

#include <Random123/philox.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "model/linear_structure.hpp"
#include "stepper/exact_step.hpp"

namespace slidespec::stepper {

namespace {
constexpr double two_to_minus_53 = 1.0 / 9007199254740992.0;
constexpr std::int64_t two_to_52 = std::int64_t{1} << 52;

// std::llround for 0 <= x < 2^52 (ties away from zero), without the library call:
// the truncation and the fraction x - t are exact there.
std::int64_t round_half_away(double x) {
  const auto t = static_cast<std::int64_t>(x);
  return t + (x - static_cast<double>(t) >= 0.5 ? 1 : 0);
}
}  // namespace

RenewalDraw draw_renewal(std::uint64_t seed, std::uint64_t stream, std::uint64_t realization,
                         std::uint64_t contact, std::uint64_t renewal_count) {
  r123::Philox4x64 philox;
  const r123::Philox4x64::ctr_type counter = {{realization, contact, renewal_count, 0}};
  const r123::Philox4x64::key_type key = {{seed, stream}};
  const auto bits = philox(counter, key);
  const std::uint64_t force_bits = bits[0] >> 11;  // 53 random bits
  RenewalDraw draw;
  draw.force_uniform = static_cast<double>(force_bits) * two_to_minus_53;
  draw.force_units = static_cast<std::int64_t>(force_bits) - two_to_52;
  draw.spacing_uniform = static_cast<double>(bits[1] >> 11) * two_to_minus_53;
  return draw;
}

RenewalState::RenewalState(const std::vector<model::Contact>& contacts,
                           const std::vector<int>& class_of_contact, Renewal renewal,
                           std::uint64_t seed, std::uint64_t stream,
                           std::uint64_t first_realization, int lanes)
    : poisson_(renewal == Renewal::poisson),
      seed_(seed),
      stream_(stream),
      first_(first_realization),
      lanes_(lanes),
      contacts_(static_cast<int>(class_of_contact.size())),
      inputs_(0),
      leaves_(1),
      class_of_contact_(class_of_contact) {
  for (int c : class_of_contact_) inputs_ = std::max(inputs_, c);
  if (contacts.size() != class_of_contact.size())
    throw std::invalid_argument("renewal: one class per contact expected");
  force_unit_.assign(static_cast<size_t>(inputs_), 0.0);
  for (int j = 0; j < contacts_; ++j) {
    const double unit = contacts[j].random_force_amplitude * two_to_minus_53;
    double& class_unit = force_unit_[static_cast<size_t>(class_of_contact_[j] - 1)];
    if (class_unit != 0.0 && class_unit != unit)
      throw std::invalid_argument("renewal: the contacts of an input class differ in force amplitude");
    class_unit = unit;
    renewal_distance_.push_back(contacts[j].renewal_distance);
  }
  while (leaves_ < contacts_) leaves_ *= 2;
  const size_t cells = static_cast<size_t>(contacts_) * lanes_;
  force_units_.assign(cells, 0);
  mark_.assign(cells, 0.0);
  count_.assign(cells, 0);
  input_units_.assign(static_cast<size_t>(inputs_) * lanes_, 0);
  input_forces_.assign(static_cast<size_t>(inputs_) * lanes_, 0.0);
  next_mark_.assign(lanes_, 0.0);
  renewals_.assign(lanes_, 0);
  jump_energy_.assign(lanes_, 0.0);
  tree_.assign(static_cast<size_t>(2 * leaves_) * lanes_, -1);
  tree_mark_.assign(static_cast<size_t>(2 * leaves_) * lanes_, INFINITY);  // empty leaves never win

  // Stationary start: fresh forces; the first mark is where a stationary renewal process
  // puts it ahead of x = 0 (memoryless exponential for Poisson, uniform phase for periodic).
  for (int lane = 0; lane < lanes_; ++lane) {
    for (int j = 0; j < contacts_; ++j) {
      const RenewalDraw d = draw_renewal(seed_, stream_, first_ + lane, j, 0);
      const size_t cell = static_cast<size_t>(j) * lanes_ + lane;
      force_units_[cell] = d.force_units;
      mark_[cell] = poisson_ ? -renewal_distance_[j] * std::log1p(-d.spacing_uniform)
                             : renewal_distance_[j] * d.spacing_uniform;
      update_tree(lane, j);
    }
    refresh_inputs(lane);
  }
}

void RenewalState::update_tree(int lane, int contact) {
  // Tournament tree over the contacts' marks: each node holds the contact with the
  // earliest mark below it (and that mark), so finding and replacing the next renewal
  // costs O(log N). Walking up, the new winner stays in registers and only the
  // siblings are read: their loads do not wait on the level below, so the chain per
  // level is one compare and select (it was load, load, compare, store per level).
  const size_t base = static_cast<size_t>(2 * leaves_) * lane;
  int* tree = tree_.data() + base;
  double* tree_mark = tree_mark_.data() + base;
  int node = leaves_ + contact;
  int winner = contact;
  double winner_mark = mark_[static_cast<size_t>(contact) * lanes_ + lane];
  tree[node] = winner;
  tree_mark[node] = winner_mark;
  for (; node > 1; node /= 2) {
    const int sibling = tree[node ^ 1];
    const double sibling_mark = tree_mark[node ^ 1];
    // Ties go to the left child, as they always have: the renewal order is part of the trajectory.
    const bool take_sibling = (node & 1) == 0 ? sibling_mark < winner_mark : !(winner_mark < sibling_mark);
    winner = take_sibling ? sibling : winner;
    winner_mark = take_sibling ? sibling_mark : winner_mark;
    tree[node / 2] = winner;
    tree_mark[node / 2] = winner_mark;
  }
  next_mark_[lane] = winner_mark;
}

void RenewalState::refresh_inputs(int lane) {
  for (int k = 0; k < inputs_; ++k) input_units_[static_cast<size_t>(k) * lanes_ + lane] = 0;
  for (int j = 0; j < contacts_; ++j)
    input_units_[static_cast<size_t>(class_of_contact_[j] - 1) * lanes_ + lane] +=
        force_units_[static_cast<size_t>(j) * lanes_ + lane];
  publish_inputs(lane);
}

void RenewalState::publish_inputs(int lane) {
  for (int k = 0; k < inputs_; ++k) {
    const size_t cell = static_cast<size_t>(k) * lanes_ + lane;
    input_forces_[cell] = force_unit_[static_cast<size_t>(k)] * static_cast<double>(input_units_[cell]);
  }
}

void RenewalState::renew_next(int lane) {
  const int j = tree_[static_cast<size_t>(2 * leaves_) * lane + 1];
  const size_t cell = static_cast<size_t>(j) * lanes_ + lane;
  const std::uint64_t count = ++count_[cell];
  const RenewalDraw d = draw_renewal(seed_, stream_, first_ + lane, j, count);
  const size_t input_class = static_cast<size_t>(class_of_contact_[j] - 1);
  const size_t input = input_class * lanes_ + lane;
  const std::int64_t jump = d.force_units - force_units_[cell];
  input_units_[input] += jump;
  const double unit = force_unit_[input_class];
  jump_energy_[lane] += (unit * static_cast<double>(jump)) * (unit * static_cast<double>(jump));
  force_units_[cell] = d.force_units;
  const double spacing = renewal_distance_[static_cast<size_t>(j)];
  mark_[cell] += poisson_ ? -spacing * std::log1p(-d.spacing_uniform) : spacing;
  ++renewals_[lane];
  update_tree(lane, j);
  publish_inputs(lane);
}

void RenewalState::step_with_renewals(int lane, const ExactStep& step, double steady_start,
                                      double steady_end, double advance, double xi_start, double* z,
                                      double& increment) {
  switch (step.dimension + 1) {
    case 4: return step_shaped<4>(lane, step, steady_start, steady_end, advance, xi_start, z, increment);
    case 6: return step_shaped<6>(lane, step, steady_start, steady_end, advance, xi_start, z, increment);
    case 8: return step_shaped<8>(lane, step, steady_start, steady_end, advance, xi_start, z, increment);
    default: throw std::logic_error("renewal step: shape not compiled");
  }
}

// The state's size known at compile time: the copies of y, done several times per
// renewal, are a few moves instead of a max_state-wide copy.
template <int State>
void RenewalState::step_shaped(int lane, const ExactStep& step, double steady_start, double steady_end,
                               double advance, double xi_start, double* z, double& increment) {
  constexpr std::int64_t whole = std::int64_t{1} << ExactStep::fraction_bits;
  const double tick = 1.0 / static_cast<double>(whole);  // time unit: dt 2^-fraction_bits
  constexpr int state = State;
  const int velocity = 1 + step.velocity_component;
  constexpr int room = ExactStep::max_state;  // advance_partial may use all of it as scratch
  double g[8] = {}, y_now[room], y[room], y_end[room];
  auto forces = [&] {
    for (int k = 0; k < inputs_; ++k) g[k] = input_forces_[static_cast<size_t>(k) * lanes_ + lane];
  };
  auto copy = [](const double* from, double* to) { std::memcpy(to, from, sizeof(double) * state); };
  auto x_at = [&](std::int64_t n, const double* y_n) {
    return steady_start + advance * (static_cast<double>(n) * tick) + (xi_start + y_n[0]);
  };
  auto rate = [&](const double* y_n) { return advance + y_n[velocity] * step.dt; };  // dx/dt times dt
  forces();
  // y = (xi - xi_n, z) now and at the step's end; the plain step's end is the caller's.
  y_now[0] = 0.0;
  y_end[0] = increment;
  for (int r = 1; r < state; ++r) y_now[r] = y_end[r] = z[r - 1];
  bool renewed = false;
  std::int64_t now = 0;  // the time reached, in ticks
  double x_now = steady_start + xi_start;
  double x_end = steady_end + (xi_start + increment);
  while (x_end >= next_mark_[lane]) {
    const double mark = next_mark_[lane];
    // The crossing time: the cubic through x and dx/dt at both ends of what is left of the
    // step (solved by Newton from the linear guess), then one Newton step on the exact
    // trajectory, whose error is second order in the cubic's.
    const double left = static_cast<double>(whole - now) * tick;
    const double m0 = rate(y_now) * left, m1 = rate(y_end) * left;
    double u = x_end > x_now ? (mark - x_now) / (x_end - x_now) : 1.0;
    for (int iteration = 0; iteration < 3; ++iteration) {
      u = std::min(1.0, std::max(0.0, u));
      const double u2 = u * u, u3 = u2 * u;
      const double cubic = (2 * u3 - 3 * u2 + 1) * x_now + (u3 - 2 * u2 + u) * m0 + (3 * u2 - 2 * u3) * x_end +
                           (u3 - u2) * m1;
      const double slope = (6 * u2 - 6 * u) * x_now + (3 * u2 - 4 * u + 1) * m0 + (6 * u - 6 * u2) * x_end +
                           (3 * u2 - 2 * u) * m1;
      if (!(slope > 0)) break;
      const double correction = (cubic - mark) / slope;
      u -= correction;
      if (correction == 0) break;  // a fixed point: further iterations would repeat it
    }
    u = std::min(1.0, std::max(0.0, u));
    std::int64_t cross = now + round_half_away(u * static_cast<double>(whole - now));
    copy(y_now, y);
    step.advance_partial(cross - now, y, g);
    if (rate(y) > 0) {
      const double ticks = std::nearbyint((x_at(cross, y) - mark) / rate(y) * static_cast<double>(whole));
      const auto refined = static_cast<std::int64_t>(
          std::clamp(static_cast<double>(cross) - ticks, static_cast<double>(now), static_cast<double>(whole)));
      if (refined != cross) {
        cross = refined;
        copy(y_now, y);
        step.advance_partial(cross - now, y, g);
      }
    }
    copy(y, y_now);
    now = cross;
    x_now = x_at(now, y_now);
    renew_next(lane);
    forces();
    renewed = true;
    copy(y_now, y_end);
    step.advance_partial(whole - now, y_end, g);
    x_end = steady_end + (xi_start + y_end[0]);
  }
  if (!renewed) return;
  increment = y_end[0];
  for (int r = 1; r < state; ++r) z[r - 1] = y_end[r];
}

}  // namespace slidespec::stepper
