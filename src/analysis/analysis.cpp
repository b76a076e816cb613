// From a record to its spectrum, the sensor's floor, and the two fits (docs/analysis.md).
#include <algorithm>
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>

#include "analysis/line_fit.hpp"
#include "analysis/names.hpp"
#include "analysis/report.hpp"
#include "util/suggest.hpp"
#include "util/numbers.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {

namespace {

// xi is correlated over ~a/v (seconds) and diffusive beyond, so the per-sample least-squares
// error of v would be far too small; the scatter of the speeds of long blocks is honest.
constexpr int kSpeedBlocks = 16;
constexpr std::size_t kMinBlockSamples = 8;

// The usable band ends where the sensor's floor reaches this fraction of the estimate.
constexpr double kFloorShareOfUsable = 0.1;

/// Weighted least squares y = a + b u with standard errors of y; returns a, b, var(b), chi2.
struct WeightedLine {
  double a, b, b_variance, chi2;
};

WeightedLine weighted_line(const std::vector<double>& u, const std::vector<double>& y,
                           const std::vector<double>& sigma) {
  double s = 0, su = 0, sy = 0, suu = 0, suy = 0;
  for (std::size_t k = 0; k < u.size(); ++k) {
    const double w = 1 / (sigma[k] * sigma[k]);
    s += w, su += w * u[k], sy += w * y[k], suu += w * u[k] * u[k], suy += w * u[k] * y[k];
  }
  const double determinant = s * suu - su * su;
  const double b = (s * suy - su * sy) / determinant;
  const double a = (sy - b * su) / s;
  double chi2 = 0;
  for (std::size_t k = 0; k < u.size(); ++k) chi2 += std::pow((y[k] - a - b * u[k]) / sigma[k], 2);
  return {a, b, s / determinant, chi2};
}

/// A least-squares error inflated when the scatter says the model does not describe the
/// data to within the error bars (chi2/dof > 1), never shrunk below the statistical one.
double inflated(double error, double chi2_per_dof) { return error * std::sqrt(std::max(1.0, chi2_per_dof)); }

// A point needs 12 segments: the first after one segment, then one every quarter segment.
constexpr double kSegmentsForLowestPoint = 1 + 11 / 4.0;

/// The lowest omega of the log grid 10^(k/points_per_decade) whose band fits 12 segments
/// into the record; the estimator leaves out a point that still falls short.
double lowest_omega(const Record& record, const AnalysisRequest& request) {
  const double duration = static_cast<double>(record.samples()) * record.dt;
  EstimatorConfig probe;
  probe.dt = record.dt;
  probe.omega_min = 2 * std::numbers::pi / duration;
  probe.points_per_decade = request.points_per_decade;
  if (probe.omega_min >= full_rate_band_floor(record.dt)) return probe.omega_min;  // no band at all
  const SpectrumEstimator layout(probe, 1);
  const double step = std::pow(10.0, 1.0 / request.points_per_decade);
  double omega =
      std::pow(10.0, std::ceil(std::log10(probe.omega_min) * request.points_per_decade) / request.points_per_decade);
  while (kSegmentsForLowestPoint * layout.segment_duration(omega) > duration && omega < full_rate_band_floor(record.dt))
    omega *= step;
  return omega;
}

}  // namespace

SlidingFit fit_sliding(const Record& record) {
  const std::vector<double> x = observed_values(record);
  const detail::Line line = detail::fit_line(x, 0, x.size(), record.dt);
  SlidingFit fit;
  fit.v = line.slope;
  fit.x0 = line.intercept;
  double sum2 = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sum2 += std::pow(x[i] - fit.x0 - fit.v * i * record.dt, 2);
  fit.xi_rms = std::sqrt(sum2 / static_cast<double>(x.size()));

  // A short record (under kSpeedBlocks blocks of kMinBlockSamples) takes fewer blocks,
  // rather than no error at all.
  const int blocks = static_cast<int>(std::min<std::size_t>(kSpeedBlocks, x.size() / kMinBlockSamples));
  if (blocks >= 2) {
    const std::size_t block = x.size() / static_cast<std::size_t>(blocks);
    double mean = 0, mean2 = 0;
    for (int b = 0; b < blocks; ++b) {
      const double speed = detail::fit_line(x, b * block, (b + 1) * block, record.dt).slope;
      mean += speed / blocks;
      mean2 += speed * speed / blocks;
    }
    const double variance = std::max(0.0, mean2 - mean * mean) * blocks / (blocks - 1);
    fit.v_error = std::sqrt(variance / blocks);
    fit.blocks = blocks;
  }
  return fit;
}

std::vector<double> sliding_fluctuation(const Record& record, const SlidingFit& fit) {
  std::vector<double> xi = observed_values(record);
  for (std::size_t i = 0; i < xi.size(); ++i) xi[i] -= fit.x0 + fit.v * static_cast<double>(i) * record.dt;
  return xi;
}

double friction_coefficient(double normal_load_mass, double driving_mass) {
  if (!(normal_load_mass > 0 && std::isfinite(normal_load_mass)))
    throw InputError("{normal_mass}: must be a positive mass in kg");
  if (!(driving_mass > 0 && std::isfinite(driving_mass)))
    throw InputError("{driving_mass}: must be a positive mass in kg");
  return driving_mass / normal_load_mass;
}

namespace {
constexpr std::array<detail::Word<Estimator>, 3> kEstimatorWords{
    {{"auto", Estimator::automatic}, {"welch", Estimator::welch}, {"streaming", Estimator::streaming}}};
}  // namespace

Estimator parse_estimator(const std::string& name) {
  return detail::parse_word(kEstimatorWords, name, "{estimator}", "estimator");
}

const char* to_string(Estimator estimator) { return detail::name_of(kEstimatorWords, estimator); }

namespace {

/// The streaming estimator's points: 12 segments per point, a cascade of segment lengths.
std::vector<AnalysisPoint> streaming_points(const Record& record, const AnalysisRequest& request,
                                            const std::vector<double>& xi, RecordSpectrum& result) {
  EstimatorConfig config;
  config.dt = record.dt;
  config.omega_min = request.omega_min > 0 ? request.omega_min : lowest_omega(record, request);
  config.omega_max = request.omega_max;
  config.points_per_decade = request.points_per_decade;
  config.input = SampleKind::value;
  const auto too_short = [&] {
    return InputError("the record (" + std::to_string(result.samples) +
                      " samples) is too short for the streaming estimator, whose lowest point needs 12 "
                      "segments; use {estimator} welch");
  };
  if (request.omega_min <= 0 && config.omega_min >= full_rate_band_floor(record.dt)) throw too_short();
  SpectrumEstimator estimator(config, 1);
  // In pieces of a few milliseconds, between which a stop is heard (pieces change no number).
  constexpr std::size_t kPieceSamples = std::size_t{1} << 18;
  for (std::size_t first = 0; first < xi.size(); first += kPieceSamples) {
    hear_stop(request.stop);
    estimator.push(xi.data() + first, std::min(kPieceSamples, xi.size() - first));
  }
  result.accumulator = estimator.merged();
  std::vector<AnalysisPoint> points;
  for (const SpectrumPoint& e : result.accumulator.spectrum(PointValue::bin_average)) {
    AnalysisPoint p{e.omega, e.C, e.standard_error, 0, e.n_avg, e.bandwidth, false};
    p.dof = 2 * e.C * e.C / (e.standard_error * e.standard_error);
    p.lower = e.C - 2 * e.standard_error, p.upper = e.C + 2 * e.standard_error;
    p.segment_samples = std::size_t(std::llround(2 * std::numbers::pi / (e.bin_spacing * record.dt)));
    points.push_back(p);
  }
  if (points.empty()) throw too_short();
  return points;
}

/// Welch's points of xi, or of a reciprocating record's strokes (several pieces of xi).
std::vector<AnalysisPoint> welch_points(const Record& record, const AnalysisRequest& request,
                                        const std::vector<std::vector<double>>& pieces, RecordSpectrum& result) {
  WelchRequest welch;
  welch.omega_min = request.omega_min;
  welch.omega_max = request.omega_max;
  welch.points_per_decade = request.points_per_decade;
  welch.stop = request.stop;
  result.welch =
      pieces.size() == 1 ? welch_spectrum(pieces.front(), record.dt, welch) : welch_spectrum(pieces, record.dt, welch);
  std::vector<AnalysisPoint> points;
  for (const WelchPoint& w : result.welch.points) {
    AnalysisPoint p{w.omega,
                    w.C,
                    w.standard_error,
                    0,
                    double(result.welch.segments * w.bins),
                    double(w.bins) * result.welch.bin_spacing,
                    false};
    p.dof = w.dof;
    p.lower = w.lower, p.upper = w.upper;
    p.segment_samples = result.welch.segment_samples;
    p.leaky = w.leaky;
    result.leaky_points += w.leaky ? 1 : 0;
    points.push_back(p);
  }
  if (points.empty())
    throw InputError("no spectrum point between {omega_min} and {omega_max} (the record's bins are " +
                     util::format_number(result.welch.bin_spacing) + " rad/s apart)");
  return points;
}

}  // namespace

std::vector<double> expected_points(const RecordSpectrum& spectrum,
                                    const std::function<double(double)>& true_spectrum) {
  if (spectrum.estimator == Estimator::welch) return welch_expected(spectrum.welch, true_spectrum);
  std::vector<double> values;
  for (const SpectrumPoint& e : spectrum.accumulator.expected(true_spectrum)) values.push_back(e.C);
  return values;
}

namespace {

std::string observable_channel(const Record& r) {
  switch (r.observable) {
    case Observable::force:
      return "force " + r.force_channel;
    case Observable::slip:
      return "slip " + r.column + " - F/K, K = " + util::format_number(r.machine_stiffness) +
             " N/m, F = " + r.force_channel;
    default:
      return "column " + r.column;
  }
}

/// Whether most steps between readings are whole multiples of q, as a sensor of resolution q
/// reads: a step of no multiple is none at all (the same reading twice).
bool readings_on_grid(const std::vector<double>& x, double q) {
  constexpr double kOffGrid = 0.01;  // of q: beyond it a step is not a multiple of q
  constexpr double kOnGridShare = 0.9;
  std::size_t on = 0;
  for (std::size_t i = 1; i < x.size(); ++i) {
    const double steps = (x[i] - x[i - 1]) / q, whole = std::round(steps);
    on += (whole == 0 ? steps == 0 : std::fabs(steps - whole) < kOffGrid) ? 1 : 0;
  }
  return double(on) >= kOnGridShare * double(x.size() - 1);
}

}  // namespace

void check_band(const AnalysisRequest& request) {
  for (const auto& [option, omega] :
       {std::pair{"{omega_min}", request.omega_min}, std::pair{"{omega_max}", request.omega_max}})
    if (!(omega >= 0) || !std::isfinite(omega))
      throw InputError(std::string(option) + ": " + util::format_number(omega) +
                       " is not a frequency > 0 in rad/s (leave it out for what the record allows)");
  if (request.omega_min > 0 && request.omega_max > 0 && request.omega_min >= request.omega_max)
    throw InputError("{omega_min} " + util::format_number(request.omega_min) + " must be below {omega_max} " +
                     util::format_number(request.omega_max));
  if (request.points_per_decade < 1 || request.points_per_decade > 100)
    throw InputError("{points}: must be between 1 and 100 per decade");
}

namespace {

/// The sliding fluctuation of `record`, or of each of its `strokes`, with the sliding fit
/// and sample count in `result`. Each stroke is its own line (its own direction and speed);
/// the speed reported is the strokes' mean |v|, its error from their scatter.
std::vector<std::vector<double>> sliding_pieces(const Record& record, const std::vector<Record>& strokes,
                                                RecordSpectrum& result, const std::atomic<bool>* stop) {
  std::vector<std::vector<double>> pieces;
  if (strokes.empty()) {
    result.samples = record.samples();
    result.sliding = fit_sliding(record);
    hear_stop(stop);
    pieces.push_back(sliding_fluctuation(record, result.sliding));
    return pieces;
  }
  double sum = 0, sum2 = 0, xi2 = 0;
  for (const Record& stroke : strokes) {
    const SlidingFit fit = fit_sliding(stroke);
    pieces.push_back(sliding_fluctuation(stroke, fit));
    result.samples += stroke.samples();
    sum += std::fabs(fit.v), sum2 += fit.v * fit.v;
    xi2 += fit.xi_rms * fit.xi_rms * double(stroke.samples());
  }
  const double n = double(strokes.size()), mean = sum / n;
  result.sliding.v = mean;
  result.sliding.v_error = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
  result.sliding.xi_rms = std::sqrt(xi2 / double(result.samples));
  result.sliding.blocks = int(strokes.size());
  return pieces;
}

/// The estimator the request asks for, or the one that suits the record (Welch's in strokes),
/// and why, into `result`.
void choose_estimator(const AnalysisRequest& request, bool strokes, RecordSpectrum& result) {
  result.estimator = request.estimator;
  if (strokes) {
    if (request.estimator == Estimator::streaming)
      throw InputError(
          "{estimator} streaming: a reciprocating record's strokes are analyzed by Welch's estimator "
          "alone ({window} T0:T1 takes one stretch)");
    result.estimator = Estimator::welch;
    result.estimator_reason = "the strokes of a reciprocating record: one Welch segment length in each stroke";
  } else if (request.estimator == Estimator::automatic) {
    const bool long_record = result.samples > kWelchLargestRecord;
    result.estimator = long_record ? Estimator::streaming : Estimator::welch;
    result.estimator_reason = long_record ? "automatic: over " + std::to_string(kWelchLargestRecord) +
                                                " samples, the streaming estimator's cascade guards the low band"
                                          : "automatic: up to " + std::to_string(kWelchLargestRecord) +
                                                " samples, Welch reaches down to 9 x 2 pi / T";
  } else {
    result.estimator_reason = "{estimator}";
  }
}

/// The spectrum of `record`, or of its `strokes` (records of their own) as pieces of one.
RecordSpectrum analyze(const Record& record, const std::vector<Record>& strokes, const AnalysisRequest& request) {
  // A record's values stay within 1e30 m (record.cpp): a sensor's floor beyond them has a
  // square beyond the doubles (an inf floor reported ok).
  constexpr double kLargestSensorLength = 1e30;
  if (request.resolution < 0 || !(request.resolution <= kLargestSensorLength))
    throw InputError("{resolution}: must be a length from 0 to 1e30 m");
  if (request.sensor_noise < 0 || !(request.sensor_noise <= kLargestSensorLength))
    throw InputError("{sensor_noise}: must be a length from 0 to 1e30 m");
  check_band(request);
  if (record.observable == Observable::force && request.resolution + request.sensor_noise > 0)
    throw InputError(std::string(request.resolution > 0 ? "{resolution}" : "{sensor_noise}") +
                     ": a displacement sensor's floor, and the observable is the force; leave it out");
  RecordSpectrum result;
  result.observable = record.observable;
  result.channel = observable_channel(record);
  result.dt = record.dt;
  const std::vector<std::vector<double>> pieces = sliding_pieces(record, strokes, result, request.stop);
  hear_stop(request.stop);
  result.duration = static_cast<double>(result.samples) * record.dt;
  result.quantization_variance = request.resolution * request.resolution / 12;
  result.sensor_noise_variance = request.sensor_noise * request.sensor_noise;

  choose_estimator(request, !strokes.empty(), result);
  AnalysisRequest band = request;
  if (record.interpolation_cut > 0 && !(request.omega_max > 0 && request.omega_max <= record.interpolation_cut)) {
    band.omega_max = record.interpolation_cut;
    result.top_set_by_interpolation = true;
    result.interpolation_interval = record.interpolation_interval;
  }
  result.points = result.estimator == Estimator::welch ? welch_points(record, band, pieces, result)
                                                       : streaming_points(record, band, pieces.front(), result);
  // The estimator's own top: the bin below Nyquist (welch), half of Nyquist (streaming).
  const double nyquist = std::numbers::pi / record.dt, spacing = result.welch.bin_spacing;
  const double estimator_top =
      result.estimator == Estimator::welch ? (std::ceil(nyquist / spacing - 1e-9) - 1) * spacing : nyquist / 2;
  result.top_set_by_omega_max =
      !result.top_set_by_interpolation && request.omega_max > 0 && request.omega_max < estimator_top;

  // White noise of variance q^2/12 (+ sigma^2) per sample (docs/model.md §3: C = s^2 dt / 2 pi),
  // through the same bins and window as the estimate so that the two compare point by point.
  const double white =
      (result.quantization_variance + result.sensor_noise_variance) * record.dt / (2 * std::numbers::pi);
  const std::vector<double> floor = expected_points(result, [white](double) { return white; });

  bool floor_reached = false;
  result.usable_low = result.points.front().omega;
  result.usable_high = result.points.back().omega;
  for (std::size_t k = 0; k < result.points.size(); ++k) {
    AnalysisPoint& p = result.points[k];
    p.noise_floor = floor[k];
    p.below_floor = p.C_x < p.noise_floor + 2 * p.standard_error;
    if (!floor_reached && p.noise_floor > kFloorShareOfUsable * p.C_x && white > 0) {
      floor_reached = true;
      result.usable_high_set_by_floor = true;
      // Reached at the lowest point: no usable band, 0 .. 0.
      result.usable_high = k > 0 ? result.points[k - 1].omega : 0;
      if (k == 0) result.usable_low = 0;
    }
  }
  result.top_to_floor = white > 0 ? result.points.back().C_x / floor.back() : 0;
  result.floor_above_spectrum = white > 0 && std::all_of(result.points.begin(), result.points.end(),
                                                         [](const AnalysisPoint& p) { return p.noise_floor >= p.C_x; });
  result.readings_off_grid = request.resolution > 0 && record.observable == Observable::displacement &&
                             !readings_on_grid(record.displacement, request.resolution);
  return result;
}

}  // namespace

RecordSpectrum analyze_record(const Record& record, const AnalysisRequest& request) {
  return analyze(record, {}, request);
}

RecordSpectrum analyze_strokes(const Record& record, const Strokes& strokes, const AnalysisRequest& request,
                               std::vector<std::string>& notes) {
  std::vector<Record> pieces;
  for (const SteadySegment& middle : strokes.middles) pieces.push_back(record_window(record, middle.start, middle.end));
  RecordSpectrum result = analyze(record, pieces, request);
  result.strokes = strokes;
  char note[400];
  std::snprintf(note, sizeof note,
                "a reciprocating record: %zu strokes at %.3g m/s; the middle %.0f%% of each (%.4g s at the shortest) "
                "analyzed, %zu Welch segments in all, the strokes' periodograms averaged; lowest omega a stroke allows "
                "%.4g rad/s",
                strokes.middles.size(), strokes.speed, 100 * (1 - 2 * kStrokeEndShare), strokes.middle_duration,
                result.welch.segments, strokes.lowest_omega);
  notes.push_back(note);
  return result;
}

SlopeFit fit_slope(const RecordSpectrum& spectrum, double omega_low, double omega_high) {
  if (!(omega_low > 0 && omega_high > omega_low)) throw InputError("{fit_slope}: need 0 < LO < HI in rad/s");
  SlopeFit fit;
  fit.omega_low = omega_low;
  fit.omega_high = omega_high;
  std::vector<double> u, y, sigma;
  // The exponent of the motion, not of motion plus sensor: the white floor is known, so it
  // is subtracted; points that do not stand out of it carry no slope and are left out.
  for (const AnalysisPoint& p : spectrum.points) {
    if (p.omega < omega_low || p.omega > omega_high || p.below_floor) continue;
    const double motion = p.C_x - p.noise_floor;
    u.push_back(std::log(p.omega));
    y.push_back(std::log(motion));
    sigma.push_back(p.standard_error / motion);  // the error of ln C, to first order
    fit.reaches_floor |= p.omega > spectrum.usable_high;
  }
  fit.points = static_cast<int>(u.size());
  if (fit.points < 3)
    throw InputError("{fit_slope}: the band holds " + std::to_string(fit.points) +
                     " points above the sensor floor; a slope and its error need at least 3");
  const WeightedLine line = weighted_line(u, y, sigma);
  fit.slope = line.b;
  fit.chi2_per_dof = line.chi2 / (fit.points - 2);
  fit.slope_error = inflated(std::sqrt(line.b_variance), fit.chi2_per_dof);
  fit.amplitude = std::exp(line.a);
  return fit;
}

namespace {

struct PowerLawSolution {
  double amplitude, floor, chi2;
};

/// For a slope the power law is linear in (amplitude, floor): their weighted least squares,
/// the floor held at 0 where it would fall below, and the chi2 there.
PowerLawSolution power_law_at(double slope, const RecordSpectrum& spectrum, const std::vector<std::size_t>& inside,
                              const std::vector<double>& sigma, double pivot, bool floor_given) {
  double saa = 0, saf = 0, sff = 0, sac = 0, sfc = 0;
  for (std::size_t k : inside) {
    const AnalysisPoint& p = spectrum.points[k];
    const double w = 1 / (sigma[k] * sigma[k]), a = std::pow(p.omega / pivot, slope);
    const double c = floor_given ? p.C_x - p.noise_floor : p.C_x;
    saa += w * a * a, saf += w * a, sff += w, sac += w * a * c, sfc += w * c;
  }
  PowerLawSolution best{sac / saa, 0, 0};
  if (!floor_given) {
    const double det = saa * sff - saf * saf;
    const double amplitude = (sac * sff - saf * sfc) / det, floor = (saa * sfc - saf * sac) / det;
    if (floor > 0) best = {amplitude, floor, 0};  // a floor below zero is no floor: held at 0
  }
  for (std::size_t k : inside) {
    const AnalysisPoint& p = spectrum.points[k];
    const double model = best.amplitude * std::pow(p.omega / pivot, slope) + (floor_given ? p.noise_floor : best.floor);
    best.chi2 += std::pow((p.C_x - model) / sigma[k], 2);
  }
  return best;
}

/// The errors and correlations of (amplitude, slope, floor) from the Jacobian at the optimum,
/// scaled by chi2/dof when the scatter says so.
void power_law_errors(const RecordSpectrum& spectrum, const std::vector<std::size_t>& inside,
                      const std::vector<double>& sigma, int parameters, PowerLawFit& fit) {
  Eigen::MatrixXd jacobian(fit.points, parameters);
  for (int i = 0; i < fit.points; ++i) {
    const AnalysisPoint& p = spectrum.points[inside[std::size_t(i)]];
    const double a = std::pow(p.omega / fit.pivot, fit.slope), s = sigma[inside[std::size_t(i)]];
    jacobian(i, 0) = a / s;
    jacobian(i, 1) = fit.amplitude * a * std::log(p.omega / fit.pivot) / s;
    if (!fit.floor_given) jacobian(i, 2) = 1 / s;
  }
  const Eigen::MatrixXd covariance = (jacobian.transpose() * jacobian).inverse() * std::max(1.0, fit.chi2_per_dof);
  fit.amplitude_error = std::sqrt(covariance(0, 0));
  fit.slope_error = std::sqrt(covariance(1, 1));
  fit.floor_error = fit.floor_given ? 0 : std::sqrt(covariance(2, 2));
  for (int i = 0; i < parameters; ++i)
    for (int j = 0; j < parameters; ++j)
      fit.correlation[i][j] = covariance(i, j) / std::sqrt(covariance(i, i) * covariance(j, j));
}

/// Each point's model and residual inside the band, and what the band leaves open.
void power_law_model(const RecordSpectrum& spectrum, const std::vector<std::size_t>& inside,
                     const std::vector<double>& sigma, PowerLawFit& fit) {
  fit.model.assign(spectrum.points.size(), std::numeric_limits<double>::quiet_NaN());
  fit.residuals = fit.model;
  for (std::size_t k : inside) {
    const AnalysisPoint& p = spectrum.points[k];
    fit.model[k] = fit.amplitude * std::pow(p.omega / fit.pivot, fit.slope) + fit.floor;
    fit.residuals[k] = (p.C_x - fit.model[k]) / sigma[k];
  }
  std::string undetermined;
  if (!fit.floor_given && !(fit.floor > 2 * fit.floor_error)) {
    undetermined = "the white floor is not determined (below the spectrum across the band; at most " +
                   util::short_number(fit.floor + 2 * fit.floor_error) + " " + spectrum_unit(spectrum.observable) +
                   "); ";
  }
  fit.undetermined = undetermined +
                     "a power law and a white floor say nothing of the model's alpha, N and a, which enter only "
                     "through the amplitude and the corner frequencies: fit them with {compare_case} and {fit} "
                     "alpha,a (a machine-driven record through its spring with {machine_stiffness})";
}

}  // namespace

PowerLawFit fit_power_law(const RecordSpectrum& spectrum, double omega_low, double omega_high) {
  if (!(omega_low > 0 && omega_high > omega_low)) throw InputError("{fit_band}: need 0 < LO < HI in rad/s");
  PowerLawFit fit;
  fit.omega_low = omega_low, fit.omega_high = omega_high;
  fit.floor_given = spectrum.quantization_variance + spectrum.sensor_noise_variance > 0;
  std::vector<std::size_t> inside;
  double log_pivot = 0;
  for (std::size_t k = 0; k < spectrum.points.size(); ++k) {
    const AnalysisPoint& p = spectrum.points[k];
    if (p.omega < omega_low || p.omega > omega_high || p.leaky || !(p.C_x > 0)) continue;
    inside.push_back(k);
    log_pivot += std::log(p.omega);
  }
  const int parameters = fit.floor_given ? 2 : 3;
  fit.points = int(inside.size());
  if (fit.points < parameters + 1)
    throw InputError("{fit} power-law: the band " + util::format_number(omega_low) + " .. " +
                     util::format_number(omega_high) + " rad/s holds " + std::to_string(fit.points) +
                     " usable points; amplitude, slope" + (fit.floor_given ? "" : " and floor") + " need at least " +
                     std::to_string(parameters + 1));
  fit.dof = fit.points - parameters;
  fit.pivot = std::exp(log_pivot / fit.points);

  // For a slope s the model is linear in (amplitude, floor): solve it, keep the best s.
  std::vector<double> sigma(spectrum.points.size()), shape(spectrum.points.size());
  for (std::size_t k : inside) sigma[k] = spectrum.points[k].standard_error;
  const auto solve = [&](double slope) {
    return power_law_at(slope, spectrum, inside, sigma, fit.pivot, fit.floor_given);
  };
  constexpr double kSteepest = kSteepestPowerLawSlope, kFlattest = kFlattestPowerLawSlope, kScanStep = 0.01;
  PowerLawSolution best{0, 0, std::numeric_limits<double>::infinity()};
  for (int iteration = 0; iteration < 4; ++iteration) {
    best.chi2 = std::numeric_limits<double>::infinity();
    for (double slope = kSteepest; slope <= kFlattest; slope += kScanStep) {
      const PowerLawSolution trial = solve(slope);
      if (trial.chi2 < best.chi2) best = trial, fit.slope = slope;
    }
    for (double step = kScanStep / 2; step > 1e-6; step /= 2)  // refine about the grid's best
      for (const double slope : {fit.slope - step, fit.slope + step}) {
        const PowerLawSolution trial = solve(slope);
        if (trial.chi2 < best.chi2) best = trial, fit.slope = slope;
      }
    // Weights from the model's level, as for alpha: a point that happens to be low has a
    // small error bar and would pull the fit down.
    for (std::size_t k : inside) {
      const AnalysisPoint& p = spectrum.points[k];
      const double model =
          best.amplitude * std::pow(p.omega / fit.pivot, fit.slope) + (fit.floor_given ? p.noise_floor : best.floor);
      sigma[k] = p.standard_error / p.C_x * model;
    }
  }
  best = solve(fit.slope);
  // The refinement may step a little beyond the grid's end: within a grid step of it, the
  // minimum is the range's end, not chi2's.
  fit.slope_at_search_edge = fit.slope <= kSteepest + kScanStep || fit.slope >= kFlattest - kScanStep;
  fit.amplitude = best.amplitude;
  fit.floor = fit.floor_given ? spectrum.points[inside.front()].noise_floor : best.floor;
  fit.chi2_per_dof = best.chi2 / fit.dof;

  power_law_errors(spectrum, inside, sigma, parameters, fit);
  power_law_model(spectrum, inside, sigma, fit);
  return fit;
}

std::pair<double, double> default_alpha_band(const RecordSpectrum& s, const Parameters& p) {
  const Landmarks l = landmarks(p);
  const double low = std::max(s.usable_low, 5 * l.renewal_rate);
  const double high = std::min(s.usable_high, l.omega_c / 3);
  if (!(s.usable_high > s.usable_low)) throw InputError(detail::no_usable_band_for_fit("alpha"));
  if (!(high > low))
    throw InputError("{fit} alpha: the usable band " + util::format_number(s.usable_low) + " .. " +
                     util::format_number(s.usable_high) +
                     " rad/s misses the model's omega^-4 band; give {fit_band} LO HI");
  return {low, high};
}

int model_order(const Parameters& params, ModelOrder order) {
  if (order == ModelOrder::first) return 1;
  try {
    SecondOrderTheory{params};
    return 2;
  } catch (const InputError&) {
    return 1;
  }
}

std::vector<double> model_spectrum(const RecordSpectrum& spectrum, const Parameters& params, ModelOrder order) {
  // A sensor takes point samples, so the frequencies above Nyquist fold onto the band; a few
  // aliases are plenty for a spectrum that falls as omega^-8 above omega_c.
  const auto aliased = [&](const auto& theory) {
    const double sampling_rate = 2 * std::numbers::pi / spectrum.dt;
    const auto sampled = [&](double omega) {
      double sum = theory(omega);
      for (int k = 1; k <= 4; ++k)
        sum += theory(std::abs(omega - k * sampling_rate)) + theory(omega + k * sampling_rate);
      return sum;
    };
    return expected_points(spectrum, sampled);
  };
  std::vector<double> values;
  if (model_order(params, order) == 2 && best_theory(params).kind == TheoryKind::quasi_static)
    values = aliased(QuasiStaticTheory(params));  // beyond the series' limit (docs/model.md §7.5)
  else if (model_order(params, order) == 2)
    values = aliased(SecondOrderTheory(params));
  else
    values = aliased(LumpedTheory(params));
  if (spectrum.observable == Observable::force) {
    // The spring's force -k_drive xi: what a machine's load cell reads of the model.
    if (!(params.drive == Drive::spring && params.k_drive > 0))
      throw InputError(
          "the model's force spectrum is the spring's, k_drive^2 C_x: the compared case needs "
          "drive = spring and k_drive > 0 ({set} drive=spring {set} k_drive=K)");
    for (double& value : values) value = spring_force_spectrum(params, value);
  }
  return values;
}

namespace {
// Weighted least squares for alpha^2 with a given shape T (the spectrum at alpha = 1);
// nothing when the band gives no positive alpha^2.
std::optional<AlphaFit> fit_alpha_to(const RecordSpectrum& spectrum, const std::vector<double>& template_spectrum,
                                     double omega_low, double omega_high) {
  if (!(omega_low > 0 && omega_high > omega_low)) throw InputError("{fit_band}: need 0 < LO < HI in rad/s");
  std::vector<std::size_t> inside;
  for (std::size_t k = 0; k < spectrum.points.size(); ++k)
    if (spectrum.points[k].omega >= omega_low && spectrum.points[k].omega <= omega_high) inside.push_back(k);
  AlphaFit fit;
  fit.omega_low = omega_low;
  fit.omega_high = omega_high;
  fit.points = static_cast<int>(inside.size());
  if (inside.empty()) throw InputError("{fit_band}: no spectrum point between LO and HI");

  // Weights from the model, not from each point's own error bar: an estimate that happens
  // to be high also has a high scatter, and 1/SE^2 weights would pull alpha down. The
  // relative error SE/C is kept from the data (it depends on the segments, not the level).
  double alpha2 = 0, sum_tt = 0, chi2 = 0;
  std::vector<double> sigma(spectrum.points.size());
  for (std::size_t k : inside) sigma[k] = spectrum.points[k].standard_error;
  for (int iteration = 0; iteration < 4; ++iteration) {
    double sum_ct = 0;
    sum_tt = 0;
    for (std::size_t k : inside) {
      const AnalysisPoint& p = spectrum.points[k];
      const double w = 1 / (sigma[k] * sigma[k]);
      sum_ct += w * (p.C_x - p.noise_floor) * template_spectrum[k];
      sum_tt += w * template_spectrum[k] * template_spectrum[k];
    }
    alpha2 = sum_ct / sum_tt;
    chi2 = 0;
    for (std::size_t k : inside) {
      const AnalysisPoint& p = spectrum.points[k];
      const double model = alpha2 * template_spectrum[k] + p.noise_floor;
      chi2 += std::pow((p.C_x - model) / sigma[k], 2);
      sigma[k] = p.standard_error / p.C_x * model;
    }
  }
  if (!(alpha2 > 0 && std::isfinite(alpha2))) return std::nullopt;
  fit.chi2_per_dof = fit.points > 1 ? chi2 / (fit.points - 1) : 0;
  fit.alpha = std::sqrt(alpha2);
  fit.alpha_error = inflated(1 / std::sqrt(sum_tt), fit.chi2_per_dof) / (2 * fit.alpha);
  return fit;
}
}  // namespace

AlphaFit fit_alpha(const RecordSpectrum& spectrum, const Parameters& params, double omega_low, double omega_high,
                   ModelOrder order) {
  Parameters unit_noise = params;
  unit_noise.alpha = 1;
  const std::optional<AlphaFit> first =
      fit_alpha_to(spectrum, model_spectrum(spectrum, unit_noise, ModelOrder::first), omega_low, omega_high);
  if (!first) throw InputError("{fit} alpha: the measured spectrum gives no positive alpha^2 in the band");
  AlphaFit fit = *first;
  // The second-order shape depends on alpha: refit at the alpha found until it settles
  // (the shape changes by O(eps^2) per step, so a few steps reach the rounding). Where no
  // theory beyond first order holds at the alpha found, the series says nothing (past the
  // stall it would send alpha off without bound): the fit stays the last one made.
  for (int step = 0; step < 8 && order == ModelOrder::best; ++step) {
    Parameters at_fit = params;
    at_fit.alpha = fit.alpha;
    if (model_order(at_fit, order) != 2) break;
    const TheoryChoice holds = best_theory(at_fit);
    if (holds.kind == TheoryKind::first_order) break;  // the first order holds: nothing to refine
    if (holds.kind == TheoryKind::none) {
      fit.order_not_reached = "fitted with the order " + std::to_string(fit.theory_order) +
                              " theory: no theory beyond it holds at the alpha found, " +
                              detail::short_number(fit.alpha) + ", to refit with";
      break;
    }
    const std::vector<double> shape = model_spectrum(spectrum, at_fit, order);
    std::vector<double> unit(shape.size());
    for (std::size_t k = 0; k < shape.size(); ++k) unit[k] = shape[k] / (fit.alpha * fit.alpha);
    const double previous = fit.alpha;
    std::optional<AlphaFit> refit = fit_alpha_to(spectrum, unit, omega_low, omega_high);
    if (!refit) {
      fit.order_not_reached = "the second-order theory at the alpha found, " + detail::short_number(previous) +
                              ", gives no positive alpha^2 in the band: fitted with the order " +
                              std::to_string(fit.theory_order) + " theory";
      break;
    }
    fit = *refit;
    fit.theory_order = 2;
    if (std::fabs(fit.alpha - previous) <= 1e-12 * previous) break;
  }
  return fit;
}

}  // namespace slidespec
