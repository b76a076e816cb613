// Force channels and units: a force, a stress or a friction coefficient read in newtons, its
// spectrum C_F, the slip x - F/K of a machine of stiffness K, and length units as labs write
// them. Synthetic records whose exact spectrum is white (docs/model.md §3: C = s^2 dt / 2 pi).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"

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
    return worded(e.what(), FrontEnd::command_line);
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
  // A header without the unit takes the option's: read as N, the spectrum is a million times
  // lower (the unit takes effect).
  std::string bare = text;
  bare.replace(bare.find("F (kN)"), 6, "F");
  format.force_unit = ForceUnit::N;
  EXPECT_GE(coverage(analyze_record(read(bare, format), {}), white(0.01)), 0.85);
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
  EXPECT_THROW(parse_force_unit("furlong"), InputError);
}

TEST(LabHeaders, ABiaxialRigsHeaderSetIsReadWithoutColumnOptions) {
  // As a Penn State-style acquisition names its columns: the load point's displacement in
  // microns, the shear and normal stresses in MPa, the layer's thickness, mu and the
  // effective normal stress (less the pore pressure).
  const std::string header =
      "Time(sec)\tLP_disp(micron)\tShr_stress(MPa)\tNor_disp(micron)\tNor_stress(MPa)\tmu\teffns_mpa\n";
  const std::string lab = header + "100\t5\t12\t300\t20\t0.6\t19.5\n100.1\t5.5\t12\t300\t20\t0.6\t19.5\n";
  const Record r = read(lab);
  EXPECT_EQ(r.column, "LP_disp(micron)");
  EXPECT_EQ(r.unit, LengthUnit::um);
  EXPECT_DOUBLE_EQ(r.displacement[1], 5.5e-6);
  EXPECT_NEAR(r.dt, 0.1, 1e-12);

  RecordFormat shear;
  shear.observable = Observable::force;
  shear.contact_area = 0.0025;  // the first force-like column that is not a normal one
  EXPECT_EQ(read(lab, shear).force_channel, "Shr_stress(MPa) x contact area 0.0025 m^2");
  EXPECT_DOUBLE_EQ(read(lab, shear).force[0], 12e6 * 0.0025);

  // mu has two normal stresses to be made a force with: which one is the lab's to say.
  RecordFormat mu = shear;
  mu.force_column = "mu";
  EXPECT_NE(refusal(lab, mu).find("which column is mu's normal stress: Nor_stress(MPa), effns_mpa?"), std::string::npos)
      << refusal(lab, mu);
  mu.normal_stress_column = "effns";  // named without its unit, as --column takes Displ for Displ(microns)
  EXPECT_DOUBLE_EQ(read(lab, mu).force[0], 0.6 * 19.5e6 * 0.0025);
  mu.normal_stress_column = "Nor_stress";
  EXPECT_DOUBLE_EQ(read(lab, mu).force[0], 0.6 * 20e6 * 0.0025);
  // The normal stress is never the friction force, nor the displacement.
  RecordFormat normal = shear;
  normal.force_column = "Nor_stress";
  EXPECT_NE(refusal(lab, normal).find("names a normal load"), std::string::npos) << refusal(lab, normal);
  normal = {};
  normal.column = "effns_mpa";
  EXPECT_NE(refusal(lab, normal).find("names a normal load, not a displacement"), std::string::npos)
      << refusal(lab, normal);
}

TEST(LabHeaders, TimeUnitsAsLabsWriteThem) {
  const std::pair<const char*, double> cases[] = {
      {"Time(sec)", 1},      {"t (msec)", 1e-3}, {"time [h]", 3600}, {"t_ms", 1e-3},  {"t (us)", 1e-6},
      {"t (\u00b5s)", 1e-6}, {"time (min)", 60}, {"t [hr]", 3600},   {"Time (s)", 1}, {"t_seconds", 1}};
  for (const auto& [name, seconds] : cases) {
    const Record r = read(std::string(name) + ",x (um)\n0,1\n10,2\n20,3\n");
    EXPECT_NEAR(r.dt, 10 * seconds, 1e-9 * seconds) << name;
  }
}

TEST(LabHeaders, AnUnknownTimeUnitIsRefusedAsAnUnknownLengthUnitIs) {
  // Read as seconds, a time in days would give a speed 86400x too high; never silently.
  for (const char* header : {"t (days),x\n", "time [fortnight],x\n", "time_weeks,x\n"}) {
    const std::string why = refusal(std::string(header) + "0,1\n1,2\n");
    EXPECT_NE(why.find("is not a time unit analyze knows (s (sec), ms"), std::string::npos) << header << why;
  }
  RecordFormat named;
  named.time_column = "T";  // named by the option: its header's unit still decides
  EXPECT_NE(refusal("T (days),x\n0,1\n1,2\n", named).find("time column T (days): 'days' is not a time unit"),
            std::string::npos)
      << refusal("T (days),x\n0,1\n1,2\n", named);
  named.time_column = "clock (ms)";
  EXPECT_NEAR(read("clock (ms),x\n0,1\n5,2\n10,3\n", named).dt, 5e-3, 1e-15);
  // A time column without a unit is in seconds, as a displacement without one is in metres.
  EXPECT_NEAR(read("time,x\n0,1\n5,2\n10,3\n").dt, 5, 1e-12);
}

TEST(LabHeaders, ForceAndStressUnitsAsLabsWriteThem) {
  constexpr double kGravity = 9.80665;
  const std::pair<const char*, double> cases[] = {{"Friction [uN]", 1e-6},
                                                  {"F (\u00b5N)", 1e-6},
                                                  {"F (mN)", 1e-3},
                                                  {"F (N)", 1},
                                                  {"F_kN", 1e3},
                                                  {"F (MN)", 1e6},
                                                  {"Ff (gf)", 1e-3 * kGravity},
                                                  {"Fx (g)", 1e-3 * kGravity},
                                                  {"F [kgf]", kGravity},
                                                  {"F (lbf)", 0.45359237 * kGravity},
                                                  {"tau (Pa)", 1},
                                                  {"tau [kPa]", 1e3},
                                                  {"shear_MPa", 1e6},
                                                  {"tau (psi)", 6894.757293168361}};
  for (const auto& [name, si] : cases) {
    RecordFormat format;
    format.observable = Observable::force;
    const std::string text = "t," + std::string(name) + "\n0,2\n1,3\n";
    const bool stress =
        std::string(name).find("tau") != std::string::npos || std::string(name).find("MPa") != std::string::npos;
    if (stress) format.contact_area = 0.5;
    EXPECT_NEAR(read(text, format).force[1], 3 * si * (stress ? 0.5 : 1), 1e-12 * si) << name;
  }
  // mN and MN are a factor 1e9 apart: a header that does not say which names no unit.
  RecordFormat force;
  force.observable = Observable::force;
  EXPECT_NE(refusal("t,F (mn)\n0,2\n1,3\n", force).find("'mn' is not a unit analyze knows"), std::string::npos)
      << refusal("t,F (mn)\n0,2\n1,3\n", force);
  EXPECT_DOUBLE_EQ(parse_force("5mN", "--normal-force"), 5e-3);
  EXPECT_DOUBLE_EQ(parse_force("5MN", "--normal-force"), 5e6);
  EXPECT_DOUBLE_EQ(parse_force("200gf", "--normal-force"), 0.2 * kGravity);
  EXPECT_THROW(parse_force("5mn", "--normal-force"), InputError);
  EXPECT_DOUBLE_EQ(parse_stiffness("2mN/um", 0, "--machine-stiffness"), 2e-3 / 1e-6);
  EXPECT_EQ(parse_force_unit("psi"), ForceUnit::psi);
  EXPECT_EQ(parse_force_unit("kgf"), ForceUnit::kgf);
  EXPECT_EQ(parse_force_unit("\u00b5N"), ForceUnit::uN);
  EXPECT_EQ(parse_length_unit("micron"), LengthUnit::um);
  EXPECT_DOUBLE_EQ(read("t,LP_disp(micron)\n0,1\n1,2\n").displacement[1], 2e-6);
  EXPECT_DOUBLE_EQ(read("t,x (nm)\n0,1\n1,2\n").displacement[1], 2e-9);
}

/// A CETR/Bruker UMT export: the instrument's preamble (settings, a '#' inside a line, blank
/// lines), the header, a row of units (gram-force, mm, sec; none for COF), a blank line.
std::string instrument_export(int samples) {
  std::ostringstream out;
  out << "Created by CETR Data Viewer ver.2.19.106 05/12/22 14:43:46\n"
         "Total number of runs - 1\n"
         "Run # 1\n"
         "Step No. 1\n"
         "\n"
         "Radius       = 3.9493\n"
         "Velocity     = 240\n"
         "Started at: 12:21:58.029 12 May 2022\n"
         "\n"
         "Fx,Fz,Z,X,V1,T,Ff,COF\n"
         "g,g,mm,mm,mm/sec,sec,g,\n"
         "\n";
  for (int k = 0; k < samples; ++k)
    out << 100 + k % 3 << ",-200,-0.69," << 0.05 * k << ",0.5," << 0.02 * k << "," << 100 + k % 3 << ","
        << (100 + k % 3) / 200.0 << "\n";
  return out.str();
}

TEST(LabHeaders, AnInstrumentExportWithAPreambleAndAUnitsRowIsRead) {
  const std::string text = instrument_export(50);
  const Record r = read(text);
  EXPECT_EQ(r.column, "X (mm)");
  EXPECT_EQ(r.unit, LengthUnit::mm);
  EXPECT_DOUBLE_EQ(r.displacement[2], 0.1e-3);
  EXPECT_NEAR(r.dt, 0.02, 1e-12);
  ASSERT_GE(r.notes.size(), 2u);
  EXPECT_EQ(r.notes[0], "lines 1-8 above the header (line 10) are the file's preamble, not read");
  EXPECT_EQ(r.notes[1], "the columns' units are the units row's (line 11)");
  // The force channel: Fx in gram-force (Fz is the normal load, never the friction).
  RecordFormat force;
  force.observable = Observable::force;
  const Record f = read(text, force);
  EXPECT_EQ(f.force_channel, "Fx (g)");
  EXPECT_NEAR(f.force[1], 101e-3 * 9.80665, 1e-12);
  force.force_column = "Fz";
  EXPECT_NE(refusal(text, force).find("names a normal load"), std::string::npos) << refusal(text, force);
  // A units row that contradicts a unit the header already names is refused.
  EXPECT_NE(refusal("t (s),x (mm)\ns,um\n0,1\n1,2\n").find("its header says mm, the units row um"), std::string::npos);
  // Without a units row the line above the numbers is the header, as always; a line below
  // it that holds numbers is a data line gone wrong, refused as one.
  EXPECT_DOUBLE_EQ(read("Sample A7\nt,x (mm)\n0,1\n1,2\n").displacement[1], 2e-3);
  EXPECT_NE(refusal("t,x\n0,abc\n0.1,2\n").find("line 2: column x: 'abc' is not a number"), std::string::npos)
      << refusal("t,x\n0,abc\n0.1,2\n");
  EXPECT_NE(refusal("0,abc\n0.1,2\n").find("line 1: column 2: 'abc' is not a number"), std::string::npos)
      << refusal("0,abc\n0.1,2\n");
  // An export of two steps: the second one's preamble ends the first one's data, said so.
  const std::string two_steps = instrument_export(50) + "\nStep No. 2\n" + instrument_export(50);
  EXPECT_NE(refusal(two_steps).find("line 64: a line of text inside the data"), std::string::npos)
      << refusal(two_steps);
  std::string endless;
  for (int k = 0; k < 1100; ++k) endless += "a line of words\n";
  EXPECT_NE(refusal(endless).find("not one of numbers"), std::string::npos) << refusal(endless);
}

TEST(LabHeaders, UnitOptionsThatContradictTheHeaderAreRefusedNamingBoth) {
  const std::string lab =
      "Time(sec)\tLP_disp(micron)\tShr_stress(MPa)\tmu\tFriction [uN]\n0\t1\t2\t0.6\t70\n"
      "0.1\t2\t2\t0.6\t71\n";
  const auto refused = [&](const RecordFormat& format, const std::string& why) {
    EXPECT_NE(refusal(lab, format).find(why), std::string::npos)
        << "expected '" << why << "': " << refusal(lab, format);
  };
  RecordFormat mm;
  mm.unit = LengthUnit::mm;  // C_x would be 1e6 too high
  refused(mm, "--units mm contradicts the header of column LP_disp(micron), which gives um");
  mm.unit = LengthUnit::um;  // saying what the header says is no contradiction
  EXPECT_DOUBLE_EQ(read(lab, mm).displacement[1], 2e-6);

  RecordFormat force;
  force.observable = Observable::force;
  force.contact_area = 0.0025;
  force.force_unit = ForceUnit::kN;
  refused(force, "--force-units kN contradicts the header of column Shr_stress(MPa), which gives MPa");
  force.force_column = "mu";
  force.force_unit = ForceUnit::MPa;
  refused(force, "--force-units MPa contradicts the header of column mu, which names a friction coefficient");
  force.contact_area = 0;
  force.force_column = "Friction";
  force.force_unit = ForceUnit::N;  // a micro-tribometer's 70 uN read as 70 N
  refused(force, "--force-units N contradicts the header of column Friction [uN], which gives uN");
  force.force_unit = ForceUnit::uN;
  EXPECT_DOUBLE_EQ(read(lab, force).force[1], 71e-6);
  // Friction without a unit is mu, as a biaxial rig writes it: another unit contradicts it.
  RecordFormat bare;
  bare.observable = Observable::force;
  bare.force_unit = ForceUnit::MPa;
  bare.contact_area = 0.0025;
  EXPECT_NE(refusal("t,Friction\n0,0.6\n1,0.6\n", bare).find("which names a friction coefficient mu"),
            std::string::npos);
  // A header naming no unit otherwise takes the option's.
  bare.force_unit = ForceUnit::N;
  bare.contact_area = 0;
  EXPECT_DOUBLE_EQ(read("t,F\n0,2\n1,3\n", bare).force[1], 3);
}

TEST(Channels, EveryOptionTakesEffectOrIsRefusedWithTheReason) {
  const std::string lab =
      "Time(s)\tDispl(microns)\tFriction\tNormal_stress(MPa)\tF\n0\t10\t0.6\t20\t5\n0.1\t11\t0.6\t20\t5\n";
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
      {force([](RecordFormat& f) { f.force_column = "F", f.force_unit = ForceUnit::N, f.normal_force = 1e4; }),
       "not a friction coefficient"},
      {force([](RecordFormat& f) { f.force_column = "F", f.force_unit = ForceUnit::N, f.contact_area = 0.0025; }),
       "a force already"},
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
