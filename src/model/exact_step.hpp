// Exact discretization of the model's linear part over one time step: the mathematics of
// the model, used by the stepper (to step) and the theory (the sampled spectrum).
#pragma once

#include <cstdint>
#include <vector>

namespace slidespec::model {

struct LumpedStructure;

/// Over a step dt with the random forces constant, the lumped system is solved exactly:
///   z_{n+1} = transition z_n + forcing g_n,   xi_{n+1} - xi_n = increment . z_n + increment_forcing . g_n
/// where z = (relative offsets of the lumped coordinates from the block, all velocities)
/// and g_k is the sum of the random forces f_j of the contacts in input class k.
/// xi itself is left out of z when nothing depends on it (every spring is relative), so
/// that the increments are never computed as differences of large numbers. With the block
/// tied to a load point (drive = spring) xi feeds back and stays bounded: z starts with xi,
/// and the running sum of the increments (where the renewal marks are) starts at 0.
struct ExactStep {
  double dt = 0;                          ///< the step [s]
  int dimension = 0;                      ///< size of z
  int inputs = 0;                         ///< number of input classes
  std::vector<double> transition;         ///< dimension x dimension, row-major
  std::vector<double> forcing;            ///< dimension x inputs, row-major
  std::vector<double> increment;          ///< dimension
  std::vector<double> increment_forcing;  ///< inputs
  std::vector<double> initial_response;   ///< dimension x inputs: z in equilibrium with g
  std::vector<int> offset_component;      ///< components of z that are miniblock offsets

  /// Renewals inside a step, by superposition: a force jump of Delta g_k at a time s before
  /// the step's end adds response(s) Delta g_k to y = (xi increment, z) at the end. Tabulated
  /// at s = dt j / response_nodes, j = 0..response_nodes, with its rate d/ds (so a crossing
  /// between nodes is served by one Taylor term from the nearest): [class][j][component].
  static constexpr int response_nodes = 256;
  std::vector<double> response;       ///< int_0^s e^{A u} du B, (dimension + 1) per node
  std::vector<double> response_rate;  ///< e^{A s} B [1/s]
  int velocity_component = 0;         ///< component of z that is the block's velocity fluctuation
};

/// Whether the block is tied to a load point by a spring (its stiffness is in the lumped
/// K_00), and then the rate at which the forces were renewed before the start [1/s].
struct LoadPoint {
  bool tied = false;
  double start_renewal_rate = 0;
};

/// Builds the exact step for dt > 0 (matrix exponentials in long double). The initial
/// state is the equilibrium with the forces at the start; tied to a load point, their mean.
ExactStep exact_step(const LumpedStructure& lumped, double dt, const LoadPoint& load_point = {});

}  // namespace slidespec::model
