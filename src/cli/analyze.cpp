#include "cli/analyze.hpp"

#include <cmath>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "analysis/report.hpp"
#include "cli/command.hpp"
#include "cli/outputs.hpp"
#include "cli/plot.hpp"
#include "io/atomic_file.hpp"
#include "util/suggest.hpp"
#include "io/tables.hpp"
#include "util/numbers.hpp"
#include "slidespec/analysis.hpp"

namespace slidespec::cli {

struct AnalysisCommands::Options {
  // analyze
  std::string file;
  RecordFormat format;
  std::string units;  // empty: from the header, else m
  std::string observable = "auto";
  std::string force_units;                            // empty: from the force column's header
  std::string contact_area, normal_force, stiffness;  // with their units, or bare in m^2, N, N/m
  std::string estimator = "auto";
  std::string window;             // T0:T1 in record time [s]
  std::string resample = "auto";  // auto, off, median or DT [s]
  bool segments = false;
  std::vector<std::string> notes;             // choices made for the user, said in every output
  std::pair<double, double> analyzed_window;  // [s], record time
  std::string resolution, sensor_noise;       // lengths, in the record's unit or with their own
  AnalysisRequest request;
  std::vector<double> slope_band;  // LO HI [rad/s]
  std::string compare_case;
  std::vector<std::string> overrides;
  std::string fit;
  std::vector<double> fit_band;  // LO HI [rad/s]
  int theory_order = 2;          // 2: the second order where it applies
  double normal_mass = 0, driving_mass = 0;
  std::string out = "analysis";
  bool quiet = false, no_plot = false;
  FigureStyle figure;
  std::string title;
  // synth
  std::string synth_case = "reference";
  std::string synth_params;  // JSON file of parameter overrides
  std::vector<std::string> synth_overrides;
  SensorRequest sensor;
  std::string synth_resolution, synth_sensor_noise;  // lengths, bare in m or with a unit
  std::string synth_units = "um";
  std::string unit_source;    // where analyze took the record's unit from
  std::string force_channel;  // what the analyzed force is made of, in words
  std::string synth_out = "record";
};

namespace {

using Options = AnalysisCommands::Options;
using detail::Verdict;

std::string short_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

// Exit status of a command whose outputs are written but do not hold what they claim.
constexpr int kFitFailedStatus = 3;

Parameters build_parameters(const std::string& case_name, const std::vector<std::string>& overrides) {
  ParameterBuilder builder(case_name);
  for (const auto& assignment : overrides) builder.set(assignment);
  return builder.build();
}

std::string number(double x) { return util::format_number(x); }

/// A record time [s] as a user reads it off the file.
std::string seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", t);
  return text;
}

/// "T0:T1" in seconds of record time.
std::pair<double, double> parse_window(const std::string& text) {
  const auto colon = text.find(':');
  double t0 = 0, t1 = 0;
  std::size_t used0 = 0, used1 = 0;
  try {
    if (colon != std::string::npos) {
      t0 = std::stod(text.substr(0, colon), &used0);
      t1 = std::stod(text.substr(colon + 1), &used1);
    }
  } catch (const std::exception&) {
    used0 = 0;
  }
  if (colon == std::string::npos || used0 != colon || used1 != text.size() - colon - 1 || !std::isfinite(t0) ||
      !std::isfinite(t1) || !(t1 > t0))
    throw InputError("--window: '" + text + "' is not T0:T1 with T0 < T1 in seconds of record time (e.g. 20100:21000)");
  return {t0, t1};
}

/// "auto", "off", "median" or an interval in seconds, into `format`.
void parse_resample(const std::string& text, RecordFormat& format) {
  if (text == "auto") return void(format.resample = Resampling::automatic);
  if (text == "off") return void(format.resample = Resampling::off);
  if (text == "median") return void(format.resample = Resampling::median);
  std::size_t used = 0;
  double dt = 0;
  try {
    dt = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(dt > 0) || !std::isfinite(dt))
    throw InputError("--resample: '" + text + "' is none of auto, off, median or an interval > 0 in seconds");
  format.resample = Resampling::interval;
  format.resample_interval = dt;
}

/// What was asked of analyze beyond the spectrum, and what came of it.
struct Findings {
  std::optional<double> mu;
  std::optional<SlopeFit> slope;
  std::optional<Parameters> model;  // the compared case, at the fitted alpha if fitted
  std::optional<AlphaFit> alpha;
  std::optional<PowerLawFit> power;
  std::optional<ModelFit> joint;  // model parameters fitted jointly (--fit alpha,a)
  Verdict spectrum_verdict;       // the spectrum is one (not 0 everywhere, no inf or nan)
  Verdict slope_verdict, alpha_verdict, power_verdict, joint_verdict;
  std::vector<double> model_values;  // model seen through the estimator, per point
  int model_order = 1;               // the theory order of model_values
  bool ok() const {
    return spectrum_verdict.ok && slope_verdict.ok && alpha_verdict.ok && power_verdict.ok && joint_verdict.ok;
  }
};

std::string analysis_table(const Options& o, const RecordSpectrum& s, const Findings& f) {
  std::ostringstream out;
  if (f.model)
    out << io::metadata_lines(*f.model, o.compare_case);
  else
    out << "# slidespec " << SLIDESPEC_VERSION << "\n";
  const SlidingFit& v = s.sliding;
  const bool force = s.observable == Observable::force;
  const std::string unit = std::string("[") + spectrum_unit(s.observable) + "]", C = force ? "C_F" : "C_x";
  // The label is the figure's legend: a long channel description (a slip's F/K with its
  // units) stays in the observable line, the legend names the observable.
  constexpr std::size_t kLongestLegendChannel = 40;
  out << "# label = measured: " << o.file << " ("
      << (s.channel.size() <= kLongestLegendChannel ? s.channel : std::string(to_string(s.observable))) << ")\n"
      << "# observable = " << to_string(s.observable) << "  # " << C << " " << unit << " of " << s.channel << "\n";
  if (!o.format.column.empty())
    out << "# units = " << to_string(o.format.unit.value_or(LengthUnit::m)) << "  # of the displacement column, from "
        << o.unit_source << "\n";
  out << "# ok = " << (f.ok() ? "true" : "false") << "  # false: a fit failed, or the spectrum is none (see its line)\n"
      << "# spectrum_ok = " << (f.spectrum_verdict.ok ? "true" : "false  # " + f.spectrum_verdict.reason) << "\n"
      << "# record = " << o.file << "\n# samples = " << s.samples << "\n# dt = " << number(s.dt) << "  # [s]\n"
      << "# duration = " << number(s.duration) << "  # [s]\n";
  if (force)
    out << "# mean_force = " << number(v.x0 + v.v * s.duration / 2) << "  # [N]\n# force_trend = " << number(v.v)
        << "  # [N/s] +- " << number(v.v_error) << ", removed with the mean\n# F_rms = " << number(v.xi_rms)
        << "  # [N] rms of F about its trend\n";
  else
    out << "# measured_mean_speed = " << number(v.v) << "  # [m/s] +- " << number(v.v_error) << " (from " << v.blocks
        << " blocks)\n"
        << "# xi_rms = " << number(v.xi_rms) << "  # [m] rms of x - x0 - v t\n";
  if (f.mu) out << "# mu = " << number(*f.mu) << "  # M'/M\n";
  out << "# resolution = " << number(o.request.resolution)
      << "  # q [m]\n# sensor_noise = " << number(o.request.sensor_noise)
      << "  # sigma [m]; floor = q^2/12 + sigma^2, white\n"
      << "# top_to_floor = " << number(s.top_to_floor) << "  # C_x / floor at the highest point\n"
      << "# usable_band = " << detail::usable_band_line(s) << "\n"
      << "# estimator = " << to_string(s.estimator) << "  # " << s.estimator_reason << "\n";
  for (const std::string& note : o.notes) out << "# note = " << note << "\n";
  for (const std::string& line : detail::segment_lines(s)) out << line << "\n";
  if (s.estimator == Estimator::welch)
    out << "# welch = Hann window, 50% overlap, " << s.welch.segments << " segments of " << s.welch.segment_samples
        << " samples, first differences divided by 4 sin^2(omega dt/2); bins " << number(s.welch.bin_spacing)
        << " rad/s apart\n# leaky_points = " << s.leaky_points
        << "  # points the window's leakage may bias high (spectrum steeper than the window allows)\n";
  if (f.slope)
    out << "# slope = " << number(f.slope->slope) << "  # +- " << number(f.slope->slope_error)
        << ", C_x ~ omega^slope over " << number(f.slope->omega_low) << " .. " << number(f.slope->omega_high)
        << " rad/s, " << f.slope->points << " points, chi2/dof " << number(f.slope->chi2_per_dof) << "\n"
        << "# slope_fit_ok = " << (f.slope_verdict.ok ? "true" : "false  # " + f.slope_verdict.reason) << "\n"
        << "# force_slope = " << number(f.slope->force_slope()) << "  # +- " << number(f.slope->slope_error)
        << ", M^2 omega^4 C_x ~ omega^force_slope\n";
  if (f.alpha)
    out << "# fitted_alpha = " << number(f.alpha->alpha) << "  # +- " << number(f.alpha->alpha_error) << " over "
        << number(f.alpha->omega_low) << " .. " << number(f.alpha->omega_high) << " rad/s, " << f.alpha->points
        << " points, chi2/dof " << number(f.alpha->chi2_per_dof) << ", theory order " << f.alpha->theory_order << "\n"
        << "# alpha_fit_ok = " << (f.alpha_verdict.ok ? "true" : "false  # " + f.alpha_verdict.reason) << "\n";
  if (f.power) {
    const PowerLawFit& p = *f.power;
    out << "# power_law = " << C << " = A (omega / " << number(p.pivot) << ")^slope + floor over "
        << number(p.omega_low) << " .. " << number(p.omega_high) << " rad/s, " << p.points << " points, dof " << p.dof
        << ", chi2/dof " << number(p.chi2_per_dof) << "\n# power_law_A = " << number(p.amplitude) << "  # +- "
        << number(p.amplitude_error) << " " << unit << "\n# power_law_slope = " << number(p.slope) << "  # +- "
        << number(p.slope_error) << "\n# power_law_floor = " << number(p.floor) << "  # +- " << number(p.floor_error)
        << " " << unit << (p.floor_given ? ", given (--resolution, --sensor-noise)" : ", fitted") << "\n"
        << "# power_law_correlation = A-slope " << short_number(p.correlation[0][1]) << ", A-floor "
        << short_number(p.correlation[0][2]) << ", slope-floor " << short_number(p.correlation[1][2]) << "\n"
        << "# power_law_fit_ok = " << (f.power_verdict.ok ? "true" : "false  # " + f.power_verdict.reason) << "\n"
        << "# undetermined = " << p.undetermined << "\n";
  }
  if (f.joint) {
    const ModelFit& m = *f.joint;
    out << "# model_fit = " << C << " = " << o.compare_case << "'s theory ("
        << (m.theory_order == 2 ? "second" : "first") << " order) + floor over " << number(m.omega_low) << " .. "
        << number(m.omega_high) << " rad/s, " << m.points << " points, dof " << m.dof << ", chi2/dof "
        << number(m.chi2_per_dof) << (m.converged ? "" : ", NOT converged") << "\n";
    for (std::size_t i = 0; i < m.names.size(); ++i)
      out << "# model_fit_" << m.names[i] << " = " << number(m.values[i]) << "  # +- " << number(m.errors[i])
          << (m.names[i] == "floor" ? " " + unit + ", fitted" : "") << "\n";
    if (m.floor_given) out << "# model_fit_floor = " << number(m.floor) << "  # " << unit << ", given\n";
    out << "# model_fit_alpha2_over_N = " << number(m.amplitude) << "  # +- " << number(m.amplitude_error)
        << ", the level the band sets\n# model_fit_correlation =";
    for (std::size_t i = 0; i < m.names.size(); ++i)
      for (std::size_t k = i + 1; k < m.names.size(); ++k)
        out << " " << m.names[i] << "-" << m.names[k] << " "
            << short_number(m.covariance[i][k] / std::sqrt(m.covariance[i][i] * m.covariance[k][k]));
    out << "\n# model_fit_ok = " << (f.joint_verdict.ok ? "true" : "false  # " + f.joint_verdict.reason) << "\n"
        << "# undetermined = " << m.undetermined << "\n";
  }
  const std::string rate = force ? "C_Fdot = omega^2 C_F [N^2/s]" : "C_v = omega^2 C_x [m^2/s]";
  out << "# columns: omega [rad/s]; " << C << " " << unit << " estimate, mean over the bin's frequencies; stderr "
      << unit << " from the scatter between segments (streaming) or chi-square statistics (welch); floor " << unit
      << " the sensor's white noise q^2/12 + sigma^2 seen through the estimator; below_floor 1 when " << C
      << " < floor + 2 stderr; n_avg; bandwidth [rad/s]; " << rate
      << "; dof equivalent degrees of freedom (stderr = " << C
      << " sqrt(2/dof)); segment FFT length [samples]; leaky 1 when window leakage may bias the point; C_low, "
      << "C_high " << unit << " the error bar, a 95.4% interval (chi-square for welch)";
  if (f.slope) out << "; fit " << unit << " the fitted power law inside its band";
  if (f.power)
    out << "; fit " << unit << " the fitted power law plus floor inside its band; residual (" << C << " - fit) / sigma";
  if (f.joint)
    out << "; fit " << unit << " the fitted model plus floor inside its band; residual (" << C << " - fit) / sigma";
  if (f.model)
    out << "; theory " << unit << " the model's " << (f.model_order == 2 ? "second" : "first")
        << "-order theory seen through the estimator (no floor)";
  out << "\n# omega\t" << C << "\tstderr\tfloor\tbelow_floor\tn_avg\tbandwidth\t" << (force ? "C_Fdot" : "C_v")
      << "\tdof\tsegment\tleaky\tC_low\tC_high" << (f.slope ? "\tfit" : "")
      << (f.power || f.joint ? "\tfit\tresidual" : "") << (f.model ? "\ttheory" : "") << "\n";
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    const AnalysisPoint& p = s.points[k];
    out << number(p.omega) << "\t" << number(p.C_x) << "\t" << number(p.standard_error) << "\t" << number(p.noise_floor)
        << "\t" << (p.below_floor ? 1 : 0) << "\t" << number(p.n_avg) << "\t" << number(p.bandwidth) << "\t"
        << number(velocity_spectrum(p.omega, p.C_x)) << "\t" << number(p.dof) << "\t" << p.segment_samples << "\t"
        << (p.leaky ? 1 : 0) << "\t" << number(p.lower) << "\t" << number(p.upper);
    if (f.slope) {
      const bool inside = p.omega >= f.slope->omega_low && p.omega <= f.slope->omega_high;
      out << "\t" << (inside ? number(f.slope->amplitude * std::pow(p.omega, f.slope->slope)) : "nan");
    }
    if (f.power) out << "\t" << number(f.power->model[k]) << "\t" << number(f.power->residuals[k]);
    if (f.joint) out << "\t" << number(f.joint->model[k]) << "\t" << number(f.joint->residuals[k]);
    if (f.model) out << "\t" << number(f.model_values[k]);
    out << "\n";
  }
  return out.str();
}

std::string analysis_json(const Options& o, const RecordSpectrum& s, const Findings& f) {
  nlohmann::ordered_json doc;
  doc["slidespec_version"] = SLIDESPEC_VERSION;
  doc["ok"] = f.ok();
  doc["record"] = {{"file", o.file},
                   {"column", o.format.column},
                   {"units", to_string(o.format.unit.value_or(LengthUnit::m))},
                   {"units_from", o.unit_source},
                   {"samples", s.samples},
                   {"dt", s.dt},
                   {"duration", s.duration}};
  nlohmann::ordered_json spectrum = detail::spectrum_json(s, f.model ? f.model_values : std::vector<double>{});
  nlohmann::ordered_json points = std::move(spectrum["points"]);
  spectrum.erase("points");
  doc.update(spectrum);  // in the spectrum's order; its points come last, after the fits
  if (s.observable != Observable::displacement) doc["observable"]["force_channel"] = o.force_channel;
  if (s.observable == Observable::slip) doc["observable"]["machine_stiffness"] = o.format.machine_stiffness;
  if (f.mu) doc["mu"] = *f.mu;
  doc["resolution"] = o.request.resolution;
  doc["sensor_noise"] = o.request.sensor_noise;
  doc["notes"] = o.notes;
  doc["record"]["start_time"] = o.analyzed_window.first;
  doc["record"]["end_time"] = o.analyzed_window.second;
  if (f.slope) doc["slope_fit"] = detail::slope_fit_json(*f.slope, f.slope_verdict);
  if (f.power) doc["power_law_fit"] = detail::power_law_json(*f.power, f.power_verdict);
  if (f.joint) doc["model_fit"] = detail::model_fit_json(*f.joint, f.joint_verdict);
  if (f.model) {
    doc["compare_case"] = o.compare_case;
    doc["model_parameters"] = io::parameters_json(*f.model);
    doc["theory_order"] = f.model_order;
  }
  if (f.alpha) doc["alpha_fit"] = detail::alpha_fit_json(*f.alpha, f.alpha_verdict);
  doc["points"] = std::move(points);
  return doc.dump(2) + "\n";
}

void print_segments(const std::vector<SteadySegment>& steady) {
  for (const SteadySegment& s : steady)
    std::cout << seconds(s.start) << "\t" << seconds(s.end) << "\t" << s.samples << "\t" << short_number(s.mean_speed)
              << "\t" << to_string(s.kind) << "\n";
}

/// analyze --segments: the steady stretches, one a line, on standard output; no file written.
/// A record whose sampling rate changes is listed part by part (each read as its own
/// --window), since an analysis can take any one of them.
int list_segments(const Options& o, const Record& record, const std::vector<SteadySegment>& steady) {
  const bool by_parts = record.parts.size() > 1 && !record.resampled && !o.format.window;
  if (!by_parts)
    for (const std::string& note : o.notes) std::cerr << "slidespec: note: " << note << "\n";
  const double first = by_parts ? record.parts.front().start : record.start_time;
  const double last =
      by_parts ? record.parts.back().end : record.start_time + double(record.displacement.size() - 1) * record.dt;
  std::cout << "# steady segments of " << o.file << " (record " << seconds(first) << ".." << seconds(last) << " s";
  if (by_parts)
    std::cout << ", " << record.parts.size() << " parts of different sampling rate, listed one after the other)\n";
  else
    std::cout << ", every " << seconds(record.dt) << " s)\n";
  std::cout << "# start [s]\tend [s]\tsamples\tmean_speed [m/s]\tkind\n";
  if (!by_parts) {
    print_segments(steady);
    return 0;
  }
  for (std::size_t k = 0; k < record.parts.size(); ++k) {
    const SamplingPart& part = record.parts[k];
    std::cout << "# part " << k + 1 << ": " << seconds(part.start) << ".." << seconds(part.end) << " s, every "
              << seconds(part.interval) << " s (--window " << seconds(part.start) << ":" << seconds(part.end) << ")\n";
    RecordFormat format = o.format;
    format.window = {part.start, part.end};
    try {
      const Record piece = read_record_file(o.file, format);
      for (const std::string& note : piece.notes)
        std::cerr << "slidespec: note: part " << k + 1 << ": " << note << "\n";
      print_segments(steady_segments(piece));
    } catch (const InputError& e) {
      std::cout << "# part " << k + 1 << " not listed: " << e.what() << "\n";
    }
  }
  return 0;
}

int command_analyze(Options o) {
  o.figure.check();
  io::check_output_prefix(o.out);
  if (!o.units.empty()) o.format.unit = parse_length_unit(o.units);
  o.format.observable = parse_observable(o.observable);
  if (!o.force_units.empty()) o.format.force_unit = parse_force_unit(o.force_units);
  if (!o.contact_area.empty()) o.format.contact_area = parse_area(o.contact_area, "--contact-area");
  if (!o.normal_force.empty()) o.format.normal_force = parse_force(o.normal_force, "--normal-force");
  if (!o.stiffness.empty())
    o.format.machine_stiffness = parse_stiffness(o.stiffness, o.format.contact_area, "--machine-stiffness");
  o.request.estimator = parse_estimator(o.estimator);
  check_band(o.request);
  Findings f;
  if (o.normal_mass > 0 || o.driving_mass > 0) f.mu = friction_coefficient(o.normal_mass, o.driving_mass);
  std::vector<std::string> fit_names;  // model parameters fitted jointly
  if (!o.fit.empty() && o.fit != "alpha" && o.fit != "power-law") fit_names = parse_fit_parameters(o.fit);
  if ((o.fit == "alpha" || !fit_names.empty()) && o.compare_case.empty())
    throw InputError("--fit " + o.fit + " needs --compare-case NAME");
  if (o.fit == "power-law" && !o.slope_band.empty())
    throw InputError("--fit power-law and --fit-slope both fit a power law; give one (--fit-band sets the band)");
  if (!o.compare_case.empty()) {  // refused before any reading, with the terms the record will add
    std::vector<std::string> ignored;
    build_parameters(o.compare_case, record_terms(o.overrides, 0, o.format.machine_stiffness, ignored));
  }

  if (!o.window.empty()) o.format.window = parse_window(o.window);
  parse_resample(o.resample, o.format);
  Record record = read_record_file(o.file, o.format);
  o.notes = record.notes;
  const std::vector<SteadySegment> steady = steady_segments(record);
  if (o.segments) return list_segments(o, record, steady);
  const std::optional<Strokes> strokes = o.format.window ? std::nullopt : find_strokes(steady, record.dt);
  if (o.format.window) {
    if (steady.size() > 1)
      o.notes.push_back("--window holds " + std::to_string(steady.size()) +
                        " segments (--segments lists them): not one steady slide");
  } else if (!strokes) {
    record = longest_steady(record, steady, o.notes);
  }
  o.analyzed_window = {record.start_time, record.start_time + double(record.displacement.size() - 1) * record.dt};
  o.format.column = record.column;
  o.format.unit = record.unit;
  o.unit_source = record.unit_source;
  o.force_channel = record.force_channel;
  if (!o.resolution.empty()) o.request.resolution = parse_length(o.resolution, record.unit, "--resolution");
  if (!o.sensor_noise.empty()) o.request.sensor_noise = parse_length(o.sensor_noise, record.unit, "--sensor-noise");
  RecordSpectrum s =
      strokes ? analyze_strokes(record, *strokes, o.request, o.notes) : analyze_record(record, o.request);
  s.segments = steady;
  f.spectrum_verdict = detail::judge_spectrum(s);
  if (!o.slope_band.empty()) {
    f.slope = fit_slope(s, o.slope_band[0], o.slope_band[1]);
    f.slope_verdict = detail::judge_chi2(f.slope->chi2_per_dof, f.slope->points - 2);
  }
  if (o.fit == "power-law") {
    f.power = o.fit_band.empty() ? fit_power_law(s, s.points.front().omega, s.points.back().omega)
                                 : fit_power_law(s, o.fit_band[0], o.fit_band[1]);
    f.power_verdict = detail::judge_power_law(*f.power);
  }
  const ModelOrder order = o.theory_order == 2 ? ModelOrder::best : ModelOrder::first;
  if (!o.compare_case.empty())
    f.model = record_model(o.compare_case, o.overrides, measured_speed(record, s), record.machine_stiffness, o.notes);
  if (f.model && !fit_names.empty()) {
    const auto [low, high] =
        o.fit_band.empty() ? std::pair{s.usable_low, s.usable_high} : std::pair{o.fit_band[0], o.fit_band[1]};
    f.joint = fit_model(s, *f.model, fit_names, low, high, order);
    f.joint_verdict = detail::judge_model(*f.joint);
    *f.model = f.joint->fitted;
  }
  if (f.model) {
    if (o.fit == "alpha") {
      const auto [low, high] =
          o.fit_band.empty() ? default_alpha_band(s, *f.model) : std::pair{o.fit_band[0], o.fit_band[1]};
      f.alpha = fit_alpha(s, *f.model, low, high, order);
      f.model->alpha = f.alpha->alpha;
      f.alpha_verdict = detail::judge_alpha(*f.alpha, *f.model);
    }
    // The theory column is the one the alpha fit was made with (first order where it stopped).
    const ModelOrder shown = f.alpha && f.alpha->theory_order == 1 ? ModelOrder::first : order;
    f.model_order = model_order(*f.model, shown);
    f.model_values = model_spectrum(s, *f.model, shown);
  }

  if (!f.ok()) {
    const std::string reason = !f.spectrum_verdict.ok ? f.spectrum_verdict.reason
                               : !f.joint_verdict.ok  ? f.joint_verdict.reason
                               : !f.power_verdict.ok  ? f.power_verdict.reason
                               : !f.alpha_verdict.ok  ? f.alpha_verdict.reason
                                                      : f.slope_verdict.reason;
    o.title = (o.title.empty() ? literal_title(o.file) : o.title) +
              (f.spectrum_verdict.ok ? " - fit FAILED: " : " - no spectrum: ") + reason.substr(0, reason.find(':'));
  }
  io::OutputSet outputs;  // the table, the JSON and the picture appear together or not at all
  outputs.add(o.out + ".tsv", analysis_table(o, s, f));
  outputs.add(o.out + ".json", analysis_json(o, s, f));
  const std::string figure = o.figure.path(o.out);
  const bool plotted =
      !o.no_plot && plot({outputs.temporary(o.out + ".tsv")},
                         outputs.add_written_by_other(figure, std::filesystem::path(figure).extension().string()),
                         o.title, o.figure) == 0;
  // As for run: a set without its figure is not the set asked for, so none of it is written.
  if (!o.no_plot && !plotted)
    throw io::WriteError(figure + " not drawn; no output written (--no-plot writes the table and JSON alone)");
  outputs.commit();
  for (const std::string& note : o.notes) std::cerr << "slidespec: note: " << note << "\n";
  // Warnings and failed fits are printed even with --quiet: they change what the files mean.
  const bool force = s.observable == Observable::force;
  const std::string unit_note =
      force ? "the force " + o.force_channel
            : std::string("read in ") + to_string(record.unit) +
                  (record.unit_source == "default" ? " (no unit in its header)" : " (from " + record.unit_source + ")");
  if (!force && std::abs(s.sliding.v) > kImplausibleSpeed)
    std::cerr << "slidespec: warning: mean speed " << s.sliding.v << " m/s is implausible for friction; likely cause: "
              << "the record was " << unit_note << "; give --units or name the unit in the header, e.g. x (mm)\n";
  if (!(s.usable_high > s.usable_low) && s.floor_above_spectrum)
    std::cerr << "slidespec: warning: no usable band: the sensor floor lies above the spectrum everywhere; likely "
                 "cause: --resolution or --sensor-noise in the wrong unit (a bare number is in "
              << to_string(record.unit) << ", the record's unit; write e.g. 0.5um)\n";
  else if (!(s.usable_high > s.usable_low))
    std::cerr << "slidespec: warning: no usable band: at the lowest point, where the band starts, the spectrum does "
                 "not clear the sensor floor by the factor the usable band needs (the floor at most 10% of "
              << (force ? "C_F" : "C_x") << "; it is "
              << short_number(100 * s.points.front().noise_floor / s.points.front().C_x) << "% there)\n";
  if (s.top_to_floor > 0 && s.top_to_floor < kWhiteFloorShortfall) {
    std::cerr << "slidespec: warning: the highest point lies at " << s.top_to_floor;
    if (s.readings_off_grid)
      std::cerr << " of the white floor: the record's steps are not whole multiples of the --resolution given, "
                   "its sensor reads finer, so the floor line lies too high\n";
    else if (s.quantization_variance == 0)
      std::cerr << " of the white sigma^2 floor: the record holds less noise there than the --sensor-noise "
                   "given, so the floor line lies too high\n";
    else
      std::cerr << " of the white q^2/12 floor: the quantization error is not white (a steady ramp read "
                   "without noise to dither it; docs/analysis.md), so the floor line is only a guide\n";
  }
  if (s.leaky_points > 0)
    std::cerr << "slidespec: warning: " << s.leaky_points << " points may be biased high by the window's leakage "
              << "(the spectrum is steeper than a prewhitened Hann window allows there; column leaky)\n";
  for (const auto& [name, verdict] : {std::pair{"slope", &f.slope_verdict}, std::pair{"alpha", &f.alpha_verdict},
                                      std::pair{"power-law", &f.power_verdict}, std::pair{"model", &f.joint_verdict}})
    if (!verdict->ok) std::cerr << "slidespec: " << name << " fit FAILED: " << verdict->reason << "\n";
  if (!f.spectrum_verdict.ok)
    std::cerr << "slidespec: not a spectrum (marked spectrum_ok = false, exit status 3): " << f.spectrum_verdict.reason
              << "\n";
  const int status = f.ok() ? 0 : kFitFailedStatus;
  if (o.quiet) return status;
  std::cerr << "slidespec: " << o.file << ": " << s.samples << " samples every " << s.dt << " s, " << unit_note;
  if (force)
    std::cerr << "; mean F = " << s.sliding.x0 + s.sliding.v * s.duration / 2 << " N, trend " << s.sliding.v << " +- "
              << s.sliding.v_error << " N/s";
  else
    std::cerr << "; v = " << s.sliding.v << " +- " << s.sliding.v_error << " m/s";
  std::cerr << "\nslidespec: spectrum " << (force ? "C_F [N^2 s]" : "C_x [m^2 s]") << " of the " << s.channel;
  if (f.mu) std::cerr << ", mu = M'/M = " << *f.mu;
  if (s.usable_high > s.usable_low)
    std::cerr << "\nslidespec: usable band " << s.usable_low << " .. " << s.usable_high << " rad/s (top set by "
              << detail::top_set_by(s) << ")";
  else
    std::cerr << "\nslidespec: usable band: " << detail::top_set_by(s);
  std::cerr << "\nslidespec: estimator " << to_string(s.estimator) << " (" << s.estimator_reason << ")";
  if (s.estimator == Estimator::welch)
    std::cerr << ": " << s.welch.segments << " segments of " << s.welch.segment_samples << " samples, dof "
              << short_number(s.points.front().dof) << " at the lowest point, " << short_number(s.points.back().dof)
              << " at the highest";
  std::cerr << "\n";
  if (f.slope && f.slope_verdict.ok) {
    std::cerr << "slidespec: C_x ~ omega^(" << f.slope->slope << " +- " << f.slope->slope_error << ") over "
              << f.slope->omega_low << " .. " << f.slope->omega_high << " rad/s (" << f.slope->points
              << " points, chi2/dof " << f.slope->chi2_per_dof << "); force spectrum ~ omega^("
              << f.slope->force_slope() << ")\n";
    if (f.slope->reaches_floor)
      std::cerr << "slidespec: warning: the slope band reaches beyond the usable band, where the sensor floor "
                   "bends the spectrum\n";
  }
  if (f.power && f.power_verdict.ok) {
    const PowerLawFit& p = *f.power;
    std::cerr << "slidespec: C_x = A (omega/" << short_number(p.pivot) << ")^s + floor over "
              << short_number(p.omega_low) << " .. " << short_number(p.omega_high)
              << " rad/s: A = " << short_number(p.amplitude) << " +- " << short_number(p.amplitude_error)
              << " m^2 s, s = " << short_number(p.slope) << " +- " << short_number(p.slope_error)
              << ", floor = " << short_number(p.floor) << " +- " << short_number(p.floor_error) << " m^2 s"
              << (p.floor_given ? " (given)" : "") << "; chi2/dof " << short_number(p.chi2_per_dof) << " (" << p.dof
              << " dof)\n";
  }
  if (f.power) std::cerr << "slidespec: not determined: " << f.power->undetermined << "\n";
  if (f.joint && f.joint_verdict.ok) {
    const ModelFit& m = *f.joint;
    std::cerr << "slidespec: " << o.compare_case << " fitted over " << short_number(m.omega_low) << " .. "
              << short_number(m.omega_high) << " rad/s:";
    for (std::size_t i = 0; i < m.names.size(); ++i)
      std::cerr << (i ? ", " : " ") << m.names[i] << " = " << short_number(m.values[i]) << " +- "
                << short_number(m.errors[i]);
    std::cerr << "; alpha^2/N = " << short_number(m.amplitude) << " +- " << short_number(m.amplitude_error)
              << "; chi2/dof " << short_number(m.chi2_per_dof) << " (" << m.dof << " dof)\n";
  }
  if (f.joint) std::cerr << "slidespec: not determined: " << f.joint->undetermined << "\n";
  if (f.alpha && f.alpha_verdict.ok)
    std::cerr << "slidespec: alpha = " << f.alpha->alpha << " +- " << f.alpha->alpha_error << " (" << o.compare_case
              << ", " << f.alpha->omega_low << " .. " << f.alpha->omega_high << " rad/s, chi2/dof "
              << f.alpha->chi2_per_dof << ", " << (f.alpha->theory_order == 2 ? "second" : "first")
              << "-order theory)\n";
  std::cerr << "slidespec: wrote " << o.out << ".tsv, .json" << (o.no_plot ? "" : ", ." + o.figure.format)
            << (f.ok() ? "" : " (marked ok = false)") << "\n";
  return status;
}

int command_synth(const Options& o) {
  io::check_output_prefix(o.synth_out);
  const LengthUnit unit = parse_length_unit(o.synth_units);
  ParameterBuilder builder(o.synth_case);
  if (!o.synth_params.empty())
    for (const auto& assignment : read_parameter_file(o.synth_params)) builder.set(assignment);
  for (const auto& assignment : o.synth_overrides) builder.set(assignment);
  const Parameters p = builder.build();
  SensorRequest sensor = o.sensor;
  if (!o.synth_resolution.empty()) sensor.resolution = parse_length(o.synth_resolution, LengthUnit::m, "--resolution");
  if (!o.synth_sensor_noise.empty())
    sensor.sensor_noise = parse_length(o.synth_sensor_noise, LengthUnit::m, "--sensor-noise");
  const Record record = synthesize_record(p, sensor);
  std::ostringstream comments;
  comments << "slidespec " << SLIDESPEC_VERSION << " synth: a simulated slider read by a displacement sensor\n"
           << "case = " << o.synth_case << "\n"
           << "label = " << io::run_label(o.synth_case, p) << "\n";
  for (const auto& [key, value] : describe(p)) comments << key << " = " << value << "\n";
  comments << "seed = " << sensor.seed << "\nsample_interval = " << sensor.sample_interval << " s\n"
           << "resolution = " << sensor.resolution << " m\nsensor_noise = " << sensor.sensor_noise << " m\n"
           << "columns: t (s), x (" << to_string(unit) << ")\n";
  io::write_atomically(o.synth_out + ".csv", record_csv(record, unit, comments.str()));
  std::cerr << "slidespec: wrote " << o.synth_out << ".csv (" << record.displacement.size()
            << " samples); analyse it with: slidespec analyze " << o.synth_out << ".csv --resolution "
            << util::format_number(sensor.resolution) << "m --sensor-noise " << util::format_number(sensor.sensor_noise)
            << "m\n";
  return 0;
}

}  // namespace

int paper_fig6(const std::string& record, const std::string& directory, const FigureStyle& figure, bool quiet) {
  figure.check();
  Options o;
  o.out = directory + "/fig6";
  io::check_output_prefix(o.out);
  o.file = record;
  if (record.empty()) {
    // A measured-like record: the concrete-fit slider read by the paper's sensor.
    Options synth;
    synth.synth_case = "concrete-fit";
    synth.synth_out = directory + "/fig6_record";
    io::check_output_prefix(synth.synth_out);
    command_synth(synth);
    o.file = synth.synth_out + ".csv";
    o.sensor_noise = util::format_number(synth.sensor.sensor_noise) + "m";
  }
  o.resolution = "0.5um";  // the paper's sensor (docs/model.md §5)
  o.compare_case = "concrete-fit";
  o.fit = "alpha";
  o.quiet = quiet;
  o.figure = figure;
  o.title = "Fig. 6: the concrete-fit model (" +
            (record.empty() ? std::string("synthetic record") : literal_title(record)) + ", alpha fitted)";
  return command_analyze(o);
}

AnalysisCommands::AnalysisCommands(CLI::App& app) : options_(std::make_shared<Options>()) {
  Options& o = *options_;
  analyze_ = app.add_subcommand("analyze", "spectrum, slope and model fit of a measured sliding-distance record");
  analyze_->add_option("file", o.file, "CSV/TSV record ('-': stdin): a time column (or --dt) and a displacement column")
      ->required();
  analyze_->add_option("--column", o.format.column, "displacement column (default: x, or the only other column)");
  analyze_->add_option("--time-column", o.format.time_column, "time column [s] (default: t or time)");
  analyze_->add_option("--dt", o.format.dt, "fixed sampling interval [s] instead of a time column");
  analyze_->add_option("--units", o.units,
                       "unit of a displacement column whose header names none: m|cm|mm|um|nm|in (default: from its "
                       "header, e.g. x (mm), else m)");
  analyze_->add_option("--observable", o.observable,
                       "the spectrum asked for: auto (default: slip with --machine-stiffness, force with "
                       "--force-column, else displacement) | displacement (C_x) | force (C_F [N^2 s] of the force "
                       "channel) | slip (C_x of x - F/K)");
  analyze_->add_option("--force-column", o.format.force_column,
                       "force, stress or friction column (default: the first naming one, e.g. Friction, shear_MPa, "
                       "F (N); never a normal one)");
  analyze_->add_option("--force-units", o.force_units,
                       "unit of a force column whose header names none: uN|mN|N|kN|MN|gf|kgf|lbf|Pa|kPa|MPa|psi|mu "
                       "(default: from its header; Friction or mu is mu)");
  analyze_->add_option("--contact-area", o.contact_area,
                       "contact area A (m^2, or 25cm2, 2500mm2): a stress x A is a force, and K in MPa/um x A is N/m");
  analyze_->add_option("--normal-force", o.normal_force, "normal force for a friction column: F = mu x FN (N, or kN)");
  analyze_->add_option("--normal-stress-column", o.format.normal_stress_column,
                       "normal-stress column for a friction column: F = mu x sigma_n x A (default: a column naming a "
                       "normal stress, with --contact-area)");
  analyze_->add_option("--machine-stiffness", o.stiffness,
                       "K: the slider's slip is x - F/K (N/m, kN/mm, or MPa/um with --contact-area); the observable "
                       "becomes the slip");
  analyze_->add_option("--time-tolerance", o.format.time_tolerance,
                       "largest relative deviation of a sampling interval from the median accepted as uniform "
                       "(default 0.01; beyond it: refused, or --resample)");
  analyze_->add_option("--resample", o.resample,
                       "sampling beyond --time-tolerance: auto (default: jitter is interpolated linearly onto the "
                       "median interval, a gap refused), off (refuse), median or DT [s] (interpolate everything, "
                       "gaps and rate changes too); the band is cut where interpolation filters it");
  analyze_->add_option("--window", o.window,
                       "T0:T1: analyze only the samples with T0 <= t <= T1, in record time [s] (default: the "
                       "longest steady segment)");
  analyze_->add_flag("--segments", o.segments,
                     "list the record's steady segments (start, end, mean speed; velocity steps and holds split "
                     "them) on standard output and stop");
  analyze_->add_option("--resolution", o.resolution,
                       "sensor resolution q (record's unit, or with one: 0.5um): draws the q^2/12 floor");
  analyze_->add_option("--sensor-noise", o.sensor_noise,
                       "rms sensor noise before quantization (record's unit, or 0.25um): adds sigma^2 to the floor");
  analyze_->add_option("--omega-min", o.request.omega_min, "lowest omega [rad/s] (default: the record allows)");
  analyze_->add_option("--omega-max", o.request.omega_max,
                       "highest omega [rad/s] (default: Nyquist for welch, half of it for streaming)");
  analyze_->add_option("--points", o.request.points_per_decade, "points per decade (default 8)");
  analyze_->add_option("--estimator", o.estimator,
                       "auto (default: welch up to 1e7 samples, streaming beyond) | welch (Hann, 50% overlap, "
                       "8 segments, from 9 x 2 pi / T to Nyquist) | streaming (the run's estimator)");
  analyze_->add_option("--fit-slope", o.slope_band, "fit C_x ~ omega^-n over LO HI [rad/s]")->expected(2);
  analyze_->add_option("--compare-case", o.compare_case,
                       "overlay this model case's theory on the record's terms: its v the measured one, and with "
                       "--machine-stiffness K driven through a spring k_drive = K (--set keeps what it sets)");
  analyze_->add_option("--set", o.overrides, "override a parameter of the compared case, KEY=VALUE");
  analyze_->add_option("--fit", o.fit,
                       "alpha: fit the compared case's alpha; alpha,a (any of alpha, a, k_drive): fit these model "
                       "parameters jointly with the floor, with covariance and what the band cannot determine; "
                       "power-law: C_x = A (omega/pivot)^s + floor jointly, with errors and correlations (the floor "
                       "fitted unless --resolution/--sensor-noise give it)");
  analyze_
      ->add_option(
          "--fit-band", o.fit_band,
          "band of the fit, LO HI [rad/s] (default: every point for power-law, the usable band for a model fit, "
          "for alpha the usable band within 5 v/a .. omega_c/3)")
      ->expected(2);
  analyze_
      ->add_option("--theory-order", o.theory_order,
                   "2 (default): compare and fit with the second-order theory where it can be computed (one "
                   "touching level, a constant force, periodic renewal to eps 0.25), else the first; 1: the "
                   "first order always (theory_kind in the output says whether either holds)")
      ->check(CLI::IsMember({1, 2}));
  analyze_->add_option("--normal-mass", o.normal_mass, "M, mass loading the slider [kg], for mu = M'/M");
  analyze_->add_option("--driving-mass", o.driving_mass, "M', hanging mass driving it [kg], for mu = M'/M");
  analyze_->add_option("--out", o.out, "output prefix: PREFIX.tsv, .json, .png (default analysis)");
  analyze_->add_flag("--quiet", o.quiet, "no summary");
  analyze_->add_flag("--no-plot", o.no_plot, "skip the figure PREFIX.png");
  o.figure.add_to(*analyze_);
  // --segments lists the record's segments and stops: an output, a fit or a figure would be ignored.
  for (const char* ignored : {"--out", "--fit", "--fit-slope", "--fit-band", "--compare-case", "--set",
                              "--theory-order", "--no-plot", "--format", "--size", "--dpi", "--omega-min",
                              "--omega-max", "--points", "--estimator", "--resolution", "--sensor-noise"})
    if (CLI::Option* option = analyze_->get_option_no_throw(ignored))
      analyze_->get_option("--segments")->excludes(option);

  synth_ = app.add_subcommand("synth", "a synthetic displacement-sensor record of a simulated slider (CSV)");
  synth_->add_option("--case", o.synth_case, "named case (default reference)");
  synth_->add_option("--set", o.synth_overrides, "override a parameter, KEY=VALUE (repeatable)");
  synth_->add_option("--params", o.synth_params,
                     "JSON file of parameter overrides (as for run: a run's output JSON or its parameters block)");
  const SensorRequest sensor_default{};
  synth_->add_option("--sample-interval", o.sensor.sample_interval,
                     with_default("sensor sampling interval [s]", sensor_default.sample_interval));
  synth_->add_option("--duration", o.sensor.duration, with_default("record length [s]", sensor_default.duration));
  synth_->add_option("--resolution", o.synth_resolution,
                     with_default("sensor resolution q, bare in m or with a unit (0.5um), 0 for exact readings",
                                  sensor_default.resolution));
  synth_->add_option("--sensor-noise", o.synth_sensor_noise,
                     with_default("rms noise before quantization, bare in m or with a unit (0.25um), which dithers "
                                  "the quantizer",
                                  sensor_default.sensor_noise));
  synth_->add_option("--seed", o.sensor.seed, with_default("random seed", static_cast<double>(sensor_default.seed)));
  synth_->add_option("--units", o.synth_units, "unit of the x column: m|mm|um (default um)");
  synth_->add_option("--out", o.synth_out, "output prefix: PREFIX.csv (default record)");
}

std::optional<int> AnalysisCommands::run() const {
  if (*analyze_) return command_analyze(*options_);
  if (*synth_) return command_synth(*options_);
  return std::nullopt;
}

}  // namespace slidespec::cli
