#include "analysis/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "analysis/names.hpp"
#include "io/points.hpp"
#include "util/numbers.hpp"
#include "slidespec/theory.hpp"

namespace slidespec::detail {

namespace {
constexpr const char* kFloorFromTheLowestPoint =
    "the sensor floor exceeds 10% of the spectrum from the lowest point on";
const std::string kNoUsableBand = std::string("none: ") + kFloorFromTheLowestPoint;
}  // namespace

std::string no_usable_band_for_fit(const std::string& fit) {
  return "{fit} " + fit + ": no usable band (" + kFloorFromTheLowestPoint + "); give {fit_band} LO HI";
}

}  // namespace slidespec::detail

namespace slidespec {

std::string top_set_by(const RecordSpectrum& s) {
  if (!s.has_usable_band()) return detail::kNoUsableBand;
  if (s.usable_high_set_by_floor) return "the sensor floor reaching 10% of the spectrum";
  if (s.top_set_by_interpolation)
    return "the interpolation filter of resampling samples " + detail::short_number(s.interpolation_interval) +
           " s apart";
  if (s.top_set_by_omega_max) return "the omega_max asked for";
  if (s.estimator == Estimator::welch) return "the bin below Nyquist";
  return "half of Nyquist";
}

}  // namespace slidespec

namespace slidespec::detail {

nlohmann::ordered_json spectrum_json(const RecordSpectrum& s, const Verdict& verdict,
                                     const std::vector<double>& theory) {
  nlohmann::ordered_json doc;
  doc["segments"] = nlohmann::ordered_json::array();
  for (const SteadySegment& g : s.segments)
    doc["segments"].push_back({{"start", g.start},
                               {"end", g.end},
                               {"kind", to_string(g.kind)},
                               {"mean_speed", g.mean_speed},
                               {"hold", g.hold}});
  if (s.strokes)
    doc["strokes"] = {{"count", s.strokes->middles.size()},
                      {"speed", s.strokes->speed},
                      {"middle_duration", s.strokes->middle_duration},
                      {"lowest_omega", s.strokes->lowest_omega}};
  const bool force = s.observable == Observable::force;
  const char* name = spectrum_name(s.observable);
  doc["observable"] = {{"name", to_string(s.observable)},
                       {"spectrum", name},
                       {"unit", spectrum_unit(s.observable)},
                       {"channel", s.channel}};
  doc["spectrum_ok"] = verdict.ok;
  if (!verdict.ok) doc["spectrum_failure"] = verdict.reason;
  if (force) {
    doc["mean_force"] = s.mean_force();
    doc["force_trend"] = {{"value", s.sliding.v}, {"standard_error", s.sliding.v_error}};
    doc["F_rms"] = s.sliding.xi_rms;
  } else {
    doc["measured_mean_speed"] = {
        {"value", s.sliding.v}, {"standard_error", s.sliding.v_error}, {"blocks", s.sliding.blocks}};
    doc["xi_rms"] = s.sliding.xi_rms;
  }
  doc["quantization_variance"] = s.quantization_variance;
  doc["top_to_floor"] = s.top_to_floor;
  doc["readings_off_grid"] = s.readings_off_grid;
  doc["usable_band"] = {{"omega_low", s.usable_low},
                        {"omega_high", s.usable_high},
                        {"empty", !s.has_usable_band()},
                        {"floor_above_spectrum", s.floor_above_spectrum},
                        {"top_set_by", top_set_by(s)}};
  doc["estimator"] = {{"name", to_string(s.estimator)}, {"reason", s.estimator_reason}};
  if (s.estimator == Estimator::welch) {
    doc["estimator"]["window"] = kWelchWindow;
    doc["estimator"]["overlap"] = kWelchOverlap;
    doc["estimator"]["prewhitening"] = kWelchPrewhitening;
    doc["estimator"]["segment_samples"] = s.welch.segment_samples;
    doc["estimator"]["segments"] = s.welch.segments;
    doc["estimator"]["bin_spacing"] = s.welch.bin_spacing;
    doc["estimator"]["leaky_points"] = s.leaky_points;
  }
  doc["points"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    const AnalysisPoint& p = s.points[k];
    nlohmann::ordered_json point = io::point_json(p.omega, name, p.C_x, p.standard_error, p.n_avg, p.bandwidth);
    point["floor"] = p.noise_floor;
    point["below_floor"] = p.below_floor;
    point["dof"] = p.dof;
    point["segment_samples"] = p.segment_samples;
    point["leaky"] = p.leaky;
    point["C_low"] = p.lower;
    point["C_high"] = p.upper;
    if (s.estimator == Estimator::welch) {
      point["first_bin"] = s.welch.points[k].first_bin;
      point["bins"] = s.welch.points[k].bins;
    }
    if (!theory.empty()) point["theory"] = theory[k];
    doc["points"].push_back(point);
  }
  return doc;
}

}  // namespace slidespec::detail

namespace slidespec::detail {

namespace {

void add_reason(Verdict& verdict, const std::string& reason) {
  verdict.reason += (verdict.ok ? "" : "; ") + reason;
  verdict.ok = false;
}

nlohmann::ordered_json with_verdict(nlohmann::ordered_json doc, const Verdict& verdict) {
  doc["ok"] = verdict.ok;
  doc["failure"] = verdict.reason;
  return doc;
}
}  // namespace

Verdict judge_chi2(double chi2_per_dof, int dof) {
  if (std::isnan(chi2_per_dof))
    return {false, "chi2/dof is not a number: the band holds nothing to fit (a spectrum of 0, or no spread)"};
  const double allowed = std::max(3.0, 1 + 5 * std::sqrt(2.0 / std::max(dof, 1)));
  if (chi2_per_dof <= allowed) return {};
  return {false, "chi2/dof " + short_number(chi2_per_dof) + " > " + short_number(allowed) +
                     ": the fitted curve does not describe the data in the band"};
}

Verdict judge_alpha(const AlphaFit& fit, const Parameters& fitted) {
  Verdict verdict = judge_chi2(fit.chi2_per_dof, fit.points - 1);
  if (!fit.order_not_reached.empty()) add_reason(verdict, fit.order_not_reached);
  const TheoryChoice holds = best_theory(fitted);
  if (holds.kind == TheoryKind::none) add_reason(verdict, "no theory holds at the fitted alpha: " + holds.reason);
  return verdict;
}

Verdict judge_spectrum(const RecordSpectrum& s) {
  const char* name = s.observable == Observable::force ? "C_F" : "C_x";
  for (const AnalysisPoint& point : s.points)
    if (!std::isfinite(point.C_x) || !std::isfinite(point.standard_error) || !std::isfinite(point.omega))
      return {false, std::string("the point at omega = ") + short_number(point.omega) + " rad/s holds inf or nan: " +
                         "beyond the range of a double (the sampling interval, units or stiffness given?)"};
  for (const AnalysisPoint& point : s.points)
    if (point.C_x != 0 && std::abs(point.C_x) < util::kSmallestSquarableSpectrum)
      return {false, std::string("the point at omega = ") + short_number(point.omega) + " rad/s holds " + name + " = " +
                         short_number(point.C_x) + ", below the " + short_number(util::kSmallestSquarableSpectrum) +
                         " whose square (its error bar) a double holds (the record's unit given?)"};
  if (!s.points.empty() &&
      std::all_of(s.points.begin(), s.points.end(), [](const AnalysisPoint& p) { return p.C_x == 0; }))
    return {false, std::string(name) +
                       " is 0 at every point: the record holds no fluctuation (a constant, or "
                       "values below the resolution of a double); no spectrum was measured"};
  return {};
}

Verdict judge_model(const ModelFit& fit) {
  Verdict verdict = judge_chi2(fit.chi2_per_dof, fit.dof);
  if (!fit.converged) add_reason(verdict, "the iteration did not settle: no minimum of chi2 was found");
  for (const std::string& name : fit.at_search_edge)
    add_reason(verdict, name +
                            " ran to the edge of its search range (a factor 1e4 from the compared case's): the "
                            "band does not bound it; fix it with {set} and fit fewer parameters");
  const TheoryChoice holds = best_theory(fit.fitted);
  if (holds.kind == TheoryKind::none) add_reason(verdict, "no theory holds at the fitted parameters: " + holds.reason);
  return verdict;
}

Verdict judge_power_law(const PowerLawFit& fit) {
  Verdict verdict = judge_chi2(fit.chi2_per_dof, fit.dof);
  const std::string range = short_number(kSteepestPowerLawSlope) + " .. " + short_number(kFlattestPowerLawSlope);
  const char* unbounded =
      ": the band does not bound it (a longer stretch of record reaches lower frequencies; "
      "{resolution} or {sensor_noise} give the floor)";
  if (fit.slope_at_search_edge)
    add_reason(verdict, "the slope " + short_number(fit.slope) + " ran to the edge of its search range (" + range +
                            ")" + unbounded);
  else if (fit.slope - fit.slope_error < kSteepestPowerLawSlope && fit.slope + fit.slope_error > kFlattestPowerLawSlope)
    add_reason(verdict, "the slope's error bar " + short_number(fit.slope) + " +- " + short_number(fit.slope_error) +
                            " spans its whole search range (" + range + ")" + unbounded);
  // A correlation that rounds to 1 leaves the covariance singular: the two parameters move
  // together (A and the floor where the slope is 0) and their errors mean nothing.
  constexpr double kIndistinguishable = 0.9995;
  const char* names[] = {"the amplitude", "the slope", "the floor"};
  const int parameters = fit.floor_given ? 2 : 3;
  for (int i = 0; i < parameters; ++i)
    for (int j = i + 1; j < parameters; ++j)
      if (!(std::fabs(fit.correlation[i][j]) <= kIndistinguishable))
        add_reason(verdict, std::string(names[i]) + " and " + names[j] +
                                " are not told apart by the band (correlation " + short_number(fit.correlation[i][j]) +
                                "): their errors mean nothing");
  return verdict;
}

nlohmann::ordered_json slope_fit_json(const SlopeFit& f, const Verdict& verdict) {
  return with_verdict({{"omega_low", f.omega_low},
                       {"omega_high", f.omega_high},
                       {"points", f.points},
                       {"slope", f.slope},
                       {"standard_error", f.slope_error},
                       {"chi2_per_dof", f.chi2_per_dof},
                       {"amplitude", f.amplitude},
                       {"force_slope", f.force_slope()},
                       {"reaches_floor", f.reaches_floor}},
                      verdict);
}

nlohmann::ordered_json power_law_json(const PowerLawFit& p, const Verdict& verdict) {
  nlohmann::ordered_json correlation = nlohmann::ordered_json::array();
  for (const auto& row : p.correlation) correlation.push_back({row[0], row[1], row[2]});
  return with_verdict({{"omega_low", p.omega_low},
                       {"omega_high", p.omega_high},
                       {"pivot", p.pivot},
                       {"points", p.points},
                       {"dof", p.dof},
                       {"amplitude", p.amplitude},
                       {"amplitude_error", p.amplitude_error},
                       {"slope", p.slope},
                       {"slope_error", p.slope_error},
                       {"floor", p.floor},
                       {"floor_error", p.floor_error},
                       {"floor_given", p.floor_given},
                       {"correlation", correlation},
                       {"chi2_per_dof", p.chi2_per_dof},
                       {"slope_at_search_edge", p.slope_at_search_edge},
                       {"undetermined", p.undetermined}},
                      verdict);
}

nlohmann::ordered_json alpha_fit_json(const AlphaFit& f, const Verdict& verdict) {
  return with_verdict({{"omega_low", f.omega_low},
                       {"omega_high", f.omega_high},
                       {"points", f.points},
                       {"alpha", f.alpha},
                       {"standard_error", f.alpha_error},
                       {"chi2_per_dof", f.chi2_per_dof},
                       {"theory_order", f.theory_order}},
                      verdict);
}

nlohmann::ordered_json model_fit_json(const ModelFit& m, const Verdict& verdict) {
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < m.names.size(); ++i)
    values[m.names[i]] = {{"value", m.values[i]}, {"standard_error", m.errors[i]}};
  return with_verdict({{"omega_low", m.omega_low},
                       {"omega_high", m.omega_high},
                       {"points", m.points},
                       {"dof", m.dof},
                       {"parameters", values},
                       {"names", m.names},
                       {"covariance", m.covariance},
                       {"floor", m.floor},
                       {"floor_error", m.floor_error},
                       {"floor_given", m.floor_given},
                       {"alpha2_over_N", {{"value", m.amplitude}, {"standard_error", m.amplitude_error}}},
                       {"chi2_per_dof", m.chi2_per_dof},
                       {"converged", m.converged},
                       {"theory_order", m.theory_order},
                       {"undetermined", m.undetermined}},
                      verdict);
}

}  // namespace slidespec::detail

namespace slidespec {

nlohmann::ordered_json analysis_json(const AnalysisReport& r, const std::string& file, const std::string& compare_case,
                                     const nlohmann::ordered_json& model_parameters, FrontEnd reader) {
  const RecordSpectrum& s = r.spectrum;
  nlohmann::ordered_json doc;
  doc["slidespec_version"] = SLIDESPEC_VERSION;
  doc["ok"] = r.ok();
  if (!file.empty()) doc["record"]["file"] = file;
  doc["record"].update({{"column", r.record.column},
                        {"units", to_string(r.record.unit)},
                        {"units_from", worded(r.record.unit_source, reader)},
                        {"samples", s.samples},
                        {"dt", s.dt},
                        {"duration", s.duration}});
  nlohmann::ordered_json spectrum = detail::spectrum_json(s, r.spectrum_verdict, r.model_values);
  nlohmann::ordered_json points = std::move(spectrum["points"]);
  spectrum.erase("points");
  doc.update(spectrum);  // in the spectrum's order; its points come last, after the fits
  if (s.observable != Observable::displacement) doc["observable"]["force_channel"] = r.record.force_channel;
  if (s.observable == Observable::slip) doc["observable"]["machine_stiffness"] = r.record.machine_stiffness;
  if (r.mu) doc["mu"] = *r.mu;
  doc["resolution"] = r.request.resolution;
  doc["sensor_noise"] = r.request.sensor_noise;
  doc["notes"] = nlohmann::ordered_json::array();
  for (const AnalysisMessage& note : r.notes) doc["notes"].push_back(worded(note.text, reader));
  doc["record"]["start_time"] = r.record.start_time;
  doc["record"]["end_time"] = r.end_time();
  if (r.slope) doc["slope_fit"] = detail::slope_fit_json(*r.slope, r.slope_verdict);
  if (r.power_law) doc["power_law_fit"] = detail::power_law_json(*r.power_law, r.power_law_verdict);
  if (r.model_fit) doc["model_fit"] = detail::model_fit_json(*r.model_fit, r.model_fit_verdict);
  if (r.model) {
    doc["compare_case"] = compare_case;
    doc["model_parameters"] = model_parameters;
    doc["theory_order"] = r.model_order;
  }
  if (r.alpha) doc["alpha_fit"] = detail::alpha_fit_json(*r.alpha, r.alpha_verdict);
  doc["points"] = std::move(points);
  // The library's words that may name options, as the reader spells them.
  const auto word = [reader](nlohmann::ordered_json& field) { field = worded(field.get<std::string>(), reader); };
  word(doc["estimator"]["reason"]);
  if (doc.contains("spectrum_failure")) word(doc["spectrum_failure"]);
  for (const char* fit : {"slope_fit", "power_law_fit", "model_fit", "alpha_fit"})
    if (doc.contains(fit)) {
      word(doc[fit]["failure"]);
      if (doc[fit].contains("undetermined")) word(doc[fit]["undetermined"]);
    }
  return doc;
}

}  // namespace slidespec
