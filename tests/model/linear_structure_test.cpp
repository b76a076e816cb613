#include "model/linear_structure.hpp"

#include <gtest/gtest.h>

using namespace slidespec;

TEST(LinearStructure, StiffnessIgnoresACommonTranslation) {
  for (const char* chain : {"chain=open", "chain=ring"}) {
    const auto s = model::tree_structure(ParameterBuilder().set(chain).build());
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(s.coordinates());
    EXPECT_LT((s.stiffness * ones).cwiseAbs().maxCoeff(), 1e-9) << chain;
  }
}

TEST(LinearStructure, DriveSpringBreaksTheTranslationOnTheBlockAlone) {
  const auto s = model::tree_structure(ParameterBuilder().set("drive=spring").set("k_drive=2e3").build());
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(s.coordinates());
  const Eigen::VectorXd restoring = s.stiffness * ones;
  EXPECT_NEAR(restoring(0), 2e3, 1e-9);
  EXPECT_LT(restoring.tail(s.coordinates() - 1).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(LinearStructure, FlatModelLumpsToBlockAndMeanMiniblock) {
  const Parameters p = ParameterBuilder().set("chain=ring").build();
  const auto lumped = model::lumped_tree_structure(p);
  ASSERT_EQ(lumped.mass.rows(), 2);
  EXPECT_DOUBLE_EQ(lumped.mass(0, 0), p.M);
  EXPECT_DOUBLE_EQ(lumped.mass(1, 1), p.N * p.m);
  EXPECT_DOUBLE_EQ(lumped.stiffness(0, 0), p.N * p.k0);
  EXPECT_DOUBLE_EQ(lumped.stiffness(0, 1), -p.N * p.k0);
  // The chain springs cancel in the mean: k1 does not reach the block.
  EXPECT_NEAR(lumped.stiffness(1, 1), p.N * p.k0, 1e-9);
  EXPECT_NEAR(lumped.damping(1, 1), p.N * p.m * (p.eta0 + p.eta1), 1e-6);
  EXPECT_EQ(lumped.class_of_contact.size(), static_cast<size_t>(p.N));
}

TEST(LinearStructure, RefusesAPartitionThatIsNotEquitable) {
  const auto s = model::tree_structure(ParameterBuilder().set("N=4").build());
  // Splitting an open chain into {1,2} and {3,4} would be equitable only by symmetry
  // of the whole chain; {1} and {2,3,4} is not: miniblock 1 has one neighbour in its class.
  EXPECT_THROW(model::lump(s, {0, 1, 2, 2, 2}), std::invalid_argument);
}
