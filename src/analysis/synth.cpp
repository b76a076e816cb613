// A synthetic sensor record: one simulated slider read by a displacement sensor, so the
// whole measured-data path can be tried (and tested) without a lab.
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
}  // namespace

Record synthesize_record(const Parameters& params, const SensorRequest& sensor) {
  if (!(sensor.sample_interval > 0 && std::isfinite(sensor.sample_interval)))
    throw InputError("{sample_interval}: must be a positive number of seconds");
  if (!(sensor.duration > 0 && std::isfinite(sensor.duration)))
    throw InputError("{duration}: must be a positive number of seconds");
  if (!(sensor.resolution >= 0 && std::isfinite(sensor.resolution)))
    throw InputError("{resolution}: must be a length >= 0 in metres");
  if (!(sensor.sensor_noise >= 0 && std::isfinite(sensor.sensor_noise)))
    throw InputError("{sensor_noise}: must be a length >= 0 in metres");
  // A step q at least the whole distance slid leaves a record of one or two readings: its
  // spectrum would be the quantization's, none of the slider's.
  const double slid = params.v * sensor.duration;
  if (sensor.resolution >= slid) {
    std::ostringstream message;
    message << "{resolution}: " << sensor.resolution
            << " m is no less than the whole distance slid, v {duration} = " << slid
            << " m: the record would be one or two readings, no spectrum of the slider; give a resolution "
            << "well below it";
    throw InputError(message.str());
  }
  const double samples = std::floor(sensor.duration / sensor.sample_interval) + 1;
  if (samples < 2 || samples > kMaxSamples) {
    std::ostringstream message;
    message << "{duration} / {sample_interval}: " << samples << " samples; between 2 and 1e8 are allowed";
    throw InputError(message.str());
  }

  // The stepper's discretization is exact for any step, so the step is the sample interval
  // and xi at the step ends is what a sensor sampling the slider would see.
  StepperConfig config;
  config.dt = sensor.sample_interval;
  config.seed = sensor.seed;
  Stepper stepper(params, config, 0, 1);
  Record record{.displacement = {},
                .force = {},
                .observable = Observable::displacement,
                .force_channel = {},
                .machine_stiffness = 0,
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
  record.displacement.reserve(static_cast<std::size_t>(samples));
  record.displacement.push_back(0.0);
  double xi = 0;
  stepper.advance(static_cast<std::int64_t>(samples) - 1, [&](const double* increments, std::size_t steps) {
    for (std::size_t n = 0; n < steps; ++n) {
      xi += increments[n];
      record.displacement.push_back(xi);
    }
  });

  std::mt19937_64 noise_source(sensor.seed ^ 0x5e2503ULL);  // independent of the stepper's streams
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::size_t n = 0; n < record.displacement.size(); ++n) {
    double x = params.v * static_cast<double>(n) * sensor.sample_interval + record.displacement[n];
    if (sensor.sensor_noise > 0) x += sensor.sensor_noise * noise(noise_source);
    if (sensor.resolution > 0) x = sensor.resolution * std::round(x / sensor.resolution);
    record.displacement[n] = x;
  }
  return record;
}

std::string record_csv(const Record& record, LengthUnit unit, const std::string& comments) {
  std::ostringstream out;
  std::istringstream lines(comments);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  out << "t (s),x (" << to_string(unit) << ")\n";  // units in the header: analyze reads them
  const double scale = 1 / metres_per(unit);
  char text[64];
  for (std::size_t n = 0; n < record.displacement.size(); ++n) {
    // 10 significant digits: time stamps of up to 1e7 samples at a round interval, and
    // readings of up to 1e9 resolution steps, print exactly.
    std::snprintf(text, sizeof text, "%.10g,%.10g\n", record.start_time + static_cast<double>(n) * record.dt,
                  record.displacement[n] * scale);
    out << text;
  }
  return out.str();
}

}  // namespace slidespec
