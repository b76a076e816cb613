// Blocks on blocks in theory: one level is today's flat model bit for bit, the tree's
// sparse solve agrees with its lumped form and with an independent branch-by-branch
// reduction, and each touching level puts its own corner at v / a_l.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>

#include "model/linear_structure.hpp"
#include "slidespec/theory.hpp"

using namespace slidespec;

namespace {

const std::vector<double> pinned_omegas = {0.1, 0.7, 3.0, 40.0, 548.0, 3e3, 1e5};

// Printed by the flat model's code at commit f4a5c01 (before levels existed), per omega:
// exact_spectrum, LumpedTheory, SampledTheory(dt = 1e-3); then interval averages over
// [500, 600] and [1, 2]. Exact pins: the tree code must round exactly as the flat did.
const double pinned_flat[3][23] = {
    {0x1.6d2704ad291e1p-25, 0x1.6d2704ad291d7p-25, 0x1.6d27052c43c67p-25,  0x1.4f24caaeddda5p-32,
     0x1.4f24caaedddabp-32, 0x1.4f24cb2227998p-32, 0x1.75b6bfb6a9b86p-40,  0x1.75b6bfb6a9b84p-40,
     0x1.75b6c009df37fp-40, 0x1.926b0147a87bdp-55, 0x1.926b0147a87bbp-55,  0x1.926ade9b04eecp-55,
     0x1.9ce52f06000e2p-62, 0x1.9ce52f06000e4p-62, 0x1.9ce53080dffep-62,   0x1.0114537e8c89fp-89,
     0x1.0114537e8c8b6p-89, 0x1.7a738ff4989e6p-88, 0x1.1c19086d94979p-129, 0x1.1c19086d94973p-129,
     0x1.dc6a581fde0fep-63, 0x1.56ec8f9c8d645p-63, 0x1.e74d784547d1ap-36},
    {0x1.2fcbf3643a96cp-29, 0x1.2fcbf3643a964p-29, 0x1.2fcbf3642a142p-29,  0x1.8c2997186c5fcp-35,
     0x1.8c2997186c603p-35, 0x1.8c299715a9becp-35, 0x1.4f703bdab6f0ep-39,  0x1.4f703bdab6f0ep-39,
     0x1.4f703bb033a68p-39, 0x1.2026b2001d84p-51,  0x1.2026b2001d83ep-51,  0x1.202698c74bb11p-51,
     0x1.f3f63c492de12p-58, 0x1.f3f63c492de13p-58, 0x1.f3f63d67da66fp-58,  0x1.41313e363f293p-85,
     0x1.41313e363f2a5p-85, 0x1.d8d5532f09538p-84, 0x1.0959077d8c8fep-128, 0x1.0959077d8c8fbp-128,
     0x1.bcf91deaa52aap-62, 0x1.b927a6dcdf599p-60, 0x1.824790815994cp-37},
    {0x1.b62ed1125279dp-29, 0x1.b62ed112527cap-29, 0x1.b62ed1aaa173bp-29, 0x1.922bea267d9cap-36,  0x1.922bea267d9b9p-36,
     0x1.922beaaa27d5ep-36, 0x1.c07013ac17383p-44, 0x1.c07013ac1738bp-44, 0x1.c07013885bebap-44,  0x1.df4c04b3b82a5p-59,
     0x1.df4c04b3b82dp-59,  0x1.df4b76c9e2f32p-59, 0x1.c309602ceaebdp-73, 0x1.c309602ceae85p-73,  0x1.c2bf270f1e025p-73,
     0x1.f9506674c3a5ap-90, 0x1.f9506674c3ad2p-90, 0x1.6de8522328ecep-88, 0x1.d8ff72af6b82fp-130, 0x1.d8ff72af6b7ep-130,
     0x1.e5f2ed3496b68p-73, 0x1.c705aae257149p-73, 0x1.246112866136cp-39},
};

Parameters pinned_case(int k) {
  if (k == 0) return ParameterBuilder("reference").build();
  if (k == 1) return ParameterBuilder("short-renewal").set("chain=ring").set("renewal=periodic").build();
  return ParameterBuilder("many-contacts").set("alpha=0.5").set("k1=0").build();
}

double relative(double a, double b) { return std::fabs(a / b - 1); }

}  // namespace

TEST(HierarchyTheory, OneLevelGivesTheFlatModelsNumbersBitForBit) {
  for (int k = 0; k < 3; ++k) {
    const Parameters p = pinned_case(k);
    const auto exact = exact_spectrum(p, pinned_omegas);
    const LumpedTheory lumped(p);
    const SampledTheory sampled(p, 1e-3);
    for (size_t i = 0; i < pinned_omegas.size(); ++i) {
      EXPECT_EQ(exact[i], pinned_flat[k][3 * i]) << k << " omega " << pinned_omegas[i];
      EXPECT_EQ(lumped(pinned_omegas[i]), pinned_flat[k][3 * i + 1]) << k << " omega " << pinned_omegas[i];
      EXPECT_EQ(sampled(pinned_omegas[i]), pinned_flat[k][3 * i + 2]) << k << " omega " << pinned_omegas[i];
    }
    const auto averages = interval_averaged_spectrum(p, {{500.0, 600.0}, {1.0, 2.0}});
    EXPECT_EQ(averages[0], pinned_flat[k][21]);
    EXPECT_EQ(averages[1], pinned_flat[k][22]);
  }
}

TEST(HierarchyTheory, SparseSolveOverEveryBlockEqualsTheLumpedTree) {
  const std::vector<std::vector<const char*>> trees = {
      {},
      {"touching=2", "chain_2=ring"},
      {"levels=3", "N=6", "N_2=4", "N_3=3", "touching=1,3", "renewal=periodic"},
  };
  const auto omegas = log_spaced_omegas(0.01, 1e6, 4);
  for (const auto& changes : trees) {
    ParameterBuilder builder("hierarchical");
    for (const char* c : changes) builder.set(c);
    const Parameters p = builder.build();
    const auto exact = exact_spectrum(p, omegas);
    const LumpedTheory lumped(p);
    for (size_t i = 0; i < omegas.size(); ++i)
      EXPECT_LT(relative(lumped(omegas[i]), exact[i]), 1e-8) << changes.size() << " omega " << omegas[i];
  }
}

// With k1 = 0 at every level the branches under the block (a level-1 block and all it
// carries) are independent: eliminating one branch by hand (its Schur complement at the
// block) and adding N identical branches must give the tree's spectrum.
TEST(HierarchyTheory, TreeWithoutSiblingSpringsIsTheSumOfIndependentBranches) {
  const Parameters p = ParameterBuilder("hierarchical").set("k1=0").set("k1_2=0").build();
  Parameters branch = p;  // the block's mass is added once below, not per branch
  branch.N = 1;
  branch.M = 0;
  const auto s = model::tree_structure(branch);
  const int n = s.coordinates();
  const std::vector<int> level_of = model::level_of_coordinates(branch);
  const auto omegas = log_spaced_omegas(0.01, 1e6, 3);
  const auto tree = exact_spectrum(p, omegas);
  using Complex = std::complex<double>;
  for (size_t i = 0; i < omegas.size(); ++i) {
    const double w = omegas[i];
    const Eigen::MatrixXcd Z = Eigen::MatrixXd(s.stiffness).cast<Complex>() -
                               w * w * Eigen::MatrixXd(s.mass).cast<Complex>() -
                               Complex(0, w) * Eigen::MatrixXd(s.damping).cast<Complex>();
    const Eigen::MatrixXcd Zbb = Z.bottomRightCorner(n - 1, n - 1);
    const Eigen::RowVectorXcd transfer = Z.block(0, 1, 1, n - 1) * Zbb.inverse();
    const Complex schur = Z(0, 0) - (transfer * Z.block(1, 0, n - 1, 1))(0, 0);
    const Complex block_compliance = 1.0 / (-w * w * p.M + static_cast<double>(p.N) * schur);
    double branch_sum = 0;
    for (int j = 1; j < n; ++j) {
      const int l = level_of[static_cast<size_t>(j)];
      if (p.touches(l)) branch_sum += random_force_spectrum(p, l, w) * std::norm(block_compliance * transfer(j - 1));
    }
    EXPECT_LT(relative(p.N * branch_sum, tree[i]), 1e-8) << "omega " << w;
  }
}

// Below the block's resonance the whole tree moves as one damped body, so
// C_x = sum_l n_l S_f,l(omega) / ((F_drive - F_kin)/v)^2 / omega^2: each touching level
// turns from omega^-2 to omega^-4 at its own v / a_l.
TEST(HierarchyTheory, EachTouchingLevelPutsItsCornerAtItsRenewalRate) {
  const Parameters p = ParameterBuilder("hierarchical").set("a_2=1e-5").build();
  const double lambda1 = p.renewal_rate(1), lambda2 = p.renewal_rate(2);
  ASSERT_NEAR(lambda2 / lambda1, 100, 1e-9);
  const double drag = (p.F_drive - p.F_kin) / p.v;
  const auto omegas = log_spaced_omegas(0.01, 20, 8);
  const auto exact = exact_spectrum(p, omegas);
  std::vector<double> omega2_C;
  for (size_t i = 0; i < omegas.size(); ++i) {
    const double w = omegas[i];
    double forcing = 0;
    for (int l = 1; l <= 2; ++l) forcing += static_cast<double>(p.blocks(l)) * random_force_spectrum(p, l, w);
    EXPECT_LT(relative(exact[i], forcing / (drag * drag * w * w)), 0.02) << "omega " << w;
    omega2_C.push_back(w * w * exact[i]);
  }
  // omega^2 C_x: a plateau below v/a_1 (weights n_l s2 / lambda_l: 30/0.5 + 300/50), a
  // second, ten times lower one between the corners (level 2 still white, 300/50), then
  // the fall past v/a_2 = 50 rad/s, begun by the last point (17.8 rad/s).
  const size_t between = 22;  // 5.6 rad/s, near sqrt(lambda1 lambda2)
  ASSERT_NEAR(omegas[between], 5.62, 0.01);
  EXPECT_GT(omega2_C.front() / omega2_C[between], 9);
  EXPECT_LT(omega2_C.front() / omega2_C[between], 11);
  EXPECT_GT(omega2_C[between] / omega2_C.back(), 1.15);
}

// The exact step of a stiff tree (microblock velocities relax in 30 ns) still gives the
// continuous-time spectrum as omega dt -> 0: O((omega dt)^2) apart, 1e-4 at omega dt = 0.01.
TEST(HierarchyTheory, SampledTreeTendsToTheContinuousSpectrum) {
  for (const char* touching : {"touching=1,2", "touching=2"}) {
    const Parameters p = ParameterBuilder("hierarchical").set(touching).build();
    const double dt = 1e-4;
    const SampledTheory sampled(p, dt);
    const LumpedTheory continuous(p);
    for (double omega : {1.0, 10.0, 100.0})
      EXPECT_LT(relative(sampled(omega), continuous(omega)), 1e-3) << touching << " omega " << omega;
  }
}
