// Blocks on blocks (docs/model.md §6): the per-level keys and the tree's structure.
#include <gtest/gtest.h>

#include <string>

#include "flat_model.hpp"
#include "model/linear_structure.hpp"
#include "slidespec/parameters.hpp"

using namespace slidespec;

namespace {

bool same_matrix(const Eigen::SparseMatrix<double>& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  const Eigen::MatrixXd da = a;
  return (da.array() == b.array()).all();  // exact: every entry summed in the same order
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

// The one-level tree against the flat model's matrices written out from docs/model.md
// (tests/model/flat_model.hpp), with and without the drive spring.
TEST(Hierarchy, OneLevelTreeIsTheFlatModelBitForBit) {
  for (const char* change : {"chain=open", "chain=ring", "N=1", "k1=0", "drive=spring"}) {
    ParameterBuilder builder;
    builder.set(change).set("levels=1");
    if (std::string(change) == "drive=spring") builder.set("k_drive=3e3");
    const Parameters p = builder.build();
    const auto tree = model::tree_structure(p);
    const as_written::FlatModel flat = as_written::flat_model(p);
    EXPECT_TRUE(same_matrix(tree.mass, flat.mass)) << change;
    EXPECT_TRUE(same_matrix(tree.damping, flat.damping)) << change;
    EXPECT_TRUE(same_matrix(tree.stiffness, flat.stiffness)) << change;
    ASSERT_EQ(tree.contacts.size(), static_cast<size_t>(p.N));
    for (size_t j = 0; j < tree.contacts.size(); ++j) {
      EXPECT_EQ(tree.contacts[j].coordinate, static_cast<int>(j) + 1);
      EXPECT_EQ(tree.contacts[j].random_force_variance, p.random_force_variance());
      EXPECT_EQ(tree.contacts[j].renewal_distance, p.a);
    }
  }
}

// Blocks on blocks under a spring: the load point pulls the top block only.
TEST(Hierarchy, DriveSpringTiesOnlyTheTopBlock) {
  const Parameters force = ParameterBuilder("hierarchical").build();
  const Parameters spring = ParameterBuilder("hierarchical").set("drive=spring").set("k_drive=5e3").build();
  Eigen::MatrixXd difference = Eigen::MatrixXd(model::tree_structure(spring).stiffness) -
                               Eigen::MatrixXd(model::tree_structure(force).stiffness);
  EXPECT_EQ(difference(0, 0), 5e3);
  difference(0, 0) = 0;
  EXPECT_EQ(difference.cwiseAbs().maxCoeff(), 0.0);
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
