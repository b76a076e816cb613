// Drive through a spring (docs/model.md §9): the theory against a dense solve of
// the full structure written out from the model (tests/model/flat_model.hpp), the
// landmarks the spring brings, and where the first order holds under it (§9.1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "../model/flat_model.hpp"
#include "model/linear_structure.hpp"
#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"
#include "theory_cases.hpp"

using namespace slidespec;

namespace {

Parameters spring_model(const std::vector<std::string>& changes, const char* k_drive = "1e4") {
  ParameterBuilder builder;
  for (const std::string& change : changes) builder.set(change);
  return builder.set("drive=spring").set("k_drive", k_drive).build();
}

const std::vector<double> kOmegas = {1e-3, 0.01, 0.1, 0.3, 1, 3, 10, 100, 350, 548, 1e3, 1e4, 1e5};

}  // namespace

TEST(SpringTheory, EqualsADenseSolveOfTheFullStructure) {
  for (const char* chain : {"chain=open", "chain=ring"})
    for (const char* renewal : {"renewal=poisson", "renewal=periodic"})
      for (const char* k_drive : {"1e2", "1e4"}) {
        const Parameters p = spring_model({"N=12", chain, renewal, "alpha=0.5"}, k_drive);
        const std::vector<double> exact = exact_spectrum(p, kOmegas);
        const LumpedTheory lumped(p);
        for (std::size_t k = 0; k < kOmegas.size(); ++k) {
          const double dense = as_written::flat_model_spectrum(p, kOmegas[k]);
          EXPECT_NEAR(exact[k] / dense, 1.0, 1e-6)
              << chain << " " << renewal << " k_drive " << k_drive << " omega " << kOmegas[k];
          EXPECT_NEAR(lumped(kOmegas[k]) / dense, 1.0, 1e-6) << chain << " " << renewal << " omega " << kOmegas[k];
        }
      }
}

// Blocks on blocks: the tree's own matrices without the spring, the spring added here on
// the top block, solved dense.
TEST(SpringTheory, TreeEqualsADenseSolveWithTheSpringOnTheTopBlock) {
  const Parameters force = ParameterBuilder("hierarchical").set("N=4").set("N_2=3").build();
  const Parameters spring =
      ParameterBuilder("hierarchical").set("N=4").set("N_2=3").set("drive=spring").set("k_drive=3e3").build();
  const model::LinearStructure s = model::tree_structure(force);
  Eigen::MatrixXd K = s.stiffness;
  K(0, 0) += 3e3;
  const std::vector<int> level_of = model::level_of_coordinates(force);
  const std::vector<double> exact = exact_spectrum(spring, kOmegas);
  for (std::size_t k = 0; k < kOmegas.size(); ++k) {
    const double omega = kOmegas[k];
    const Eigen::MatrixXcd Z = K.cast<std::complex<double>>() -
                               omega * omega * Eigen::MatrixXd(s.mass).cast<std::complex<double>>() -
                               std::complex<double>(0, omega) * Eigen::MatrixXd(s.damping).cast<std::complex<double>>();
    const Eigen::MatrixXcd G = Z.fullPivLu().inverse();
    double dense = 0;
    for (const model::Contact& c : s.contacts)
      dense += random_force_spectrum(spring, level_of[static_cast<std::size_t>(c.coordinate)], omega) *
               std::norm(G(0, c.coordinate));
    EXPECT_NEAR(exact[k] / dense, 1.0, 1e-6) << "omega " << omega;
  }
}

// docs/model.md's example: N = 12, ring, alpha = 0.5, k_drive = 1e4 N/m.
TEST(SpringTheory, FlattensBelowOmegaSAndMeetsTheConstantForceAboveTheResonance) {
  const Parameters spring = spring_model({"N=12", "chain=ring", "alpha=0.5"});
  const Parameters force = ParameterBuilder().set("N=12").set("chain=ring").set("alpha=0.5").build();
  const LumpedTheory with_spring(spring), constant_force(force);
  const double flat = spring_low_frequency_limit(spring);
  EXPECT_NEAR(flat, 2.76e-10, 0.02e-10);
  EXPECT_NEAR(with_spring(0.01) / flat, 1.0, 1e-3);
  EXPECT_NEAR(with_spring(0.01) / constant_force(0.01), 1e-4, 0.1e-4);
  EXPECT_NEAR(with_spring(1) / constant_force(1), 0.46, 0.01);
  for (double omega : {10.0, 20.0, 40.0}) {
    // (N k0 / (N k0 + k_drive))^2 = (12/13)^2 well between omega_s and omega_c (0.84 at 100).
    EXPECT_NEAR(with_spring(omega) / constant_force(omega), 144.0 / 169.0, 0.01) << omega;
  }
  for (double omega : {2e3, 1e4}) EXPECT_NEAR(with_spring(omega) / constant_force(omega), 1.0, 0.03) << omega;
  // The spring transmits the contacts' force noise at low frequency: a static force f on a
  // miniblock ends up wholly in the spring, k_drive G_0i(0) = 1.
  EXPECT_NEAR(spring_force_spectrum(spring, flat) / (spring.N * as_written::force_spectrum(spring, 0)), 1.0, 1e-9);
  EXPECT_THROW(spring_low_frequency_limit(force), InputError);
}

TEST(SpringTheory, ResonanceMovesToTheStiffenedBlock) {
  const Parameters p = spring_model({}, "1e5");
  const double resonance = landmarks(p).omega_resonance;
  EXPECT_NEAR(resonance, std::sqrt((30 * 1e4 + 1e5) / 1.0), 1e-9);
  const LumpedTheory theory(p);
  double peak = 0, where = 0;
  for (double omega = 0.8 * resonance; omega < 1.2 * resonance; omega *= 1.0005)
    if (theory(omega) > peak) peak = theory(omega), where = omega;
  EXPECT_NEAR(where / resonance, 1.0, 0.01);
}

TEST(SpringTheory, MovesAtVWithoutDiffusionInEveryTheory) {
  const Parameters p = spring_model({"alpha=3"});  // a constant force would stall here
  for (MotionTheory theory : {MotionTheory::first_order, MotionTheory::second_order, MotionTheory::quasi_static}) {
    const LongTimeMotion motion = long_time_motion(p, theory);
    EXPECT_EQ(motion.mean_speed, p.v);
    EXPECT_EQ(motion.diffusion, 0.0);
  }
  EXPECT_THROW(SecondOrderTheory{p}, InputError);
}

// The load point leads the block's steady place by d0, so that the spring's mean force
// balances the contacts' mean friction, written out from docs/model.md §1: the kinetic
// friction plus the miniblocks' damping at v, F_kin + N m eta1 v (= F_drive).
TEST(SpringTheory, TheSpringsMeanForceBalancesTheFriction) {
  for (const char* k_drive : {"1e2", "1e4", "3e6"})
    for (const char* noise : {"alpha=0.1", "alpha=3"}) {
      const Parameters p = spring_model({"N=12", noise, "F_drive=7.5"}, k_drive);
      const double friction = p.F_kin + p.N * p.m * p.eta1 * p.v;
      EXPECT_NEAR(p.k_drive * landmarks(p).spring_offset / friction, 1.0, 1e-12) << k_drive << " " << noise;
    }
  EXPECT_EQ(landmarks(ParameterBuilder().build()).spring_offset, 0.0);
}

namespace {

// A run under a spring (N = 3, poisson renewal at eps 0.3: 0.64 of the stall boundary) against
// the first order of `theory_params` at each point's omega, scaling the run's own bin-averaged
// first order (`theory_params` = the run's: that column as it is). Returns the points within 2
// standard errors and the worst deviation in standard errors.
std::pair<int, double> spring_run_against_first_order(const char* k_drive, const char* theory_k_drive) {
  Parameters p = poisson(3, 0.3);
  p.drive = Drive::spring;
  p.k_drive = std::stod(k_drive);
  Parameters theory_params = p;
  theory_params.k_drive = std::stod(theory_k_drive);
  const RunResult run = run_spectrum(p, band_request(0.02, 36, 0.02, 31));
  EXPECT_TRUE(run.complete);
  const LumpedTheory own(p), claimed(theory_params);
  int within2 = 0;
  double worst = 0;
  for (const RunPoint& point : run.points) {
    const double expected = point.theory * claimed(point.omega) / own(point.omega);
    const double z = std::fabs(point.C_x - expected) / point.standard_error;
    within2 += z <= 2;
    worst = std::max(worst, z);
  }
  return {within2, worst};
}

}  // namespace

// Under a spring with omega_s = 2 v/a the first order holds near the stall boundary, where
// under a constant force it misses by tens of standard errors (docs/model.md §9.1): every
// point within 4 standard errors, at least 75% within 2 (one sample of 14 points; the map's
// 85% is over two), and best_theory claims it. With omega_s = 0.2 v/a it does not hold and
// best_theory says none.
TEST(SpringTheory, TheFirstOrderHoldsNearTheStallUnderAStiffSpring) {
  const auto [within2, worst] = spring_run_against_first_order("1e4", "1e4");
  EXPECT_LE(worst, 4);
  EXPECT_GE(within2, 11);
  std::printf("omega_s = 2 v/a: worst %.1f stderr, %d of 14 within 2\n", worst, within2);
  Parameters p = poisson(3, 0.3);
  p.drive = Drive::spring;
  p.k_drive = 1e4;
  EXPECT_EQ(best_theory(p).kind, TheoryKind::first_order);
  const auto [soft_within2, soft_worst] = spring_run_against_first_order("1e3", "1e3");
  EXPECT_GT(soft_worst, 4);
  std::printf("omega_s = 0.2 v/a: worst %.1f stderr, %d of 14 within 2\n", soft_worst, soft_within2);
  p.k_drive = 1e3;
  EXPECT_EQ(best_theory(p).kind, TheoryKind::none);
}
