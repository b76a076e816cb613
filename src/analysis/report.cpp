#include "analysis/report.hpp"

#include "io/tables.hpp"

namespace slidespec::detail {

std::string top_set_by(const RecordSpectrum& s) {
  if (s.usable_high_set_by_floor) return "the sensor floor reaching 10% of the spectrum";
  if (s.top_set_by_interpolation) return "the resampling's interpolation filter";
  if (s.estimator == Estimator::welch) return "the bin below Nyquist, or the omega_max asked for";
  return "half of Nyquist, or the omega_max asked for";
}

nlohmann::ordered_json spectrum_json(const RecordSpectrum& s, const std::vector<double>& theory) {
  nlohmann::ordered_json doc;
  const bool force = s.observable == Observable::force;
  const char* name = force ? "C_F" : "C_x";
  doc["observable"] = {{"name", to_string(s.observable)},
                       {"spectrum", name},
                       {"unit", spectrum_unit(s.observable)},
                       {"channel", s.channel}};
  if (force) {
    doc["mean_force"] = s.sliding.x0 + s.sliding.v * s.duration / 2;
    doc["force_trend"] = {{"value", s.sliding.v}, {"standard_error", s.sliding.v_error}};
    doc["F_rms"] = s.sliding.xi_rms;
  } else {
    doc["measured_mean_speed"] = {
        {"value", s.sliding.v}, {"standard_error", s.sliding.v_error}, {"blocks", s.sliding.blocks}};
    doc["xi_rms"] = s.sliding.xi_rms;
  }
  doc["quantization_variance"] = s.quantization_variance;
  doc["top_to_floor"] = s.top_to_floor;
  doc["usable_band"] = {{"omega_low", s.usable_low}, {"omega_high", s.usable_high}, {"top_set_by", top_set_by(s)}};
  doc["estimator"] = {{"name", to_string(s.estimator)}, {"reason", s.estimator_reason}};
  if (s.estimator == Estimator::welch) {
    doc["estimator"]["window"] = "hann";
    doc["estimator"]["overlap"] = 0.5;
    doc["estimator"]["prewhitening"] = "first differences, divided by 4 sin^2(omega dt / 2)";
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
