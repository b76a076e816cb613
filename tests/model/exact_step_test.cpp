#include "model/exact_step.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "model/linear_structure.hpp"

using namespace slidespec;

TEST(ExactStep, TwoStepsOfDtEqualOneStepOfTwoDt) {
  const auto lumped = model::lumped_tree_structure(ParameterBuilder().build());
  for (double dt : {1e-5, 1e-3}) {
    const auto one = model::exact_step(lumped, dt);
    const auto two = model::exact_step(lumped, 2 * dt);
    const int d = one.dimension;
    for (int r = 0; r < d; ++r)
      for (int c = 0; c < d; ++c) {
        double squared = 0;
        for (int k = 0; k < d; ++k) squared += one.transition[r * d + k] * one.transition[k * d + c];
        EXPECT_NEAR(squared, two.transition[r * d + c], 1e-12 * (1 + std::fabs(squared)));
      }
  }
}
