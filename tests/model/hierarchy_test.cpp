// Blocks on blocks (docs/model.md §6): the per-level keys and the tree's structure.
#include <gtest/gtest.h>

#include <string>

#include "model/linear_structure.hpp"
#include "slidespec/parameters.hpp"

using namespace slidespec;

namespace {

bool same_matrix(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b) {
  if (a.rows() != b.rows() || a.nonZeros() != b.nonZeros()) return false;
  const Eigen::MatrixXd da = a, db = b;
  return (da.array() == db.array()).all();  // exact: every entry summed in the same order
}

std::string error_of(const std::vector<std::string>& settings, const char* case_name = "reference") {
  try {
    ParameterBuilder builder(case_name);
    for (const auto& s : settings) builder.set(s);
    builder.build();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Hierarchy, OneLevelTreeIsTheFlatModelBitForBit) {
  for (const char* change : {"chain=open", "chain=ring", "N=1", "k1=0"}) {
    const Parameters p = ParameterBuilder().set(change).set("levels=1").build();
    const auto tree = model::tree_structure(p);
    const auto flat = model::flat_structure(p);
    EXPECT_TRUE(same_matrix(tree.mass, flat.mass)) << change;
    EXPECT_TRUE(same_matrix(tree.damping, flat.damping)) << change;
    EXPECT_TRUE(same_matrix(tree.stiffness, flat.stiffness)) << change;
    ASSERT_EQ(tree.contacts.size(), flat.contacts.size());
    for (size_t j = 0; j < tree.contacts.size(); ++j) {
      EXPECT_EQ(tree.contacts[j].coordinate, flat.contacts[j].coordinate);
      EXPECT_EQ(tree.contacts[j].random_force_variance, flat.contacts[j].random_force_variance);
      EXPECT_EQ(tree.contacts[j].random_force_amplitude, flat.contacts[j].random_force_amplitude);
      EXPECT_EQ(tree.contacts[j].renewal_distance, flat.contacts[j].renewal_distance);
    }
  }
}

TEST(Hierarchy, LevelOneKeysAreTheFlatKeys) {
  const Parameters p = ParameterBuilder().set("N_1=12").set("a_1=2e-3").set("chain_1=ring").build();
  EXPECT_EQ(p.N, 12);
  EXPECT_EQ(p.a, 2e-3);
  EXPECT_EQ(p.chain, ChainEnds::ring);
  // The flat eta1, with the sum over touching blocks written out.
  EXPECT_EQ(p.eta1, ParameterBuilder().set("N=12").set("a=2e-3").set("chain=ring").build().eta1);
}

TEST(Hierarchy, DeeperLevelsFollowTheLevelAboveScaledToSmallerContacts) {
  const Parameters p = ParameterBuilder().set("levels=3").set("m_3=2e-11").build();
  const Level two = p.level(2), three = p.level(3);
  EXPECT_EQ(two.N, 10);
  EXPECT_DOUBLE_EQ(two.m, p.m / 1000);
  EXPECT_DOUBLE_EQ(two.k0, p.k0 / 10);
  EXPECT_DOUBLE_EQ(two.eta0, p.eta0 * 10);
  EXPECT_DOUBLE_EQ(two.a, p.a / 10);
  EXPECT_EQ(three.m, 2e-11);
  EXPECT_DOUBLE_EQ(three.a, p.a / 100);
  EXPECT_TRUE(p.touches(3));
  EXPECT_FALSE(p.touches(1));
  EXPECT_EQ(p.touching_blocks(), 3000);
}

TEST(Hierarchy, SubstrateDampingAndFrictionAreSharedByTheTouchingBlocks) {
  const Parameters p = ParameterBuilder("hierarchical").build();
  ASSERT_EQ(p.levels, 2);
  EXPECT_TRUE(p.touches(1) && p.touches(2));
  EXPECT_EQ(p.touching_blocks(), 330);
  EXPECT_DOUBLE_EQ(p.friction_per_miniblock(), p.F_kin / 330);
  const double touching_mass = 30 * p.m + 300 * p.level(2).m;
  EXPECT_NEAR(p.v * p.eta1 * touching_mass, p.F_drive - p.F_kin, 1e-12);
  EXPECT_NEAR(p.renewal_rate(), p.v / 1e-4, 1e-12);  // the fastest touching level
}

TEST(Hierarchy, BadLevelKeysAreRefusedNamingTheKey) {
  EXPECT_NE(error_of({"levels=2", "m_2=0"}).find("parameter m_2: must be > 0"), std::string::npos);
  EXPECT_NE(error_of({"levels=2", "N_3=4"}).find("parameter N_3"), std::string::npos);
  EXPECT_NE(error_of({"levels=2", "touching=3"}).find("parameter touching"), std::string::npos);
  EXPECT_NE(error_of({"levels=0"}).find("parameter levels"), std::string::npos);
  EXPECT_NE(error_of({"levels=2", "chain_2=ring", "N_2=2"}).find("parameter chain_2"), std::string::npos);
  EXPECT_NE(error_of({"a_2=x"}).find("parameter a_2: 'x' is not a number"), std::string::npos);
  EXPECT_NE(error_of({"levels=2", "alpha_2=-1"}).find("parameter alpha_2"), std::string::npos);
  EXPECT_NE(error_of({"levels=2", "N_2=0"}).find("parameter N_2"), std::string::npos);
  EXPECT_NE(error_of({"eta2_2=1"}).find("unknown parameter 'eta2_2'"), std::string::npos);
  for (const auto& message : {error_of({"levels=2", "m_2=0"}), error_of({"levels=2", "N_3=4"})})
    EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(Hierarchy, TreeLumpsByLevelToLevelsPlusOneCoordinates) {
  for (const char* chain : {"chain_2=open", "chain_2=ring"}) {
    const Parameters p = ParameterBuilder("hierarchical").set(chain).set("chain=ring").build();
    const auto tree = model::tree_structure(p);
    ASSERT_EQ(tree.coordinates(), 1 + 30 + 300);
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(tree.coordinates());
    EXPECT_LT((tree.stiffness * ones).cwiseAbs().maxCoeff(), 1e-9) << chain;
    const auto lumped = model::lumped_tree_structure(p);
    ASSERT_EQ(lumped.mass.rows(), 3);
    EXPECT_NEAR(lumped.mass(2, 2), 300 * p.level(2).m, 1e-12 * lumped.mass(2, 2));
    // Level 1 feels its 10 children per block through k0_2 only: sibling springs cancel.
    EXPECT_NEAR(lumped.stiffness(1, 2), -300 * p.level(2).k0, 1e-9);
    EXPECT_NEAR(lumped.stiffness(1, 1), 30 * p.k0 + 300 * p.level(2).k0, 1e-9);
    EXPECT_EQ(lumped.class_of_contact.size(), 330u);
  }
}
