// A synthetic sensor record: one simulated slider read by a displacement sensor, so the
// whole measured-data path can be tried (and tested) without a lab.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "slidespec/analysis.hpp"
#include "slidespec/stepper.hpp"
#include "util/numbers.hpp"

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

/// A rig's case at `factor` x its speed: the same contacts (eta1 kept), so the spring's mean
/// force is the steady friction F_kin + N m eta1 v at that speed (docs/model.md §1).
Parameters rig_at_speed(Parameters p, double factor) {
  if (factor == 1) return p;
  p.v *= factor;
  p.F_drive = p.F_kin + factor * (p.F_drive - p.F_kin);
  if (landmarks(p).forces_can_stall)
    throw InputError("{program}: at " + util::format_number(factor) + " x v the steady friction " +
                     util::format_number(p.F_drive) + " N leaves the random forces able to stall the slider " +
                     "(alpha F_kin >= 2 (F_drive - F_kin)); the model's stationary sliding does not hold there");
  return p;
}

Parameters case_at_speed(const Parameters& p, double factor, bool load_point) {
  return load_point ? rig_at_speed(p, factor) : at_speed(p, factor);
}

double slowest_renewal_rate(const Parameters& p) {
  double slowest = p.renewal_rate();
  for (int l = 1; l <= p.levels; ++l)
    if (p.touches(l)) slowest = std::min(slowest, p.renewal_rate(l));
  return slowest;
}

/// A simulated slide, sample by sample.
struct SlideTrace {
  std::vector<double> path;        ///< the load point's position [m]
  std::vector<double> xi;          ///< the slider's fluctuation about the path, continuous [m]
  std::vector<double> speed;       ///< the drive's speed factor (0 in a hold)
  std::vector<double> stepper_xi;  ///< xi of that speed's own realization (its start unknown) [m]
};

/// One realization per speed, continued each time the program returns to that speed.
struct SpeedRealization {
  double speed_factor;
  Stepper stepper;
  double xi = 0;
};

/// The load point's path through `program` and the slider's xi about it.
SlideTrace slide(const Parameters& params, const SensorRequest& sensor, const std::vector<DriveStretch>& program,
                 const std::vector<std::size_t>& starts) {
  // The stepper's discretization is exact for any step, so the step is the sample interval
  // and xi at the step ends is what a sensor sampling the slider would see.
  const std::size_t samples = starts.back() + 1;
  SlideTrace trace{std::vector<double>(samples, 0.0), std::vector<double>(samples, 0.0),
                   std::vector<double>(samples, program.front().speed_factor), std::vector<double>(samples, 0.0)};
  std::vector<SpeedRealization> realizations;
  double xi = 0, reached = 0;
  for (std::size_t k = 0; k < program.size(); ++k) {
    const double factor = program[k].speed_factor;
    const std::size_t first = starts[k], last = starts[k + 1];
    for (std::size_t n = first + 1; n <= last; ++n) {
      trace.path[n] = reached + factor * params.v * static_cast<double>(n - first) * sensor.sample_interval;
      trace.speed[n] = factor;
    }
    reached += factor * params.v * static_cast<double>(last - first) * sensor.sample_interval;
    if (factor == 0 || last == first) {
      for (std::size_t n = first + 1; n <= last; ++n) trace.xi[n] = xi;  // a hold: the slider stands
      continue;
    }
    auto realization = std::find_if(realizations.begin(), realizations.end(),
                                    [&](const auto& r) { return r.speed_factor == std::fabs(factor); });
    if (realization == realizations.end()) {
      const Parameters at = case_at_speed(params, std::fabs(factor), sensor.load_point);
      StepperConfig config;
      config.dt = sensor.sample_interval;
      config.seed = sensor.seed;
      config.stream = realizations.size();
      // A program's speeds start stationary: after kWarmUpRenewals of the slowest renewal.
      if (!sensor.program.empty()) config.warm_up = kWarmUpRenewals / slowest_renewal_rate(at);
      realizations.push_back({std::fabs(factor), Stepper(at, config, 0, 1)});
      realization = realizations.end() - 1;
    }
    // Backwards the fluctuation is mirrored; xi stays continuous across the reversal.
    const double sign = factor > 0 ? 1 : -1;
    std::size_t n = first;
    realization->stepper.advance(static_cast<std::int64_t>(last - first),
                                 [&](const double* increments, std::size_t steps) {
                                   for (std::size_t i = 0; i < steps; ++i) {
                                     xi += sign * increments[i];
                                     realization->xi += increments[i];
                                     trace.xi[++n] = xi;
                                     trace.stepper_xi[n] = realization->xi;
                                   }
                                 });
  }
  return trace;
}

/// The spring's force F_drive - k_drive xi at every sample of a rig's record, F_drive and xi
/// those of the speed sliding (mirrored backwards). Each speed's xi is taken about its mean:
/// the stepper leaves its start (the stretch that holds the first random forces) unknown.
/// In a hold the slider and the load point stand, so the force stands at its last value:
/// the model's stationary slider cannot relax through the spring.
std::vector<double> spring_force(const Parameters& params, const SlideTrace& trace) {
  struct SpeedMean {
    double speed, xi_sum = 0, samples = 0, force = 0;
  };
  std::vector<SpeedMean> means;
  const auto mean_at = [&](double speed) -> SpeedMean& {
    auto m = std::find_if(means.begin(), means.end(), [&](const SpeedMean& e) { return e.speed == speed; });
    return m != means.end() ? *m : means.emplace_back(SpeedMean{speed, 0, 0, rig_at_speed(params, speed).F_drive});
  };
  for (std::size_t n = 0; n < trace.speed.size(); ++n)
    if (trace.speed[n] != 0) {
      SpeedMean& m = mean_at(std::fabs(trace.speed[n]));
      m.xi_sum += trace.stepper_xi[n];
      m.samples += 1;
    }
  std::vector<double> force(trace.speed.size(), params.F_drive);
  for (std::size_t n = 0; n < force.size(); ++n) {
    if (trace.speed[n] == 0) {
      if (n > 0) force[n] = force[n - 1];
      continue;
    }
    const SpeedMean& m = mean_at(std::fabs(trace.speed[n]));
    force[n] =
        (trace.speed[n] > 0 ? 1 : -1) * (m.force - params.k_drive * (trace.stepper_xi[n] - m.xi_sum / m.samples));
  }
  return force;
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
  if (landmarks(params).forces_can_stall)
    throw InputError(
        "{set}: the random forces can stall the slider (alpha F_kin >= 2 (F_drive - F_kin), docs/model.md §8): a "
        "record would not be of the model's steady sliding");
  if (sensor.load_point && params.drive != Drive::spring)
    throw InputError("{load_point}: a load point pulls the slider only through a spring; {set} drive=spring");
  const std::vector<DriveStretch> program =
      sensor.program.empty() ? std::vector<DriveStretch>{{1, sensor.duration}} : sensor.program;
  const std::vector<std::size_t> starts = stretch_starts(program, sensor.sample_interval);
  double slid = 0;
  for (const DriveStretch& stretch : program) slid += std::fabs(stretch.speed_factor) * params.v * stretch.duration;
  if (sensor.resolution > 0 && sensor.resolution >= slid) {
    std::ostringstream message;
    message << "{resolution}: " << sensor.resolution << " m is no less than the whole distance slid, " << slid
            << " m: the record would be one or two readings, no spectrum of the slider; give a resolution "
            << "well below it";
    throw InputError(message.str());
  }
  if (sensor.sensor_noise >= slid) {
    std::ostringstream message;
    message << "{sensor_noise}: " << sensor.sensor_noise << " m is no less than the whole distance slid, " << slid
            << " m: the record would be the noise, no spectrum of the slider; give a noise well below it";
    throw InputError(message.str());
  }
  double asked = 0;  // the samples asked for, also where stretch_starts stopped counting
  for (const DriveStretch& stretch : program) asked += stretch.duration;
  asked = asked / sensor.sample_interval + 1;
  const double samples = starts.size() == program.size() + 1 ? double(starts.back()) + 1 : asked;
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
  SlideTrace trace = slide(params, sensor, program, starts);
  std::vector<double>& x = record.displacement;
  x = std::move(trace.path);
  // A rig reads the load point and the spring's force k_drive (load point + d0 - slider).
  if (sensor.load_point) {
    record.force = spring_force(params, trace);
    record.observable = Observable::slip;
    record.machine_stiffness = params.k_drive;
    record.force_channel = "F (N)";
  } else {
    for (std::size_t n = 0; n < x.size(); ++n) x[n] += trace.xi[n];
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
