// analyze(): the pipeline of `slidespec analyze` and Python's ss.analyze, and the rules of
// what an analysis warns about, written once for both.
#include <cmath>
#include <numeric>
#include <sstream>

#include "analysis/names.hpp"
#include "analysis/report.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"

namespace slidespec {

namespace {

using detail::short_number;
using Kind = AnalysisMessage::Kind;

// A window more than this share of which the whole record calls a hold is a hold.
constexpr double kMostHoldShare = 0.5;
// A mean speed within this many standard errors of 0 is no sliding (a 3-sigma departure).
constexpr double kStillSpeedErrors = 3;

bool fits_model(const std::string& fit) { return !fit.empty() && fit != "alpha" && fit != "power-law"; }

std::vector<AnalysisMessage> as_notes(const std::vector<std::string>& texts, const std::string& topic) {
  std::vector<AnalysisMessage> notes;
  for (const std::string& text : texts) notes.push_back({Kind::note, topic, text, {}});
  return notes;
}

void append(std::vector<AnalysisMessage>& to, std::vector<AnalysisMessage> more) {
  to.insert(to.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end()));
}

/// The stretch of `record` analyzed: all of a window, the strokes of a reciprocating record
/// (`strokes` set), else its longest sliding stretch.
Record analyzed_stretch(Record record, const AnalysisPlan& plan, AnalysisReport& report,
                        std::optional<Strokes>& strokes) {
  report.notes = as_notes(record.notes, "sampling");
  report.segments = steady_segments(record);
  hear_stop(plan.request.stop);
  if (!plan.windowed) strokes = find_strokes(report.segments, record.dt);
  if (strokes) return record;
  if (!plan.windowed) {
    std::vector<std::string> notes;
    record = longest_steady(record, report.segments, notes);
    append(report.notes, as_notes(notes, "window"));
  } else if (report.segments.size() > 1) {
    report.notes.push_back({Kind::note,
                            "window",
                            named(Option::window) + " holds " + std::to_string(report.segments.size()) + " segments (" +
                                named(Option::segments) + " lists them): not one steady slide",
                            {{"stretches", double(report.segments.size())}}});
  }
  return record;
}

std::pair<double, double> band_or(const std::optional<std::pair<double, double>>& band,
                                  std::pair<double, double> otherwise) {
  return band ? *band : otherwise;
}

void fit_power_and_slope(const AnalysisPlan& plan, AnalysisReport& r) {
  const RecordSpectrum& s = r.spectrum;
  if (plan.slope_band) {
    r.slope = fit_slope(s, plan.slope_band->first, plan.slope_band->second);
    r.slope_verdict = detail::judge_chi2(r.slope->chi2_per_dof, r.slope->points - 2);
  }
  if (plan.fit == "power-law") {
    const auto [low, high] = band_or(plan.fit_band, {s.points.front().omega, s.points.back().omega});
    r.power_law = fit_power_law(s, low, high);
    r.power_law_verdict = detail::judge_power_law(*r.power_law);
  }
}

/// What the rig case is built from: the stretch analysed, its measures and the plan's knowledge.
RigTerms rig_terms(const AnalysisPlan& plan, const AnalysisReport& r, const std::vector<FrictionStep>& steps) {
  RigTerms t;
  t.speed = measured_speed(r.record, r.spectrum);
  t.friction_force = plan.rig.friction_force;
  // A reciprocating record's force reverses with each stroke: its strokes' signed mean.
  if (!(t.friction_force > 0) && !r.record.force.empty())
    t.friction_force = r.spectrum.strokes ? stroke_friction(r.record, *r.spectrum.strokes)
                                          : std::accumulate(r.record.force.begin(), r.record.force.end(), 0.0) /
                                                double(r.record.force.size());
  t.normal_force = r.record.normal_force;
  t.machine_stiffness = r.record.machine_stiffness;
  t.slider_mass = plan.rig.slider_mass;
  t.steps = steps;
  t.start = r.record.start_time;
  t.end = r.record.start_time + double(r.record.samples() - 1) * r.record.dt;
  const auto [low, high] = band_or(plan.fit_band, {r.spectrum.usable_low, r.spectrum.usable_high});
  t.omega_low = low, t.omega_high = high;
  return t;
}

/// The compared case on the record's terms, its fitted parameters, and its theory per point.
void compare_model(const AnalysisPlan& plan, AnalysisReport& r, const std::vector<FrictionStep>& steps) {
  const RecordSpectrum& s = r.spectrum;
  std::vector<std::string> notes;
  if (plan.compare_case == kRigCase)
    r.model = rig_model(rig_terms(plan, r, steps), plan.overrides, notes);
  else
    r.model =
        record_model(plan.compare_case, plan.overrides, measured_speed(r.record, s), r.record.machine_stiffness, notes);
  append(r.notes, as_notes(notes, "model_terms"));
  if (fits_model(plan.fit)) {
    const auto [low, high] = band_or(plan.fit_band, {s.usable_low, s.usable_high});
    r.model_fit = fit_model(s, *r.model, parse_fit_parameters(plan.fit), low, high, plan.order);
    r.model_fit_verdict = detail::judge_model(*r.model_fit);
    *r.model = r.model_fit->fitted;
  }
  if (plan.fit == "alpha") {
    const auto [low, high] = plan.fit_band ? *plan.fit_band : default_alpha_band(s, *r.model);
    r.alpha = fit_alpha(s, *r.model, low, high, plan.order);
    r.model->alpha = r.alpha->alpha;
    r.alpha_verdict = detail::judge_alpha(*r.alpha, *r.model);
  }
  // The theory shown is the one the alpha fit was made with (first order where it stopped).
  const ModelOrder shown = r.alpha && r.alpha->theory_order == 1 ? ModelOrder::first : plan.order;
  r.model_order = model_order(*r.model, shown);
  r.model_values = model_spectrum(s, *r.model, shown);
}

std::string stream_number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

AnalysisMessage warning(const std::string& topic, const std::string& text,
                        std::vector<std::pair<std::string, double>> fields = {}) {
  return {Kind::warning, topic, text, std::move(fields)};
}

/// Where the usable band went missing: the floor above the spectrum everywhere (a length in
/// the wrong unit, most often), or not a tenth below it at the lowest point.
AnalysisMessage no_usable_band(const AnalysisReport& r, const AnalysisPlan& plan) {
  const RecordSpectrum& s = r.spectrum;
  if (s.floor_above_spectrum)
    return warning("no_usable_band",
                   "no usable band: the sensor floor lies above the spectrum everywhere; likely cause: " +
                       named(Option::resolution) + " or " + named(Option::sensor_noise) + " in the wrong unit " +
                       (plan.bare_lengths_in_record_unit
                            ? std::string("(a bare number is in ") + to_string(r.record.unit) +
                                  ", the record's unit; write e.g. 0.5um)"
                            : std::string("(both in metres whatever the record's unit: 0.5 um is 0.5e-6)")));
  const AnalysisPoint& lowest = s.points.front();
  return warning("no_usable_band",
                 std::string("no usable band: at the lowest point, where the band starts, the spectrum does not "
                             "clear the sensor floor by the factor the usable band needs (the floor at most 10% of ") +
                     (s.observable == Observable::force ? "C_F" : "C_x") + "; it is " +
                     short_number(100 * lowest.noise_floor / lowest.C_x) + "% there)",
                 {{"floor_share", lowest.noise_floor / lowest.C_x}});
}

/// The top of the band below the white floor: why the floor line misleads there.
AnalysisMessage floor_not_white(const RecordSpectrum& s) {
  const std::string top = "the highest point lies at " + stream_number(s.top_to_floor);
  const std::vector<std::pair<std::string, double>> fields = {{"top_to_floor", s.top_to_floor}};
  if (s.readings_off_grid)
    return warning("floor_not_white",
                   top + " of the white floor: the record's steps are not whole multiples of the " +
                       named(Option::resolution) + " given, its sensor reads finer, so the floor line lies too high",
                   fields);
  if (s.quantization_variance == 0)
    return warning("floor_not_white",
                   top + " of the white sigma^2 floor: the record holds less noise there than the " +
                       named(Option::sensor_noise) + " given, so the floor line lies too high",
                   fields);
  return warning("floor_not_white",
                 top +
                     " of the white q^2/12 floor: the quantization error is not white (a steady ramp read "
                     "without noise to dither it; docs/analysis.md), so the floor line is only a guide",
                 fields);
}

/// The record's unit in words, for a warning that blames it.
std::string unit_words(const Record& record) {
  return std::string("read in ") + to_string(record.unit) +
         (record.unit_source == "default" ? " (no unit in its header)" : " (from " + record.unit_source + ")");
}

std::vector<AnalysisMessage> warnings(const AnalysisReport& r, const AnalysisPlan& plan) {
  const RecordSpectrum& s = r.spectrum;
  std::vector<AnalysisMessage> found;
  // No sensor samples faster than a picosecond: an interval below that is the likelier slip.
  constexpr double kShortestPlausibleInterval = 1e-12;  // [s]
  const bool interval_to_blame = !std::isfinite(s.sliding.v) || r.record.dt < kShortestPlausibleInterval;
  if (s.observable != Observable::force && std::abs(s.sliding.v) > kImplausibleSpeed)
    found.push_back(
        warning("implausible_speed",
                "mean speed " + stream_number(s.sliding.v) + " m/s is implausible for friction; likely cause: " +
                    (interval_to_blame ? "the sampling interval " + stream_number(r.record.dt) + " s (" +
                                             named(Option::dt) + " or the time column's unit wrong?)"
                                       : "the record was " + unit_words(r.record) + "; give " + named(Option::units) +
                                             " or name the unit in the header, e.g. x (mm)"),
                {{"mean_speed", s.sliding.v}}));
  if (!(s.usable_high > s.usable_low)) found.push_back(no_usable_band(r, plan));
  if (s.top_to_floor > 0 && s.top_to_floor < kWhiteFloorShortfall) found.push_back(floor_not_white(s));
  if (s.leaky_points > 0)
    found.push_back(warning("leaky_points",
                            std::to_string(s.leaky_points) +
                                " points may be biased high by the window's leakage (the spectrum is steeper than a "
                                "prewhitened Hann window allows there; column leaky)",
                            {{"leaky_points", s.leaky_points}}));
  if (r.slope && r.slope->reaches_floor)
    found.push_back(
        warning("slope_reaches_floor",
                "the slope band reaches beyond the usable band, where the sensor floor bends the spectrum"));
  for (const auto& [name, verdict] :
       {std::pair{"slope", &r.slope_verdict}, std::pair{"alpha", &r.alpha_verdict},
        std::pair{"power-law", &r.power_law_verdict}, std::pair{"model", &r.model_fit_verdict}})
    if (!verdict->ok)
      found.push_back({Kind::failed_fit, name, std::string(name) + " fit FAILED: " + verdict->reason, {}});
  if (!r.spectrum_verdict.ok) found.push_back({Kind::no_spectrum, "spectrum", r.spectrum_verdict.reason, {}});
  return found;
}

}  // namespace

void check_plan(const AnalysisPlan& plan, double machine_stiffness) {
  check_band(plan.request);
  if (plan.normal_mass > 0 || plan.driving_mass > 0) friction_coefficient(plan.normal_mass, plan.driving_mass);
  if (fits_model(plan.fit)) parse_fit_parameters(plan.fit);
  if ((plan.fit == "alpha" || fits_model(plan.fit)) && plan.compare_case.empty())
    throw InputError(named(Option::fit) + " " + plan.fit + " needs " + named(Option::compare_case) + " NAME");
  if (plan.fit == "power-law" && plan.slope_band)
    throw InputError(named(Option::fit) + " power-law and " + named(Option::fit_slope) +
                     " both fit a power law; give one (" + named(Option::fit_band) + " sets the band)");
  if (plan.compare_case == kRigCase) {
    if (!(machine_stiffness > 0))
      throw InputError(named(Option::compare_case) + " rig: builds the case from the machine's spring; give " +
                       named(Option::machine_stiffness) + " K");
    // Each key and value now; their rules (F_kin below F_drive, ...) need the record's terms.
    ParameterBuilder keys("reference");
    for (const std::string& assignment : plan.overrides) keys.set(assignment);
  } else if (!plan.compare_case.empty()) {  // refused with the terms the record will add
    std::vector<std::string> ignored;
    record_model(plan.compare_case, record_terms(plan.overrides, 0, machine_stiffness, ignored), 0, 0, ignored);
  }
  if (plan.rig.friction_force < 0 || !std::isfinite(plan.rig.friction_force))
    throw InputError(named(Option::friction_force) + ": must be a force > 0");
  if (plan.rig.slider_mass < 0 || !std::isfinite(plan.rig.slider_mass))
    throw InputError(named(Option::slider_mass) + ": must be a mass > 0");
  if ((plan.rig.friction_force > 0 || plan.rig.slider_mass > 0) && plan.compare_case != kRigCase)
    throw InputError(named(plan.rig.friction_force > 0 ? Option::friction_force : Option::slider_mass) +
                     ": used only by " + named(Option::compare_case) + " rig");
}

bool AnalysisReport::ok() const {
  return spectrum_verdict.ok && slope_verdict.ok && alpha_verdict.ok && power_law_verdict.ok && model_fit_verdict.ok;
}

std::string AnalysisReport::failure() const {
  for (const Verdict* verdict :
       {&spectrum_verdict, &model_fit_verdict, &power_law_verdict, &alpha_verdict, &slope_verdict})
    if (!verdict->ok) return verdict->reason;
  return "";
}

double AnalysisReport::end_time() const { return record.start_time + double(record.samples() - 1) * record.dt; }

AnalysisReport analyze(Record record, const AnalysisPlan& plan) {
  hear_stop(plan.request.stop);
  check_plan(plan, record.machine_stiffness);
  AnalysisReport r;
  r.request = plan.request;
  r.request.stop = nullptr;  // the report outlives the analysis's stop
  if (plan.normal_mass > 0 || plan.driving_mass > 0) r.mu = friction_coefficient(plan.normal_mass, plan.driving_mass);
  std::optional<Strokes> strokes;
  // The rig's velocity steps lie outside the stretch analysed: measured on the whole record.
  const std::vector<FrictionStep> steps =
      plan.compare_case == kRigCase ? friction_steps(record, steady_segments(record)) : std::vector<FrictionStep>{};
  r.record = analyzed_stretch(std::move(record), plan, r, strokes);
  hear_stop(plan.request.stop);
  if (strokes) {
    std::vector<std::string> notes;
    r.spectrum = analyze_strokes(r.record, *strokes, plan.request, notes);
    append(r.notes, as_notes(notes, "strokes"));
  } else {
    r.spectrum = analyze_record(r.record, plan.request);
  }
  r.spectrum.segments = r.segments;
  r.spectrum_verdict = detail::judge_spectrum(r.spectrum);
  // A window over a hold is the sensor's noise at rest, not sliding noise.
  if (plan.windowed && r.record.window_hold_share > kMostHoldShare && r.spectrum_verdict.ok)
    r.spectrum_verdict = {false, named(Option::window) + " lies in a hold (" +
                                     short_number(100 * r.record.window_hold_share) +
                                     "% of it; the whole record's segments, " + named(Option::segments) +
                                     "): the record does not slide there, so its spectrum is no sliding noise"};
  // A record whose mean speed is 0 within its error does not slide at all: its spectrum
  // is the sensor's noise at rest (a record of white noise read as "sliding" at 2e-10 m/s).
  const SlidingFit& sliding = r.spectrum.sliding;
  if (!strokes && r.spectrum.observable != Observable::force && r.spectrum_verdict.ok && sliding.v_error > 0 &&
      std::abs(sliding.v) < kStillSpeedErrors * sliding.v_error)
    r.spectrum_verdict = {false, "the record does not slide: its mean speed " + short_number(sliding.v) + " +- " +
                                     short_number(sliding.v_error) + " m/s is 0 within " +
                                     short_number(kStillSpeedErrors) +
                                     " standard errors, so its spectrum is no sliding noise"};
  hear_stop(plan.request.stop);
  fit_power_and_slope(plan, r);
  if (!plan.compare_case.empty()) compare_model(plan, r, steps);
  r.warnings = warnings(r, plan);
  return r;
}

}  // namespace slidespec
