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
  const int state = 2 * n;  // (xi, r_1..r_{n-1}, q'_0..q'_{n-1})

  // q = xi * 1 + (0, r): stiffness sees only r because it annihilates a translation.
  const MatrixL mass_inverse = lumped.mass.cast<long double>().inverse();
  const MatrixL K = lumped.stiffness.cast<long double>();
  const MatrixL D = lumped.damping.cast<long double>();
  MatrixL A = MatrixL::Zero(state, state);
  MatrixL B = MatrixL::Zero(state, inputs);
  A(0, n) = 1;                                    // xi' = q'_0
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

  // Partial-step tables: one exponential per digit, then powers of it by products in
  // long double (255 products lose ~1e-17 relative, far below double's rounding).
  const int columns = state + inputs;
  const int table = 1 << ExactStep::digit_bits;
  step.partial.reserve(static_cast<size_t>(ExactStep::fraction_digits) * table * state * columns);
  for (int digit = 0; digit < ExactStep::fraction_digits; ++digit) {
    const long double fraction = std::ldexp(1.0L, -ExactStep::digit_bits * (digit + 1));
    const MatrixL unit = (augmented * fraction).exp();
    MatrixL power = MatrixL::Identity(columns, columns);
    for (int k = 0; k < table; ++k) {
      for (int j = 0; j < columns; ++j)
        for (int i = 0; i < state; ++i) step.partial.push_back(static_cast<double>(power(i, j)));
      power = power * unit;
    }
  }
  return step;
}

namespace {

// The digit maps with the shape known at compile time: the rows' sums unroll and interleave
// (each is a chain of dependent adds), which a run's renewals spend most of their time in.
// Maps are stored column-major, so that the rows advance together in vector registers.
template <int State, int Inputs>
void apply_digits(const ExactStep& step, std::int64_t n, double* y, const double* g) {
  constexpr int columns = State + Inputs, table = 1 << ExactStep::digit_bits;
  for (int digit = 0; digit < ExactStep::fraction_digits; ++digit) {
    const int k = static_cast<int>((n >> (ExactStep::digit_bits * (ExactStep::fraction_digits - 1 - digit))) &
                                   (table - 1));
    if (k == 0) continue;  // the identity: skipped, so a zero time leaves every bit alone
    const double* map = step.partial.data() + (static_cast<size_t>(digit) * table + k) * State * columns;
    // Column by column, each row's sum in the order y_0 .. y_last, g_0 .. g_last as before;
    // the rows are independent lanes, so this vectorizes without changing a bit.
    double next[State];
    for (int i = 0; i < State; ++i) next[i] = map[i] * y[0];
    for (int j = 1; j < State; ++j)
      for (int i = 0; i < State; ++i) next[i] = next[i] + map[j * State + i] * y[j];
    for (int c = 0; c < Inputs; ++c)
      for (int i = 0; i < State; ++i) next[i] = next[i] + map[(State + c) * State + i] * g[c];
    for (int i = 0; i < State; ++i) y[i] = next[i];
  }
}

}  // namespace

void ExactStep::advance_partial(std::int64_t n, double* y, const double* g) const {
  const int state = dimension + 1;
  switch (state * 8 + inputs) {
    case 4 * 8 + 1: apply_digits<4, 1>(*this, n, y, g); break;
    case 6 * 8 + 1: apply_digits<6, 1>(*this, n, y, g); break;
    case 6 * 8 + 2: apply_digits<6, 2>(*this, n, y, g); break;
    case 8 * 8 + 1: apply_digits<8, 1>(*this, n, y, g); break;
    case 8 * 8 + 2: apply_digits<8, 2>(*this, n, y, g); break;
    case 8 * 8 + 3: apply_digits<8, 3>(*this, n, y, g); break;
    default: throw std::logic_error("partial step: shape not compiled");
  }
  // n = 2^fraction_bits, the whole step, has no digits below: the full step's map.
  if (n >> fraction_bits) {
    double next[max_state] = {};
    for (int i = 0; i < state; ++i) {
      double sum = 0;
      if (i == 0) {
        sum = y[0];
        for (int j = 1; j < state; ++j) sum = sum + increment[j - 1] * y[j];
        for (int c = 0; c < inputs; ++c) sum = sum + increment_forcing[c] * g[c];
      } else {
        sum = transition[(i - 1) * dimension] * y[1];
        for (int j = 2; j < state; ++j) sum = sum + transition[(i - 1) * dimension + j - 1] * y[j];
        for (int c = 0; c < inputs; ++c) sum = sum + forcing[(i - 1) * inputs + c] * g[c];
      }
      next[i] = sum;
    }
    std::memcpy(y, next, sizeof next);
  }
}

}  // namespace slidespec::stepper
