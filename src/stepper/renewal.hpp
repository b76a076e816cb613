// Renewal of the random forces: marks on the sliding distance, counter-based random numbers.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "slidespec/parameters.hpp"

namespace slidespec::model {
struct Contact;  // kept out of the kernel's translation units: they must not see Eigen
}

namespace slidespec::stepper {

/// The random stream (docs/numerics.md, "Random numbers"): Philox4x32-10 keyed by the seed,
/// counter (event, event >> 32 | tag << 16 | stream << 24, realization, realization >> 32).
/// Every number is a pure function of these indices, so no generator state is carried or
/// split between lanes, batches, threads or processes.
namespace draw {
constexpr std::uint32_t renewal_tag = 0;      ///< + class: the event-th renewal of a class
constexpr std::uint32_t contact_tag = 16;     ///< + class: contact `event`'s first force and phase
constexpr std::uint32_t first_mark_tag = 32;  ///< + class: the first mark of a merged process
constexpr int max_stream = 255;
using Words = std::array<std::uint32_t, 4>;
/// The four words of one draw (the scalar reference; the kernels compute the same in lanes).
Words words(std::uint64_t seed, std::uint64_t stream, std::uint64_t realization, std::uint32_t tag,
            std::uint64_t event);
/// A force in units of its class's alpha f_kin 2^-33: an odd integer in (-2^32, 2^32),
/// so the force is uniform on (-alpha f_kin / 2, alpha f_kin / 2) to 2^-33, and sums of up
/// to 2^20 of them are exact in a double.
inline double force_units(std::uint32_t word) { return 2.0 * word - 4294967295.0; }
/// A uniform number in (0, 1], a multiple of 2^-52, from the draw's last two words.
double open_uniform(std::uint32_t word2, std::uint32_t word3);
}  // namespace draw

/// What the kernels read and write of a batch's renewal state: structure of arrays, lane
/// index fastest. Contacts are grouped by input class (a touching level); for periodic
/// renewal each class's contacts are kept in the order of their phases, so the next to
/// renew is the one after the last, cyclically, and no search is needed.
struct RenewalLanes {
  int lanes = 0;   ///< stride of every per-lane array
  int inputs = 0;  ///< input classes K
  bool periodic = false;
  std::uint32_t key[2] = {};      ///< the seed
  std::uint64_t stream_bits = 0;  ///< stream << 24, or-ed into the second counter word
  // Per class:
  double force_unit[3] = {};     ///< alpha f_kin 2^-33 [N]
  double contacts[3] = {};       ///< N_k
  double first_contact[3] = {};  ///< row of the class's first contact in `forces`
  double spacing[3] = {};        ///< mean distance between renewals of the class: a/N_k
                                 ///< (one merged Poisson process), or a for periodic [m]
  // Per lane (realization words), per class and lane, per contact and lane:
  const std::uint64_t* realization_low = nullptr;
  const std::uint64_t* realization_high = nullptr;
  const std::uint64_t* lane_index = nullptr;  ///< 0, 1, 2, ...: the column of each lane
  double* force_sum = nullptr;                ///< [class][lane] sum of the class's forces, in units
  double* next_mark = nullptr;                ///< [class][lane] the class's next mark [m]
  double* events = nullptr;                   ///< [class][lane] renewals so far (an exact integer)
  double* position = nullptr;                 ///< [class][lane] periodic: the place in the cycle of the next
  double* cycles = nullptr;                   ///< [class][lane] periodic: completed cycles
  // The class's next renewal, drawn one renewal ahead so that the generator's latency is
  // off the path from one renewal to the next ([class][lane]):
  double* upcoming_force = nullptr;    ///< the force it brings, in units
  double* upcoming_contact = nullptr;  ///< poisson: which of the class's contacts (0..N_k-1)
  double* upcoming_spacing = nullptr;  ///< poisson: the distance to the mark after it, in spacings
  double* forces = nullptr;            ///< [contact][lane] in units
  const double* phases = nullptr;      ///< [contact][lane] periodic: where in [0, a) it renews [m]
  double* renewals = nullptr;          ///< [lane]
  double* jump_energy = nullptr;       ///< [lane] sum of (f_new - f_old)^2 [N^2]
  double* passes = nullptr;            ///< [lane] renewal passes of the lane's group (a diagnostic)
};

/// The renewal state of a batch of lanes: the storage behind RenewalLanes, and the
/// stationary start. For Poisson renewal the marks of the N_k contacts of a class together
/// are one Poisson process of mean spacing a/N_k, the renewing contact uniform among them
/// (exact: a superposition of independent Poisson processes, thinned by a fair choice).
class RenewalState {
 public:
  /// `class_of_contact[j]` in 1..inputs for `contacts[j]`; `lanes` lanes of which lane k is
  /// realization first + k. Throws std::invalid_argument if a class mixes amplitudes or
  /// renewal distances, or has more than 2^20 contacts.
  RenewalState(const std::vector<model::Contact>& contacts, const std::vector<int>& class_of_contact, Renewal renewal,
               std::uint64_t seed, std::uint64_t stream, std::uint64_t first_realization, int lanes);
  RenewalState(RenewalState&&) noexcept;
  RenewalState& operator=(RenewalState&&) noexcept;

  RenewalLanes& lanes_view() { return view_; }
  int lanes() const { return view_.lanes; }
  int inputs() const { return view_.inputs; }
  /// Sum of the random forces of input class k in `lane` [N], as the kernels compute it.
  double input_force(int k, int lane) const;
  std::uint64_t renewals(int lane) const { return static_cast<std::uint64_t>(renewals_[lane]); }
  /// Sum over the lane's renewals of (f_new - f_old)^2 [N^2]: the realized strength of
  /// the random forcing, whose expectation the model fixes (a control variate for run).
  double jump_energy(int lane) const { return jump_energy_[lane]; }
  /// Renewal passes run by the lane's group while it stepped: renewals over passes times
  /// the width is the lanes' utilization (a diagnostic: no result depends on it).
  std::uint64_t passes(int lane) const { return static_cast<std::uint64_t>(passes_[lane]); }
  /// Renewals, jump energy and passes start again from zero (after a warm-up).
  void reset_counters();

 private:
  /// Each input class's force unit, contact count, first row and mark spacing, from its
  /// `members` (contact indices); returns each class's renewal distance a [m].
  std::vector<double> describe_classes(const std::vector<model::Contact>& contacts,
                                       const std::vector<std::vector<int>>& members);
  /// Sizes every per-lane array for `rows` contacts in all.
  void allocate(std::size_t rows);
  /// A lane's stationary start: fresh forces; marks where a stationary renewal process puts
  /// them ahead of x = 0 (memoryless for Poisson; a uniform phase per contact for periodic).
  void start_lane(int lane, const std::vector<std::vector<int>>& members, const std::vector<double>& distance,
                  std::uint64_t seed, std::uint64_t stream, std::uint64_t realization);
  void bind();  // points view_ at the vectors
  RenewalLanes view_;
  std::vector<std::uint64_t> realization_low_, realization_high_, lane_index_;
  std::vector<double> force_sum_, next_mark_, events_, position_, cycles_, forces_, phases_;
  std::vector<double> upcoming_force_, upcoming_contact_, upcoming_spacing_;
  std::vector<double> renewals_, jump_energy_, passes_;
};

}  // namespace slidespec::stepper
