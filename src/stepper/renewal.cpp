#include "stepper/renewal.hpp"

#include <Random123/philox.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "model/linear_structure.hpp"
#include "stepper/kernel.hpp"

namespace slidespec::stepper {

namespace {
struct ScalarDraw {
  double force;                // units
  std::uint64_t contact_word;  // chooses the contact: floor(word N / 2^32)
  double spacing;              // -log u: the distance to the next mark in mean spacings
};
}  // namespace

namespace draw {

Words words(std::uint64_t seed, std::uint64_t stream, std::uint64_t realization, std::uint32_t tag,
            std::uint64_t event) {
  r123::Philox4x32 philox;
  const r123::Philox4x32::ctr_type counter = {
      {static_cast<std::uint32_t>(event), static_cast<std::uint32_t>((event >> 32) | tag << 16 | stream << 24),
       static_cast<std::uint32_t>(realization), static_cast<std::uint32_t>(realization >> 32)}};
  const r123::Philox4x32::key_type key = {{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
  const auto out = philox(counter, key);
  return {out[0], out[1], out[2], out[3]};
}

double open_uniform(std::uint32_t word2, std::uint32_t word3) {
  // 1.m with 52 random mantissa bits is uniform on [1, 2) in steps of 2^-52; 2 - it is exact.
  const std::uint64_t bits = std::uint64_t{word2} << 20 | word3 >> 12;
  return 2.0 - std::bit_cast<double>(bits | 0x3ff0000000000000u);
}

}  // namespace draw

RenewalState::RenewalState(const std::vector<model::Contact>& contacts, const std::vector<int>& class_of_contact,
                           Renewal renewal, std::uint64_t seed, std::uint64_t stream, std::uint64_t first_realization,
                           int lanes) {
  if (contacts.size() != class_of_contact.size())
    throw std::invalid_argument("renewal: one class per contact expected");
  if (stream > draw::max_stream) throw std::invalid_argument("renewal: stream beyond 255");
  RenewalLanes& v = view_;
  v.lanes = lanes;
  v.periodic = renewal == Renewal::periodic;
  v.key[0] = static_cast<std::uint32_t>(seed);
  v.key[1] = static_cast<std::uint32_t>(seed >> 32);
  v.stream_bits = stream << 24;
  for (int c : class_of_contact) v.inputs = std::max(v.inputs, c);
  if (v.inputs < 1 || v.inputs > 3) throw std::invalid_argument("renewal: 1 to 3 input classes expected");

  // Contacts grouped by class; within a class they are exchangeable (one amplitude, one a).
  std::vector<std::vector<int>> members(static_cast<size_t>(v.inputs));
  for (size_t j = 0; j < contacts.size(); ++j)
    members[static_cast<size_t>(class_of_contact[j] - 1)].push_back(static_cast<int>(j));
  const std::vector<double> distance = describe_classes(contacts, members);
  size_t rows = 0;
  for (const auto& m : members) rows += m.size();
  allocate(rows);
  for (int lane = 0; lane < lanes; ++lane)
    start_lane(lane, members, distance, seed, stream, first_realization + static_cast<std::uint64_t>(lane));
  bind();
}

std::vector<double> RenewalState::describe_classes(const std::vector<model::Contact>& contacts,
                                                   const std::vector<std::vector<int>>& members) {
  RenewalLanes& v = view_;
  double row = 0;
  std::vector<double> distance(static_cast<size_t>(v.inputs), 0.0);
  for (int k = 0; k < v.inputs; ++k) {
    const auto& m = members[static_cast<size_t>(k)];
    if (m.size() > (size_t{1} << 20)) throw std::invalid_argument("renewal: an input class has over 2^20 contacts");
    if (m.empty()) continue;  // a level above the touching ones: its mark stays at infinity
    for (int j : m)
      if (contacts[j].random_force_amplitude != contacts[m[0]].random_force_amplitude ||
          contacts[j].renewal_distance != contacts[m[0]].renewal_distance)
        throw std::invalid_argument("renewal: the contacts of an input class differ in force amplitude or a");
    distance[k] = contacts[m[0]].renewal_distance;
    v.force_unit[k] = contacts[m[0]].random_force_amplitude * 0x1p-33;
    v.contacts[k] = static_cast<double>(m.size());
    v.first_contact[k] = row;
    v.spacing[k] = v.periodic ? distance[k] : distance[k] / static_cast<double>(m.size());
    row += static_cast<double>(m.size());
  }
  return distance;
}

void RenewalState::allocate(std::size_t rows) {
  const int lanes = view_.lanes;
  const size_t cells = static_cast<size_t>(view_.inputs) * lanes;
  realization_low_.resize(lanes);
  realization_high_.resize(lanes);
  lane_index_.resize(lanes);
  force_sum_.assign(cells, 0.0);
  next_mark_.assign(cells, 0.0);
  events_.assign(cells, 0.0);
  position_.assign(cells, 0.0);
  cycles_.assign(cells, 0.0);
  upcoming_force_.assign(cells, 0.0);
  upcoming_contact_.assign(cells, 0.0);
  upcoming_spacing_.assign(cells, 0.0);
  forces_.assign(rows * lanes, 0.0);
  phases_.assign(view_.periodic ? rows * lanes : 0, 0.0);
  renewals_.assign(lanes, 0.0);
  jump_energy_.assign(lanes, 0.0);
  passes_.assign(lanes, 0.0);
}

void RenewalState::start_lane(int lane, const std::vector<std::vector<int>>& members,
                              const std::vector<double>& distance, std::uint64_t seed, std::uint64_t stream,
                              std::uint64_t realization) {
  const RenewalLanes& v = view_;
  const int lanes = v.lanes;
  // The kernels' own draw (the scalar path's), so the start uses the same logarithm.
  auto scalar_draw = [&](std::uint32_t tag, std::uint64_t event) {
    const std::uint64_t counter[4] = {event & 0xffffffffu, (event >> 32) | tag << 16 | stream << 24,
                                      realization & 0xffffffffu, realization >> 32};
    std::uint64_t out[4];
    double exponential;
    const std::uint64_t* const in[4] = {&counter[0], &counter[1], &counter[2], &counter[3]};
    std::uint64_t* const words[4] = {&out[0], &out[1], &out[2], &out[3]};
    path_kernels(SimdPath::scalar).draw_lanes(v.key, in, 1, words, &exponential);
    return ScalarDraw{draw::force_units(static_cast<std::uint32_t>(out[0])), out[1], exponential};
  };
  realization_low_[lane] = realization & 0xffffffffu;
  realization_high_[lane] = realization >> 32;
  lane_index_[lane] = static_cast<std::uint64_t>(lane);
  std::vector<std::pair<double, double>> phase_force;
  for (int k = 0; k < v.inputs; ++k) {
    const auto& m = members[static_cast<size_t>(k)];
    const size_t cell = static_cast<size_t>(k) * lanes + lane;
    if (m.empty()) {
      next_mark_[cell] = INFINITY;
      continue;
    }
    const auto tag = static_cast<std::uint32_t>(k);
    phase_force.clear();
    double sum = 0;
    for (size_t i = 0; i < m.size(); ++i) {
      const draw::Words w = draw::words(seed, stream, realization, draw::contact_tag + tag, i);
      const double force = draw::force_units(w[0]);
      sum += force;
      phase_force.emplace_back(distance[k] * (1.0 - draw::open_uniform(w[2], w[3])), force);
    }
    force_sum_[cell] = sum;
    if (v.periodic) std::sort(phase_force.begin(), phase_force.end());
    for (size_t i = 0; i < m.size(); ++i) {
      const size_t at = (static_cast<size_t>(v.first_contact[k]) + i) * lanes + lane;
      forces_[at] = phase_force[i].second;
      if (v.periodic) phases_[at] = phase_force[i].first;
    }
    if (v.periodic) {
      next_mark_[cell] = phase_force[0].first;
    } else {
      next_mark_[cell] = v.spacing[k] * scalar_draw(draw::first_mark_tag + tag, 0).spacing;
    }
    const ScalarDraw upcoming = scalar_draw(draw::renewal_tag + tag, 0);
    upcoming_force_[cell] = upcoming.force;
    upcoming_contact_[cell] = std::floor(static_cast<double>(upcoming.contact_word) * v.contacts[k] * 0x1p-32);
    upcoming_spacing_[cell] = upcoming.spacing;
  }
}

RenewalState::RenewalState(RenewalState&& other) noexcept { *this = std::move(other); }

RenewalState& RenewalState::operator=(RenewalState&& other) noexcept {
  view_ = other.view_;
  realization_low_ = std::move(other.realization_low_);
  realization_high_ = std::move(other.realization_high_);
  lane_index_ = std::move(other.lane_index_);
  force_sum_ = std::move(other.force_sum_);
  next_mark_ = std::move(other.next_mark_);
  events_ = std::move(other.events_);
  position_ = std::move(other.position_);
  cycles_ = std::move(other.cycles_);
  upcoming_force_ = std::move(other.upcoming_force_);
  upcoming_contact_ = std::move(other.upcoming_contact_);
  upcoming_spacing_ = std::move(other.upcoming_spacing_);
  forces_ = std::move(other.forces_);
  phases_ = std::move(other.phases_);
  renewals_ = std::move(other.renewals_);
  jump_energy_ = std::move(other.jump_energy_);
  passes_ = std::move(other.passes_);
  bind();
  return *this;
}

void RenewalState::bind() {
  RenewalLanes& v = view_;
  v.realization_low = realization_low_.data();
  v.realization_high = realization_high_.data();
  v.lane_index = lane_index_.data();
  v.force_sum = force_sum_.data();
  v.next_mark = next_mark_.data();
  v.events = events_.data();
  v.position = position_.data();
  v.cycles = cycles_.data();
  v.upcoming_force = upcoming_force_.data();
  v.upcoming_contact = upcoming_contact_.data();
  v.upcoming_spacing = upcoming_spacing_.data();
  v.forces = forces_.data();
  v.phases = phases_.data();
  v.renewals = renewals_.data();
  v.jump_energy = jump_energy_.data();
  v.passes = passes_.data();
}

void RenewalState::reset_counters() {
  std::fill(renewals_.begin(), renewals_.end(), 0.0);
  std::fill(jump_energy_.begin(), jump_energy_.end(), 0.0);
  std::fill(passes_.begin(), passes_.end(), 0.0);
}

double RenewalState::input_force(int k, int lane) const {
  return view_.force_unit[k] * force_sum_[static_cast<size_t>(k) * view_.lanes + lane];
}

}  // namespace slidespec::stepper
