// The renewal stream: the kernels' Philox4x32-10 against Random123's (the published
// generator), and their -log u against the C library, on every instruction-set path.
#include <Random123/philox.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "stepper/kernel.hpp"
#include "slidespec/simd.hpp"
#include "stepper/renewal.hpp"

using namespace slidespec;

namespace {

constexpr int kLanes = 4096;

struct Counters {
  std::vector<std::uint64_t> word[4];
  Counters() {
    // Counters spread over every bit of each word, plus the edges.
    std::uint64_t state = 0x9E3779B97F4A7C15u;
    for (auto& w : word) w.resize(kLanes);
    for (int l = 0; l < kLanes; ++l)
      for (int i = 0; i < 4; ++i) {
        state = state * 6364136223846793005u + 1442695040888963407u;
        word[i][l] = l < 4 ? (l % 2 ? 0xffffffffu : 0u) : state >> 32;
      }
  }
};

}  // namespace

// Random123's own known-answer vector for philox4x32_10 (its kat_vectors file): counter
// and key all ones give 408f276d 41c83b0e a20bc7c6 6d5451fd.
TEST(RenewalDraws, Random123SatisfiesItsPublishedKnownAnswers) {
  struct Vector {
    std::uint32_t counter[4], key[2], out[4];
  };
  const Vector vectors[] = {
      {{0, 0, 0, 0}, {0, 0}, {0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}},
      {{0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu},
       {0xffffffffu, 0xffffffffu},
       {0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}},
      {{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u},
       {0xa4093822u, 0x299f31d0u},
       {0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}},
  };
  for (const Vector& v : vectors) {
    r123::Philox4x32 philox;
    const auto out = philox({{v.counter[0], v.counter[1], v.counter[2], v.counter[3]}}, {{v.key[0], v.key[1]}});
    for (int i = 0; i < 4; ++i) EXPECT_EQ(out[i], v.out[i]) << "word " << i;
  }
}

TEST(RenewalDraws, EveryPathGivesRandom123sWordsAndTheLogarithmToAnUlp) {
  const Counters counters;
  const std::uint32_t keys[][2] = {{0u, 0u}, {0xffffffffu, 0xffffffffu}, {0x243f6a88u, 0x85a308d3u}};
  for (SimdPath path : available_simd_paths()) {
    const auto& table = stepper::path_kernels(path);
    for (const auto& key : keys) {
      std::vector<std::uint64_t> out[4];
      for (auto& w : out) w.assign(kLanes, 0);
      std::vector<double> exponential(kLanes);
      const std::uint64_t* const in[4] = {counters.word[0].data(), counters.word[1].data(), counters.word[2].data(),
                                          counters.word[3].data()};
      std::uint64_t* const words[4] = {out[0].data(), out[1].data(), out[2].data(), out[3].data()};
      table.draw_lanes(key, in, kLanes, words, exponential.data());
      int wrong_words = 0, wrong_logs = 0;
      double worst_ulps = 0;
      for (int l = 0; l < kLanes; ++l) {
        r123::Philox4x32 philox;
        const r123::Philox4x32::ctr_type c = {
            {static_cast<std::uint32_t>(counters.word[0][l]), static_cast<std::uint32_t>(counters.word[1][l]),
             static_cast<std::uint32_t>(counters.word[2][l]), static_cast<std::uint32_t>(counters.word[3][l])}};
        const auto expected = philox(c, {{key[0], key[1]}});
        for (int i = 0; i < 4; ++i) wrong_words += out[i][l] != expected[i];
        const double u = stepper::draw::open_uniform(expected[2], expected[3]);
        const double exact = -std::log(u);
        const double ulps =
            std::fabs(exponential[l] - exact) / std::max(std::ldexp(1.0, -1074), std::fabs(exact) * 0x1p-52);
        worst_ulps = std::max(worst_ulps, ulps);
        wrong_logs += !(ulps <= 1.0);
      }
      EXPECT_EQ(wrong_words, 0) << to_string(path);
      EXPECT_EQ(wrong_logs, 0) << to_string(path) << ": worst " << worst_ulps << " ulp";
    }
  }
}

// The uniform's ends: all-zero bits give u = 1 (a zero spacing), all ones 2^-52.
TEST(RenewalDraws, TheUniformSpansZeroToOneClosedAtOne) {
  EXPECT_EQ(stepper::draw::open_uniform(0u, 0u), 1.0);
  EXPECT_EQ(stepper::draw::open_uniform(0xffffffffu, 0xffffffffu), 0x1p-52);
  EXPECT_EQ(stepper::draw::force_units(0u), -4294967295.0);
  EXPECT_EQ(stepper::draw::force_units(0xffffffffu), 4294967295.0);
}
