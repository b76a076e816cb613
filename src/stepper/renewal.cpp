#include "stepper/renewal.hpp"

#include <Random123/philox.h>

#include <cmath>
#include <stdexcept>

#include "model/linear_structure.hpp"

namespace slidespec::stepper {

namespace {
constexpr double two_to_minus_53 = 1.0 / 9007199254740992.0;
constexpr std::int64_t two_to_52 = std::int64_t{1} << 52;
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

void RenewalState::renew_passed(int lane, double x) {
  const int* tree = tree_.data() + static_cast<size_t>(2 * leaves_) * lane;
  while (next_mark_[lane] <= x) {
    const int j = tree[1];
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
  }
  publish_inputs(lane);
}

}  // namespace slidespec::stepper
