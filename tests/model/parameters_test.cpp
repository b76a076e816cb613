#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "slidespec/parameters.hpp"

using namespace slidespec;

TEST(Parameters, ReferenceCaseDerivesEta1FromSpeed) {
  const Parameters p = ParameterBuilder("reference").build();
  EXPECT_EQ(p.N, 30);
  EXPECT_NEAR(p.eta1, 3.333333e7, 1e2);  // (F_drive - F_kin) / (N m v)
  EXPECT_DOUBLE_EQ(p.v, 0.5e-3);
}

TEST(Parameters, GivingEta1DerivesSpeed) {
  const Parameters p = ParameterBuilder("reference").set("eta1=1e7").build();
  EXPECT_NEAR(p.v, 5.0 / (30 * 1e-5 * 1e7), 1e-15);
}

TEST(Parameters, EveryCaseBuildsAndChangesOnlyItsKeys) {
  const Parameters ref = ParameterBuilder("reference").build();
  for (const Case& c : cases()) {
    const Parameters p = ParameterBuilder(c.name).build();
    EXPECT_EQ(c.name == "many-contacts" ? 100 : 30, p.N) << c.name;
    EXPECT_DOUBLE_EQ(c.name == "fast" ? 5e-3 : 0.5e-3, p.v) << c.name;
    EXPECT_DOUBLE_EQ(c.name == "short-renewal" ? 1e-4 : 1e-3, p.a) << c.name;
    EXPECT_DOUBLE_EQ(p.k0, ref.k0) << c.name;
  }
}

TEST(Parameters, ReferenceLandmarksMatchModelSection4) {
  const Landmarks l = landmarks(ParameterBuilder("reference").build());
  EXPECT_NEAR(l.omega_c, 547.7, 0.1);
  EXPECT_NEAR(l.diffusion, 1.39e-9, 0.01e-9);
  EXPECT_NEAR(l.coupling_eps, 0.0745, 0.0005);
  // Eq. (1) prefactor with the paper's forces equals alpha^2 v^3 / (12 pi N a).
  EXPECT_NEAR(l.eq1_prefactor, 0.5e-3 * 0.5e-3 * 0.5e-3 / (12 * M_PI * 30 * 1e-3), 1e-22);
}

TEST(Parameters, StallRegionIsFlagged) {
  const Landmarks l = landmarks(ParameterBuilder().set("N=7").set("F_drive=8").set("F_kin=6").set("a=3e-4").build());
  EXPECT_NEAR(l.coupling_eps, 0.46, 0.01);
  EXPECT_TRUE(l.forces_can_stall);
}

// Each bad input is refused with an InputError whose one-line message names the key.
struct BadInput {
  const char* name;
  std::vector<const char*> assignments;
  const char* must_mention;
};

class RefusesBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(RefusesBadInput, WithMessageNamingTheKey) {
  const BadInput& bad = GetParam();
  try {
    ParameterBuilder builder;
    for (const char* a : bad.assignments) builder.set(a);
    builder.build();
    FAIL() << "accepted " << bad.name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(bad.must_mention), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Parameters, RefusesBadInput,
    ::testing::Values(
        BadInput{"DriveNotAboveFriction", {"F_drive=5"}, "F_drive"},
        BadInput{"DriveBelowFriction", {"F_drive=4"}, "F_drive"}, BadInput{"NoMiniblocks", {"N=0"}, "N"},
        BadInput{"FractionalN", {"N=2.5"}, "N"}, BadInput{"ZeroBlockMass", {"M=0"}, "M"},
        BadInput{"NegativeMiniblockMass", {"m=-1e-5"}, "m"}, BadInput{"NegativeSpring", {"k0=-1"}, "k0"},
        BadInput{"NegativeChainSpring", {"k1=-1"}, "k1"}, BadInput{"ZeroRenewalDistance", {"a=0"}, "parameter a"},
        BadInput{"NegativeNoise", {"alpha=-0.1"}, "alpha"}, BadInput{"NotANumber", {"v=fast"}, "parameter v"},
        BadInput{"Infinite", {"M=inf"}, "M"}, BadInput{"NaN", {"k0=nan"}, "k0"},
        BadInput{"UnknownKey", {"mass=3"}, "mass"}, BadInput{"MissingEquals", {"N30"}, "N30"},
        BadInput{"EmptyValue", {"N="}, "N"}, BadInput{"BothSpeedAndEta1", {"v=1e-3", "eta1=1e7"}, "eta1"},
        BadInput{"RingTooShort", {"chain=ring", "N=2"}, "ring"}, BadInput{"UnknownChain", {"chain=loop"}, "chain"},
        BadInput{"UnknownRenewal", {"renewal=gamma"}, "renewal"},
        BadInput{"SpringWithoutStiffness", {"drive=spring"}, "parameter k_drive"},
        BadInput{"StiffnessWithoutSpring", {"k_drive=1e4"}, "parameter k_drive"},
        BadInput{"NegativeDriveStiffness", {"drive=spring", "k_drive=-1"}, "parameter k_drive"},
        BadInput{"UnknownDrive", {"drive=rope"}, "parameter drive"}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(Parameters, UnknownCaseIsRefused) { EXPECT_THROW(ParameterBuilder("slow"), InputError); }

// docs/model.md §9: the keys are listed only for a spring, so every output of a
// constant-force model is what it was without them; the landmarks follow the spring.
TEST(Parameters, SpringKeysAreDescribedOnlyWithASpring) {
  const auto force = describe(ParameterBuilder().build());
  for (const auto& [key, value] : force) EXPECT_TRUE(key != "drive" && key != "k_drive") << key;
  const Parameters spring = ParameterBuilder().set("drive=spring").set("k_drive=2e4").build();
  const auto described = describe(spring);
  const auto has = [&](const std::string& key, const std::string& value) {
    return std::find(described.begin(), described.end(), std::make_pair(key, value)) != described.end();
  };
  EXPECT_TRUE(has("drive", "spring"));
  EXPECT_TRUE(has("k_drive", "20000"));
  const Landmarks l = landmarks(spring);
  EXPECT_DOUBLE_EQ(l.omega_s, 2e4 * spring.v / (spring.F_drive - spring.F_kin));
  EXPECT_DOUBLE_EQ(l.omega_resonance, std::sqrt((30 * 1e4 + 2e4) / 1.0));
  EXPECT_EQ(l.diffusion, 0.0);
  // The rest of section 1 holds unchanged: eta1 from v as under a constant force.
  EXPECT_EQ(spring.eta1, ParameterBuilder().build().eta1);
}

TEST(Parameters, K1ZeroIsAllowed) { EXPECT_NO_THROW(ParameterBuilder().set("k1=0").build()); }

// docs/model.md §2's table, generated from parameters.def: the docs list every key with
// its unit, range and reference value, and nothing the table does not have.
std::string markdown_parameter_table() {
  std::ostringstream out;
  out << "| key | meaning | unit | allowed | reference |\n|---|---|---|---|---|\n";
  for (const ParameterInfo& row : parameter_table()) {
    std::ostringstream reference;
    if (row.kind == "real")
      reference << std::stod(row.reference);  // 6 digits: eta1 is 3.33333e+07, not all 17
    else
      reference << row.reference;
    out << "| `" << row.key << "`" << (row.per_level ? ", `" + row.key + "_l`" : "") << " | " << row.doc << " | "
        << (row.unit.empty() ? "–" : row.unit) << " | " << (row.allowed.empty() ? "–" : row.allowed) << " | "
        << reference.str() << " |\n";
  }
  return out.str();
}

TEST(ParameterTable, DocsTableIsGenerated) {
  std::ifstream file(SLIDESPEC_SOURCE_DIR "/docs/model.md");
  ASSERT_TRUE(file) << "cannot read docs/model.md";
  const std::string docs{std::istreambuf_iterator<char>(file), {}};
  const std::string begin = "<!-- generated from include/slidespec/parameters.def -->\n";
  const std::string end = "<!-- end of the generated table -->";
  const auto first = docs.find(begin), last = docs.find(end);
  ASSERT_NE(first, std::string::npos) << "docs/model.md lacks the line " << begin;
  ASSERT_NE(last, std::string::npos) << "docs/model.md lacks the line " << end;
  const std::string expected = markdown_parameter_table();
  EXPECT_EQ(docs.substr(first + begin.size(), last - first - begin.size()), expected)
      << "docs/model.md §2's table differs from parameters.def; put this table between the two lines:\n"
      << expected;
}

// tools/parameter_symbols.tsv, generated from parameters.def: plot_spectra.py reads the
// symbols there, as it runs where the Python module is not built.
TEST(ParameterTable, ToolsSymbolFileIsTheTable) {
  std::ostringstream expected;
  expected << "# How figures write each parameter, generated from include/slidespec/parameters.def (the test\n"
              "# ParameterTable.ToolsSymbolFileIsTheTable prints this file when they differ): key, a tab, and\n"
              "# the symbol in the figure's markup (*italic*, _{subscript}). tools/plot_spectra.py reads it.\n";
  for (const ParameterInfo& row : parameter_table()) expected << row.key << "\t" << row.symbol << "\n";
  std::ifstream file(SLIDESPEC_SOURCE_DIR "/tools/parameter_symbols.tsv");
  ASSERT_TRUE(file) << "cannot read tools/parameter_symbols.tsv";
  const std::string written{std::istreambuf_iterator<char>(file), {}};
  EXPECT_EQ(written, expected.str()) << "tools/parameter_symbols.tsv differs from parameters.def; write it as:\n"
                                     << expected.str();
}

TEST(ParameterTable, EveryKeyParsesAndDescribesItsReferenceValue) {
  // Setting each key to its reference value (as text) rebuilds the reference case exactly.
  const auto reference = describe(ParameterBuilder("reference").build());
  for (const ParameterInfo& row : parameter_table()) {
    if (row.key == "eta1") continue;  // derived from v: giving it too is refused
    ParameterBuilder builder;
    builder.set(row.key, row.reference);
    EXPECT_EQ(describe(builder.build()), reference) << row.key;
  }
}

TEST(ParameterTable, RangesAreChecked) {
  for (const ParameterInfo& row : parameter_table()) {
    if (row.kind != "real" && row.kind != "count") continue;
    if (!std::isfinite(row.range.low)) continue;
    const double outside = row.range.low_included ? row.range.low - 1 : row.range.low;
    std::ostringstream text;
    text << outside;
    try {
      ParameterBuilder().set(row.key, text.str()).build();
      ADD_FAILURE() << row.key << "=" << outside << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("parameter " + row.key + ": must be " + row.allowed), std::string::npos)
          << e.what();
    }
  }
}
