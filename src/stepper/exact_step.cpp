#include "stepper/exact_step.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <unsupported/Eigen/MatrixFunctions>

#include "model/linear_structure.hpp"

namespace slidespec::stepper {

ExactStep exact_step(const model::LumpedStructure& lumped, double dt) {
  using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  const int n = static_cast<int>(lumped.mass.rows());
  int inputs = 0;
  for (int c : lumped.class_of_contact) inputs = std::max(inputs, c);  // classes 1..n-1
  const int state = 2 * n;                                             // (xi, r_1..r_{n-1}, q'_0..q'_{n-1})

  // q = xi * 1 + (0, r): stiffness sees only r because it annihilates a translation.
  const MatrixL mass_inverse = lumped.mass.cast<long double>().inverse();
  const MatrixL K = lumped.stiffness.cast<long double>();
  const MatrixL D = lumped.damping.cast<long double>();
  MatrixL A = MatrixL::Zero(state, state);
  MatrixL B = MatrixL::Zero(state, inputs);
  A(0, n) = 1;                                                // xi' = q'_0
  for (int c = 1; c < n; ++c) A(c, n + c) = 1, A(c, n) = -1;  // r_c' = q'_c - q'_0
  const MatrixL stiffness_on_r = -mass_inverse * K.rightCols(n - 1);
  A.block(n, 1, n, n - 1) = stiffness_on_r;
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

  ExactStep step;
  step.dt = dt;
  step.dimension = state - 1;
  step.inputs = inputs;
  for (int i = 1; i < state; ++i) {
    for (int j = 1; j < state; ++j) step.transition.push_back(static_cast<double>(Phi(i, j)));
    for (int k = 0; k < inputs; ++k) step.forcing.push_back(static_cast<double>(Gamma(i, k)));
  }
  for (int j = 1; j < state; ++j) step.increment.push_back(static_cast<double>(Phi(0, j)));
  for (int k = 0; k < inputs; ++k) step.increment_forcing.push_back(static_cast<double>(Gamma(0, k)));

  // Equilibrium of z for constant g: 0 = A_z z + B_z g (A without the xi row and column).
  const MatrixL Az = A.bottomRightCorner(state - 1, state - 1);
  const MatrixL response = -Az.fullPivLu().solve(B.bottomRows(state - 1));
  for (int i = 0; i < state - 1; ++i)
    for (int k = 0; k < inputs; ++k) step.initial_response.push_back(static_cast<double>(response(i, k)));
  for (int c = 1; c < n; ++c) step.offset_component.push_back(c - 1);
  step.velocity_component = n - 1;  // z = (r_1..r_{n-1}, q'_0, ...): q'_0 is the block's

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
      for (int i = 0; i < state; ++i) {
        step.response.push_back(static_cast<double>(powers[j](i, state + k)));
        step.response_rate.push_back(static_cast<double>(rate(i)));
      }
    }
  return step;
}

}  // namespace slidespec::stepper
