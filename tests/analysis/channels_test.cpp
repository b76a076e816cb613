// Force channels and units: a force, a stress or a friction coefficient read in newtons, its
// spectrum C_F, the slip x - F/K of a machine of stiffness K, and length units as labs write
// them. Synthetic records whose exact spectrum is white (docs/model.md §3: C = s^2 dt / 2 pi).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

#include "slidespec/analysis.hpp"

namespace slidespec {
namespace {

constexpr double kDt = 0.1;  // [s]
constexpr int kSamples = 20000;

Record read(const std::string& text, const RecordFormat& format = {}) {
  std::istringstream in(text);
  return read_record(in, "test.txt", format);
}

std::string refusal(const std::string& text, const RecordFormat& format = {}) {
  try {
    read(text, format);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// The share of points whose error bar holds `exact`, and the spectrum for its other checks.
double coverage(const RecordSpectrum& s, double exact) {
  int inside = 0;
  for (const AnalysisPoint& p : s.points) inside += p.lower <= exact && exact <= p.upper ? 1 : 0;
  return double(inside) / double(s.points.size());
}

double white(double rms) { return rms * rms * kDt / (2 * std::numbers::pi); }

/// Rows "t,<columns...>" of `kSamples` samples; `row(k)` gives the fields after the time.
template <class Row>
std::string table(const std::string& header, Row row) {
  std::ostringstream out;
  out.precision(17);
  out << header << "\n";
  for (int k = 0; k < kSamples; ++k) out << k * kDt << "," << row(k) << "\n";
  return out.str();
}

TEST(Channels, HeaderUnitsAsWrittenAndForceColumnsNeverAsDisplacement) {
  const std::string lab = "Time(s)\tDispl(microns)\tFriction\tNormal_stress(MPa)\n0\t10\t0.6\t20\n0.1\t11\t0.6\t20\n";
  const Record r = read(lab);
  EXPECT_EQ(r.column, "Displ(microns)");
  EXPECT_EQ(r.unit, LengthUnit::um);
  EXPECT_DOUBLE_EQ(r.displacement[1], 11e-6);
  RecordFormat friction;
  friction.column = "Friction";
  EXPECT_NE(refusal(lab, friction).find("not a displacement"), std::string::npos) << refusal(lab, friction);
  EXPECT_NE(refusal("t,shear_MPa\n0,1\n1,2\n").find("not a displacement"), std::string::npos);
  EXPECT_NE(refusal("t,mu\n0,0.6\n1,0.61\n").find("friction coefficient"), std::string::npos);
  // The normal stress presses the surfaces together: neither a displacement nor the friction
  // force, and never advised as --force-column.
  RecordFormat normal;
  normal.column = "Normal_stress";
  EXPECT_NE(refusal(lab, normal).find("names a normal load, not a displacement"), std::string::npos)
      << refusal(lab, normal);
  EXPECT_EQ(refusal(lab, normal).find("give it as --force-column"), std::string::npos) << refusal(lab, normal);
  RecordFormat normal_force;
  normal_force.observable = Observable::force;
  normal_force.force_column = "Normal_stress";
  normal_force.contact_area = 0.0025;
  EXPECT_NE(refusal(lab, normal_force).find("--force-column Normal_stress: the header names a normal load"),
            std::string::npos)
      << refusal(lab, normal_force);
  RecordFormat dt;
  dt.dt = 0.1;
  EXPECT_NE(refusal(lab, dt).find("--dt: the record has a time column"), std::string::npos);
  EXPECT_EQ(parse_length_unit("microns"), LengthUnit::um);
  EXPECT_EQ(parse_length_unit("\u00b5m"), LengthUnit::um);
}

TEST(Channels, AColumnIsNamedByItsHeaderWithOrWithoutItsUnit) {
  const std::string lab = "t (s),x (mm),F (N),G [kN]\n0,1,10,1\n0.1,2,11,1\n0.2,3,12,1\n";
  RecordFormat named;
  named.column = "x";
  named.force_column = "F";
  named.observable = Observable::force;
  named.time_column = "t";
  const Record r = read(lab, named);
  EXPECT_EQ(r.column, "x (mm)");
  EXPECT_EQ(r.unit, LengthUnit::mm);
  EXPECT_DOUBLE_EQ(r.force[1], 11);
  named.force_column = "g";  // any case, a unit in square brackets too
  EXPECT_DOUBLE_EQ(read(lab, named).force[1], 1000);
  named.force_column = "F (N)";  // the whole header with its unit
  EXPECT_DOUBLE_EQ(read(lab, named).force[1], 11);
  // Two headers without their units alike: the name is ambiguous, and said so.
  RecordFormat twice;
  twice.column = "x";
  const std::string two = "t,x (mm),x (um)\n0,1,1\n0.1,2,2\n";
  EXPECT_NE(refusal(two, twice).find("names 2 columns"), std::string::npos) << refusal(two, twice);
  twice.column = "x (um)";
  EXPECT_EQ(read(two, twice).unit, LengthUnit::um);
}

TEST(Channels, AForceInKilonewtonsGivesItsSpectrumInNewtons) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0, 0.01);  // [kN]: 10 N rms
  const std::string text = table("t,x (um),F (kN)", [&](int k) {
    std::ostringstream row;
    row.precision(17);
    row << 0.5 * k * kDt << "," << 30 + noise(rng);
    return row.str();
  });
  RecordFormat format;
  format.observable = Observable::force;
  const Record r = read(text, format);
  EXPECT_EQ(r.observable, Observable::force);
  EXPECT_EQ(r.force_channel, "F (kN)");
  const RecordSpectrum s = analyze_record(r, {});
  EXPECT_EQ(s.observable, Observable::force);
  EXPECT_NEAR(s.sliding.x0 + s.sliding.v * s.duration / 2, 30e3, 1);  // the mean force [N]
  EXPECT_GE(coverage(s, white(10)), 0.85) << "C_F of 10 N rms white noise: " << white(10) << " N^2 s";
  // Read as N instead, the spectrum is a million times lower: the unit takes effect.
  format.force_unit = ForceUnit::N;
  EXPECT_GE(coverage(analyze_record(read(text, format), {}), white(0.01)), 0.85);
}

TEST(Channels, FrictionTimesNormalStressTimesAreaIsTheForce) {
  std::mt19937_64 rng(12);
  std::normal_distribution<double> noise(0, 1e-3);
  constexpr double kArea = 0.0025, kSigma = 20;  // [m^2], [MPa]: 50 kN per unit of mu
  const std::string text = table("Time(s),Displ(microns),Friction,Normal_stress(MPa)", [&](int k) {
    std::ostringstream row;
    row.precision(17);
    row << 3 * k * kDt << "," << 0.6 + noise(rng) << "," << kSigma;
    return row.str();
  });
  RecordFormat format;
  format.observable = Observable::force;
  EXPECT_NE(refusal(text, format).find("--contact-area"), std::string::npos) << refusal(text, format);
  format.contact_area = kArea;
  const RecordSpectrum s = analyze_record(read(text, format), {});
  EXPECT_GE(coverage(s, white(1e-3 * kSigma * 1e6 * kArea)), 0.85);
  // A normal force instead of the stress column: F = mu x FN.
  format.contact_area = 0;
  format.normal_force = 1e4;
  EXPECT_GE(coverage(analyze_record(read(text, format), {}), white(1e-3 * 1e4)), 0.85);
}

TEST(Channels, SlipIsTheDisplacementMinusForceOverStiffness) {
  // The load point wanders as a random walk r, the slider slips by v t + w (w white): the
  // machine's spring carries F = F0 + K (x - slip), so x - F/K is the slip whatever r does.
  std::mt19937_64 rng(13);
  std::normal_distribution<double> step(0, 1e-6), w(0, 1e-8);  // [m]
  constexpr double kStiffness = 1e8, kSpeed = 1e-6;            // [N/m], [m/s]
  double walk = 0;
  const std::string text = table("t_s,x (um),F (N)", [&](int k) {
    walk += step(rng);
    const double x = kSpeed * k * kDt + walk, slip = kSpeed * k * kDt + w(rng);
    std::ostringstream row;
    row.precision(17);
    row << x * 1e6 << "," << 5e3 + kStiffness * (x - slip);
    return row.str();
  });
  RecordFormat format;
  format.machine_stiffness = kStiffness;
  const Record r = read(text, format);
  EXPECT_EQ(r.observable, Observable::slip);
  const RecordSpectrum s = analyze_record(r, {});
  EXPECT_NEAR(s.sliding.v, kSpeed, 1e-9);
  EXPECT_GE(coverage(s, white(1e-8)), 0.85);
  // The displacement alone is the random walk, far above the slip's white level.
  EXPECT_LT(coverage(analyze_record(read(text), {}), white(1e-8)), 0.2);
}

TEST(Channels, LengthUnitsAsWrittenAndUnknownOnesRefused) {
  EXPECT_DOUBLE_EQ(read("t,x (cm)\n0,1\n1,2\n").displacement[1], 0.02);
  EXPECT_DOUBLE_EQ(read("t,x [in]\n0,1\n1,2\n").displacement[1], 2 * 0.0254);
  EXPECT_DOUBLE_EQ(read("t,Displ(mm)\n0,1\n1,2\n").displacement[1], 2e-3);
  EXPECT_DOUBLE_EQ(read("t,x_um\n0,1\n1,2\n").displacement[1], 2e-6);
  for (const char* header : {"t,Displ(km)\n", "t,x (furlong)\n", "t,x_ft\n"}) {
    const std::string why = refusal(std::string(header) + "0,1\n1,2\n");
    EXPECT_NE(why.find("not a length unit analyze knows (m, cm, mm"), std::string::npos) << header << why;
  }
  RecordFormat metres;
  metres.unit = LengthUnit::m;  // --units decides over a header analyze cannot read
  EXPECT_DOUBLE_EQ(read("t,Displ(km)\n0,1\n1,2\n", metres).displacement[1], 2);
  EXPECT_EQ(parse_length_unit("inch"), LengthUnit::inch);
  EXPECT_THROW(parse_length_unit("km"), InputError);
  EXPECT_EQ(parse_force_unit("MPa"), ForceUnit::MPa);
  EXPECT_EQ(parse_force_unit("friction"), ForceUnit::mu);
  EXPECT_THROW(parse_force_unit("psi"), InputError);
}

TEST(Channels, EveryOptionTakesEffectOrIsRefusedWithTheReason) {
  const std::string lab = "Time(s)\tDispl(microns)\tFriction\tNormal_stress(MPa)\n0\t10\t0.6\t20\n0.1\t11\t0.6\t20\n";
  const auto refused = [&](const RecordFormat& format, const std::string& why) {
    EXPECT_NE(refusal(lab, format).find(why), std::string::npos)
        << "expected '" << why << "': " << refusal(lab, format);
  };
  // Each format: the force observable (unless said) with one option that cannot take effect.
  const auto force = [](auto change) {
    RecordFormat format;
    format.observable = Observable::force;
    change(format);
    return format;
  };
  const std::pair<RecordFormat, std::string> cases[] = {
      {force([](RecordFormat& f) { f.observable = Observable::automatic, f.contact_area = 0.0025; }),
       "--contact-area: applies to a force channel"},  // the displacement observable reads no area
      {force([](RecordFormat& f) { f.observable = Observable::slip; }), "needs --machine-stiffness"},
      {force([](RecordFormat& f) { f.machine_stiffness = 1e9; }), "--machine-stiffness: gives the slip"},
      {force([](RecordFormat&) {}), "give --contact-area"},  // mu without a normal load
      {force([](RecordFormat& f) { f.normal_force = 1e4, f.normal_stress_column = "Normal_stress(MPa)"; }), "give one"},
      {force([](RecordFormat& f) { f.force_unit = ForceUnit::N, f.normal_force = 1e4; }), "not a friction coefficient"},
      {force([](RecordFormat& f) { f.force_unit = ForceUnit::N, f.contact_area = 0.0025; }), "a force already"},
  };
  for (const auto& [format, why] : cases) refused(format, why);

  EXPECT_DOUBLE_EQ(parse_stiffness("0.01MPa/um", 0.0025, "--machine-stiffness"), 0.01e6 * 0.0025 / 1e-6);
  EXPECT_DOUBLE_EQ(parse_stiffness("2kN/mm", 0, "--machine-stiffness"), 2e6);
  EXPECT_THROW(parse_stiffness("0.01MPa/um", 0, "--machine-stiffness"), InputError);
  EXPECT_DOUBLE_EQ(parse_area("25cm2", "--contact-area"), 25e-4);
  EXPECT_DOUBLE_EQ(parse_force("50kN", "--normal-force"), 5e4);
  EXPECT_THROW(parse_force("-1", "--normal-force"), InputError);
}

}  // namespace
}  // namespace slidespec
