// Sweep grids (src/cli/sweep.cpp): lists and ranges as the values a user means, every
// combination, and the planned-work weights behind the progress of several runs.
#include <gtest/gtest.h>

#include "cli/sweep.hpp"

namespace slidespec::cli {
namespace {

using Values = std::vector<std::string>;

TEST(Sweep, RangesGiveTheValuesAUserMeans) {
  const auto axes = parse_sweep({"alpha=0.1:1:0.1", "N=10..100", "log", "5", "chain=open,ring"});
  ASSERT_EQ(axes.size(), 3u);
  EXPECT_EQ(axes[0].values, (Values{"0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1"}));
  EXPECT_EQ(axes[1].values, (Values{"10", "18", "32", "56", "100"}));
  EXPECT_EQ(axes[2].values, (Values{"open", "ring"}));
  EXPECT_EQ(parse_sweep({"a=1e-4..1e-3", "lin", "3"})[0].values, (Values{"1e-04", "0.00055", "0.001"}));
  EXPECT_EQ(parse_sweep({"N=1..3", "lin", "3"})[0].values, (Values{"1", "2", "3"}));
  // Quoted as one argument, the same grid.
  EXPECT_EQ(parse_sweep({"N=10..100 log 5"})[0].values, axes[1].values);
}

TEST(Sweep, GridIsEveryCombinationFirstKeySlowest) {
  const auto grid = sweep_grid(parse_sweep({"alpha=1,2", "N=5,6,7"}));
  ASSERT_EQ(grid.size(), 6u);
  EXPECT_EQ(grid[0], (std::vector<std::pair<std::string, std::string>>{{"alpha", "1"}, {"N", "5"}}));
  EXPECT_EQ(grid[5], (std::vector<std::pair<std::string, std::string>>{{"alpha", "2"}, {"N", "7"}}));
}

TEST(Sweep, MalformedWordsAreRefused) {
  for (const std::vector<std::string>& words : {std::vector<std::string>{"alpha"},
                                                {"N=10..100"},
                                                {"N=10..100", "log", "1"},
                                                {"alpha=1:0:0.1"},
                                                {"alpha=0:1:0"},
                                                {"a=-1..1", "log", "3"},
                                                {"alpha=1,,2"},
                                                {"alpha=1", "alpha=2"},
                                                {"alpha=x:1:0.1"},
                                                // values that round to one: 10, 10, 11, 11, 12
                                                {"N=10..12", "log", "5"},
                                                {"N=1..3", "lin", "5"},
                                                {"N=1:3:0.5"}})
    EXPECT_THROW(parse_sweep(words), InputError) << words[0];
}

TEST(Sweep, ProgressWeighsSubBandsAndRunsByTheirPlannedWork) {
  const std::vector<double> work = {2, 1, 1};
  EXPECT_DOUBLE_EQ(weighted_fraction(0, work), 0);
  EXPECT_DOUBLE_EQ(weighted_fraction(1.0 / 3, work), 0.5);  // the end of the first, double band
  EXPECT_DOUBLE_EQ(weighted_fraction(0.5, work), 0.625);
  EXPECT_DOUBLE_EQ(weighted_fraction(1, work), 1);
  // A run of 100 miniblocks plans about 101/31 the work of one of 30 over the same band
  // (one whose realizations hold enough renewals in either case not to be lengthened).
  RunRequest request;
  request.omega_max = 750;
  const double ratio = planned_work(ParameterBuilder("many-contacts").build(), request) /
                       planned_work(ParameterBuilder("reference").build(), request);
  EXPECT_NEAR(ratio, 101.0 / 31.0, 0.5);
}

}  // namespace
}  // namespace slidespec::cli
