#include <gtest/gtest.h>

#include "slidespec/estimator.hpp"

TEST(Estimator, HeaderCompiles) { SUCCEED(); }
