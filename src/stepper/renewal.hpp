// Renewal of the random forces: marks on the sliding distance, counter-based random numbers.
#pragma once

#include <cstdint>
#include <vector>

#include "slidespec/parameters.hpp"

namespace slidespec::model {
struct Contact;  // kept out of the kernel's translation units: they must not see Eigen
}

namespace slidespec::stepper {

struct ExactStep;

// Exact sums of up to 2^74 forces in units of 2^-53 alpha f_kin.
__extension__ using WideSum = __int128;

/// Uniform [0, 1) doubles for (realization, contact, renewal count), keyed by (seed, stream):
/// Philox4x64-10, so every number is a pure function of its indices and no stream state
/// has to be carried or split between lanes, batches or threads.
struct RenewalDraw {
  double force_uniform;    ///< r in f = alpha f_kin (r - 0.5); exact multiple of 2^-53
  std::int64_t force_units;///< r * 2^53 - 2^52: the force in units of alpha f_kin 2^-53
  double spacing_uniform;  ///< for the distance to the next mark
};
RenewalDraw draw_renewal(std::uint64_t seed, std::uint64_t stream, std::uint64_t realization,
                         std::uint64_t contact, std::uint64_t renewal_count);

/// The renewal state of a batch of lanes, laid out contact-major (structure of arrays:
/// contact i of every lane is contiguous). The sums of the forces per input class are
/// kept exactly, as integers, so they never drift however many renewals happen; that
/// needs one force amplitude per class (a level), while renewal distances are per contact.
class RenewalState {
 public:
  /// `class_of_contact[j]` in 1..inputs for `contacts[j]`; `lanes` lanes of which lane k is
  /// realization first + k. Throws std::invalid_argument if a class mixes amplitudes.
  RenewalState(const std::vector<model::Contact>& contacts, const std::vector<int>& class_of_contact,
               Renewal renewal, std::uint64_t seed, std::uint64_t stream,
               std::uint64_t first_realization, int lanes);

  /// One step of `lane` in which the block passes its next mark: every renewal is applied
  /// at its own time inside the step, in the order of the marks, and the step's end state
  /// replaces the plain step's. `z` holds z_n on entry and z_{n+1} on return;
  /// `increment` the plain step's xi increment on entry and the true one on return.
  /// x(t) = steady_start + advance t/dt + xi_start + (xi(t) - xi_n); the step ends at
  /// steady_end (the kernel's own product, so both test the same x against the marks).
  void step_with_renewals(int lane, const ExactStep& step, double steady_start, double steady_end,
                          double advance, double xi_start, double* z, double& increment);

  int lanes() const { return lanes_; }
  int inputs() const { return inputs_; }
  /// Sum of the random forces of input class k in each lane [N]: inputs()*lanes(), class-major.
  const double* input_forces() const { return input_forces_.data(); }
  /// The nearest mark ahead of each lane [m].
  const double* next_marks() const { return next_mark_.data(); }
  std::uint64_t renewals(int lane) const { return renewals_[lane]; }
  /// Sum over the lane's renewals of (f_new - f_old)^2 [N^2]: the realized strength of
  /// the random forcing, whose expectation the model fixes (a control variate for run).
  double jump_energy(int lane) const { return jump_energy_[lane]; }

 private:
  template <int State>
  void step_shaped(int lane, const ExactStep& step, double steady_start, double steady_end, double advance,
                   double xi_start, double* z, double& increment);
  void renew_next(int lane);  // the contact with the nearest mark, then the tree
  void update_tree(int lane, int contact);
  void refresh_inputs(int lane);
  void publish_inputs(int lane);  // input_forces_ from the exact integer sums

  std::vector<double> force_unit_;        // per input class: alpha f_kin 2^-53 [N]
  std::vector<double> renewal_distance_;  // per contact [m]
  bool poisson_;
  std::uint64_t seed_, stream_, first_;
  int lanes_, contacts_, inputs_, leaves_;
  std::vector<int> class_of_contact_;
  std::vector<std::int64_t> force_units_;   // contact-major
  std::vector<double> mark_;                // contact-major
  std::vector<std::uint64_t> count_;        // contact-major
  std::vector<WideSum> input_units_;         // class-major
  std::vector<double> input_forces_;        // class-major
  std::vector<double> next_mark_;
  std::vector<std::uint64_t> renewals_;
  std::vector<double> jump_energy_;
  std::vector<int> tree_;                   // per lane: tournament tree of the earliest mark
  std::vector<double> tree_mark_;           // per lane: the mark of each tree node's contact
};

}  // namespace slidespec::stepper
