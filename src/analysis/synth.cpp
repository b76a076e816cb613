// A synthetic sensor record: one simulated slider read by a displacement sensor, so the
// whole measured-data path can be tried (and tested) without a lab.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "slidespec/analysis.hpp"
#include "slidespec/stepper.hpp"

namespace slidespec {

namespace {
// A record beyond this is a typing error, not an experiment (0.8 GB of doubles).
constexpr double kMaxSamples = 1e8;
// A stepper starts with its forces' law in sliding distance and reaches it in time after a
// few renewals of each contact (docs/run.md): a program's speeds are warmed up over this many.
constexpr double kWarmUpRenewals = 10;
}  // namespace

std::vector<DriveStretch> stroke_program(double strokes, double stroke_length, double v, double dwell) {
  if (!(strokes >= 1 && strokes <= 1e6 && strokes == std::floor(strokes)))
    throw InputError("{strokes}: must be a whole number of strokes from 1 to 1e6");
  if (!(stroke_length > 0 && std::isfinite(stroke_length)))
    throw InputError("{stroke_length}: must be a positive length in metres");
  if (!(dwell >= 0 && std::isfinite(dwell))) throw InputError("{dwell}: must be a time >= 0 in seconds");
  std::vector<DriveStretch> program;
  for (int k = 0; k < int(strokes); ++k) {
    if (k > 0 && dwell > 0) program.push_back({0, dwell});
    program.push_back({k % 2 == 0 ? 1.0 : -1.0, stroke_length / v});
  }
  return program;
}

namespace {

/// The sample index where each of `program`'s stretches starts, and after the last where
/// the record ends: stretch boundaries on the sampling grid.
std::vector<std::size_t> stretch_starts(const std::vector<DriveStretch>& program, double dt) {
  std::vector<std::size_t> starts = {0};
  double time = 0;
  for (const DriveStretch& stretch : program) {
    if (!(stretch.duration > 0 && std::isfinite(stretch.duration) && std::isfinite(stretch.speed_factor)))
      throw InputError("{program}: each stretch needs a finite speed factor and a positive duration in seconds");
    time += stretch.duration;
    if (time / dt > kMaxSamples) break;  // refused by the caller, naming the sample count
    starts.push_back(std::size_t(std::llround(time / dt)));
  }
  return starts;
}

/// The case at `factor` x its speed: its forces kept, so eta1 = (F_drive - F_kin) / (N m v)
/// goes as 1 / speed.
Parameters at_speed(Parameters p, double factor) {
  p.v *= factor;
  p.eta1 /= factor;
  return p;
}

double slowest_renewal_rate(const Parameters& p) {
  double slowest = p.renewal_rate();
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) slowest = std::min(slowest, p.renewal_rate(l));
  return slowest;
}

/// At every sample the load point's path through `program` and the slider's xi about it.
void slide(const Parameters& params, const SensorRequest& sensor, const std::vector<DriveStretch>& program,
           const std::vector<std::size_t>& starts, std::vector<double>& path, std::vector<double>& xi_at) {
  // The stepper's discretization is exact for any step, so the step is the sample interval
  // and xi at the step ends is what a sensor sampling the slider would see. One stepper per
  // speed (its own stream), continued each time the program returns to that speed.
  std::vector<std::pair<double, Stepper>> steppers;
  double xi = 0, reached = 0;
  for (std::size_t k = 0; k < program.size(); ++k) {
    const double factor = program[k].speed_factor;
    const std::size_t first = starts[k], last = starts[k + 1];
    for (std::size_t n = first + 1; n <= last; ++n)
      path[n] = reached + factor * params.v * static_cast<double>(n - first) * sensor.sample_interval;
    reached += factor * params.v * static_cast<double>(last - first) * sensor.sample_interval;
    if (factor == 0 || last == first) {
      for (std::size_t n = first + 1; n <= last; ++n) xi_at[n] = xi;  // a hold: the slider stands
      continue;
    }
    auto stepper =
        std::find_if(steppers.begin(), steppers.end(), [&](const auto& s) { return s.first == std::fabs(factor); });
    if (stepper == steppers.end()) {
      StepperConfig config;
      config.dt = sensor.sample_interval;
      config.seed = sensor.seed;
      config.stream = steppers.size();
      // A program's speeds start stationary: after kWarmUpRenewals of the slowest renewal.
      if (!sensor.program.empty())
        config.warm_up = kWarmUpRenewals / slowest_renewal_rate(at_speed(params, std::fabs(factor)));
      steppers.emplace_back(std::fabs(factor), Stepper(at_speed(params, std::fabs(factor)), config, 0, 1));
      stepper = steppers.end() - 1;
    }
    // Backwards the fluctuation is mirrored; xi stays continuous across the reversal.
    const double sign = factor > 0 ? 1 : -1;
    std::size_t n = first;
    stepper->second.advance(static_cast<std::int64_t>(last - first), [&](const double* increments, std::size_t steps) {
      for (std::size_t i = 0; i < steps; ++i) {
        xi += sign * increments[i];
        xi_at[++n] = xi;
      }
    });
  }
}

}  // namespace

Record synthesize_record(const Parameters& params, const SensorRequest& sensor) {
  if (!(sensor.sample_interval > 0 && std::isfinite(sensor.sample_interval)))
    throw InputError("{sample_interval}: must be a positive number of seconds");
  if (sensor.program.empty() && !(sensor.duration > 0 && std::isfinite(sensor.duration)))
    throw InputError("{duration}: must be a positive number of seconds");
  if (!(sensor.resolution >= 0 && std::isfinite(sensor.resolution)))
    throw InputError("{resolution}: must be a length >= 0 in metres");
  if (!(sensor.sensor_noise >= 0 && std::isfinite(sensor.sensor_noise)))
    throw InputError("{sensor_noise}: must be a length >= 0 in metres");
  if (sensor.load_point && params.drive != Drive::spring)
    throw InputError("{set} drive=spring: a load point pulls the slider only through a spring");
  if (sensor.load_point && !sensor.program.empty())
    throw InputError("{program}: a rig's load-point record is of one speed; give one or the other");
  const std::vector<DriveStretch> program =
      sensor.program.empty() ? std::vector<DriveStretch>{{1, sensor.duration}} : sensor.program;
  double slid = 0;
  for (const DriveStretch& stretch : program) slid += std::fabs(stretch.speed_factor) * params.v * stretch.duration;
  if (sensor.resolution >= slid) {
    std::ostringstream message;
    message << "{resolution}: " << sensor.resolution << " m is no less than the whole distance slid, " << slid
            << " m: the record would be one or two readings, no spectrum of the slider; give a resolution "
            << "well below it";
    throw InputError(message.str());
  }
  const std::vector<std::size_t> starts = stretch_starts(program, sensor.sample_interval);
  const double samples = starts.size() == program.size() + 1 ? double(starts.back()) + 1 : kMaxSamples + 1;
  if (samples < 2 || samples > kMaxSamples) {
    std::ostringstream message;
    message << (sensor.program.empty() ? "{duration}" : "{program}") << " / {sample_interval}: " << samples
            << " samples; between 2 and 1e8 are allowed";
    throw InputError(message.str());
  }

  Record record{.displacement = {},
                .force = {},
                .observable = Observable::displacement,
                .force_channel = {},
                .machine_stiffness = 0,
                .normal_force = 0,
                .dt = sensor.sample_interval,
                .start_time = 0,
                .column = "x",
                .unit = LengthUnit::m,
                .unit_source = "synthesized",
                .parts = {},
                .jitter = 0,
                .resampled = false,
                .interpolation_cut = 0,
                .interpolation_interval = 0,
                .notes = {}};
  std::vector<double>& x = record.displacement;
  x.assign(static_cast<std::size_t>(samples), 0.0);
  std::vector<double> xi(x.size(), 0.0);
  slide(params, sensor, program, starts, x, xi);

  // A rig reads the load point, v t, and the spring's force k_drive (v t + d0 - x) = F_drive - k_drive xi.
  // The increments leave xi's start unknown (the stretch that holds the first random forces):
  // xi is taken about its mean, so the force's mean over the record is F_drive.
  if (sensor.load_point) {
    double mean_xi = 0;
    for (double xi_n : xi) mean_xi += xi_n / double(xi.size());
    record.force.reserve(xi.size());
    for (double xi_n : xi) record.force.push_back(params.F_drive - params.k_drive * (xi_n - mean_xi));
    record.observable = Observable::slip;
    record.machine_stiffness = params.k_drive;
    record.force_channel = "F (N)";
  } else {
    for (std::size_t n = 0; n < x.size(); ++n) x[n] += xi[n];
  }

  std::mt19937_64 noise_source(sensor.seed ^ 0x5e2503ULL);  // independent of the stepper's streams
  std::normal_distribution<double> noise(0.0, 1.0);
  for (double& reading : x) {
    if (sensor.sensor_noise > 0) reading += sensor.sensor_noise * noise(noise_source);
    if (sensor.resolution > 0) reading = sensor.resolution * std::round(reading / sensor.resolution);
  }
  return record;
}

std::string record_csv(const Record& record, LengthUnit unit, const std::string& comments) {
  std::ostringstream out;
  std::istringstream lines(comments);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  const bool force = !record.force.empty();
  out << "t (s),x (" << to_string(unit) << ")" << (force ? ",F (N)" : "")
      << "\n";  // units in the header: analyze reads them
  const double scale = 1 / metres_per(unit);
  char text[64];
  for (std::size_t n = 0; n < record.displacement.size(); ++n) {
    // 10 significant digits: time stamps of up to 1e7 samples at a round interval, and
    // readings of up to 1e9 resolution steps, print exactly.
    std::snprintf(text, sizeof text, "%.10g,%.10g", record.start_time + static_cast<double>(n) * record.dt,
                  record.displacement[n] * scale);
    out << text;
    if (force) {
      // 12 digits: kN forces keep the fluctuations of a stiff spring (k_drive xi ~ 1e-3 N).
      std::snprintf(text, sizeof text, ",%.12g", record.force[n]);
      out << text;
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace slidespec
