// Exact discretization of the model's linear part over one time step.
#pragma once

#include <cstdint>
#include <vector>


namespace slidespec::model {
struct LumpedStructure;
}

namespace slidespec::stepper {

/// Over a step dt with the random forces constant, the lumped system is solved exactly:
///   z_{n+1} = transition z_n + forcing g_n,   xi_{n+1} - xi_n = increment . z_n + increment_forcing . g_n
/// where z = (relative offsets of the lumped coordinates from the block, all velocities)
/// and g_k is the sum of the random forces f_j of the contacts in input class k.
/// xi itself is left out of z: nothing depends on it (every spring is relative), and
/// keeping it out means the increments are never computed as differences of large numbers.
struct ExactStep {
  double dt = 0;                         ///< the step [s]
  int dimension = 0;                     ///< size of z
  int inputs = 0;                        ///< number of input classes
  std::vector<double> transition;        ///< dimension x dimension, row-major
  std::vector<double> forcing;           ///< dimension x inputs, row-major
  std::vector<double> increment;         ///< dimension
  std::vector<double> increment_forcing; ///< inputs
  std::vector<double> initial_response;  ///< dimension x inputs: z in equilibrium with g
  std::vector<int> offset_component;     ///< components of z that are miniblock offsets

  /// Renewals inside a step: the exact map over any time dt n / 2^fraction_bits, 0 <= n <=
  /// 2^fraction_bits, as at most `fraction_digits` table maps (one per base-2^digit_bits
  /// digit of n). Table (digit d, value k) maps y = (xi increment, z) and g over
  /// dt k 2^-(digit_bits (d + 1)): y' = P y + Q g, stored column-major as [P | Q], rows and
  /// columns of P over the (dimension + 1) components of y.
  static constexpr int digit_bits = 8, fraction_digits = 3, fraction_bits = digit_bits * fraction_digits;
  std::vector<double> partial;           ///< [digit][k][column][row]
  int velocity_component = 0;            ///< component of z that is the block's velocity fluctuation

  /// y' = map over dt n 2^-fraction_bits of (y, g), in place; y has dimension + 1 components
  /// in an array of max_state (the rest is scratch).
  static constexpr int max_state = 16;
  void advance_partial(std::int64_t n, double* y, const double* g) const;
};

/// Builds the exact step for dt > 0 (matrix exponentials in long double).
ExactStep exact_step(const model::LumpedStructure& lumped, double dt);

}  // namespace slidespec::stepper
