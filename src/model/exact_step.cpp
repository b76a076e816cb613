#include "model/exact_step.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <unsupported/Eigen/MatrixFunctions>

#include "model/linear_structure.hpp"

namespace slidespec::model {

ExactStep exact_step(const LumpedStructure& lumped, double dt, const LoadPoint& load_point) {
  using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  const int n = static_cast<int>(lumped.mass.rows());
  int inputs = 0;
  for (int c : lumped.class_of_contact) inputs = std::max(inputs, c);  // classes 1..n-1
  const int state = 2 * n;                                             // (xi, r_1..r_{n-1}, q'_0..q'_{n-1})

  // q = xi * 1 + (0, r). The stiffness annihilates a translation unless the block is tied
  // to the load point: then K 1 = k_drive e_0 and xi feeds back.
  const bool tied = load_point.tied;
  const MatrixL mass_inverse = lumped.mass.cast<long double>().inverse();
  const MatrixL K = lumped.stiffness.cast<long double>();
  const MatrixL D = lumped.damping.cast<long double>();
  MatrixL A = MatrixL::Zero(state, state);
  MatrixL B = MatrixL::Zero(state, inputs);
  A(0, n) = 1;                                                // xi' = q'_0
  for (int c = 1; c < n; ++c) A(c, n + c) = 1, A(c, n) = -1;  // r_c' = q'_c - q'_0
  const MatrixL stiffness_on_r = -mass_inverse * K.rightCols(n - 1);
  A.block(n, 1, n, n - 1) = stiffness_on_r;
  if (tied) A.block(n, 0, n, 1) = -mass_inverse * K.rowwise().sum();
  A.block(n, n, n, n) = -mass_inverse * D;
  // Input class k (1-based lumped coordinate k) feels minus the sum of its contacts' f_j.
  for (int k = 0; k < inputs; ++k) B.block(n, k, n, 1) = -mass_inverse.col(k + 1);

  // Van Loan: exp([[A, B], [0, 0]] dt) = [[Phi, Gamma], [0, I]], Gamma = int_0^dt e^{As} ds B.
  MatrixL augmented = MatrixL::Zero(state + inputs, state + inputs);
  augmented.topLeftCorner(state, state) = A * static_cast<long double>(dt);
  augmented.topRightCorner(state, inputs) = B * static_cast<long double>(dt);
  const MatrixL E = augmented.exp();
  const MatrixL Phi = E.topLeftCorner(state, state);
  const MatrixL Gamma = E.topRightCorner(state, inputs);

  // z leaves xi out when nothing depends on it, so that increments are never differences
  // of large numbers; tied, xi is bounded and z starts with it.
  const int first = tied ? 0 : 1;
  ExactStep step;
  step.dt = dt;
  step.dimension = state - first;
  step.inputs = inputs;
  for (int i = first; i < state; ++i) {
    for (int j = first; j < state; ++j) step.transition.push_back(static_cast<double>(Phi(i, j)));
    for (int k = 0; k < inputs; ++k) step.forcing.push_back(static_cast<double>(Gamma(i, k)));
  }
  // The increment of xi; tied, its own coefficient Phi(0, 0) - 1 is taken in long double.
  for (int j = first; j < state; ++j) step.increment.push_back(static_cast<double>(Phi(0, j) - (j == 0 ? 1 : 0)));
  for (int k = 0; k < inputs; ++k) step.increment_forcing.push_back(static_cast<double>(Gamma(0, k)));

  // The start for the forces g now. Untied: z in equilibrium with g, 0 = A_z z + B_z g (the
  // model's slowest internal rate is far above the renewal rate). Tied, the block remembers
  // the forces over 1/omega_s, which may be as long as a renewal time: the mean of z given
  // g, the forces having been renewed at rate lambda before, (lambda - A) z = B g.
  const MatrixL Az = A.bottomRightCorner(state - first, state - first);
  const MatrixL memory =
      static_cast<long double>(load_point.start_renewal_rate) * MatrixL::Identity(state - first, state - first);
  const MatrixL response = tied ? MatrixL((memory - Az).fullPivLu().solve(B.bottomRows(state - first)))
                                : MatrixL(-Az.fullPivLu().solve(B.bottomRows(state - first)));
  for (int i = 0; i < state - first; ++i)
    for (int k = 0; k < inputs; ++k) step.initial_response.push_back(static_cast<double>(response(i, k)));
  for (int c = 1; c < n; ++c) step.offset_component.push_back(c - first);
  step.velocity_component = n - first;  // z = ([xi,] r_1..r_{n-1}, q'_0, ...): q'_0 is the block's

  // Response tables: one exponential over dt / nodes, then powers of it by products in
  // long double (256 products lose ~1e-17 relative, far below double's rounding).
  const int columns = state + inputs;
  const int nodes = ExactStep::response_nodes;
  const MatrixL unit = (augmented / static_cast<long double>(nodes)).exp();
  std::vector<MatrixL> powers{MatrixL::Identity(columns, columns)};
  for (int j = 1; j <= nodes; ++j) powers.push_back(powers.back() * unit);
  for (int k = 0; k < inputs; ++k)
    for (int j = 0; j <= nodes; ++j) {
      const MatrixL rate = powers[j].topLeftCorner(state, state) * B.col(k);
      // y = (xi increment, z): xi's row, then z's rows (which start with xi again when tied).
      for (int y = 0; y <= state - first; ++y) {
        const int i = y == 0 ? 0 : y - 1 + first;
        step.response.push_back(static_cast<double>(powers[j](i, state + k)));
        step.response_rate.push_back(static_cast<double>(rate(i)));
      }
    }
  return step;
}

}  // namespace slidespec::model
