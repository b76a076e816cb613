#include "cli/synth_command.hpp"

#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

namespace {

/// "F1:T1,F2:T2,...": the load point at F x the case's v for T seconds, stretch after stretch.
std::vector<DriveStretch> parse_program(const std::string& text) {
  std::vector<DriveStretch> program;
  std::stringstream stretches(text);
  for (std::string stretch; std::getline(stretches, stretch, ',');) {
    const auto colon = stretch.find(':');
    const std::optional<double> factor =
        colon == std::string::npos ? std::nullopt : util::parse_number(stretch.substr(0, colon));
    const std::optional<double> duration =
        colon == std::string::npos ? std::nullopt : util::parse_number(stretch.substr(colon + 1));
    if (!factor || !duration || !std::isfinite(*factor) || !(*duration > 0) || !std::isfinite(*duration))
      throw InputError("--program: '" + stretch +
                       "' is not F:T (F x the case's v, 0 a hold, for T > 0 seconds), e.g. 1:100,0:2,3:100");
    program.push_back({*factor, *duration});
  }
  if (program.empty() || text.back() == ',') throw InputError("--program: an empty stretch in '" + text + "'");
  return program;
}

/// The drive the options ask for: strokes, a program, or none (the case's v throughout).
std::vector<DriveStretch> drive_of(const SynthOptions& o, const Parameters& p) {
  if (!o.program.empty()) return parse_program(o.program);
  // --strokes and --stroke-length come together: a length given means strokes asked for,
  // and stroke_program refuses a count of 0 that would otherwise read as none.
  if (o.stroke_length.empty()) return {};
  return stroke_program(o.strokes, parse_length(o.stroke_length, LengthUnit::m, "--stroke-length"), p.v, o.dwell);
}

/// The CSV's '#' lines: what made the record, enough to make it again.
std::string synth_comments(const SynthOptions& o, const Parameters& p, const SensorRequest& sensor) {
  std::ostringstream comments;
  comments << "slidespec " << SLIDESPEC_VERSION << " synth: a simulated slider read by a displacement sensor\n"
           << "case = " << o.model.case_name << "\n"
           << "label = " << o.model.label(p) << "\n";
  for (const auto& [key, value] : describe(p)) comments << key << " = " << value << "\n";
  comments << "seed = " << sensor.seed << "\nsample_interval = " << sensor.sample_interval << " s\n"
           << "resolution = " << sensor.resolution << " m\nsensor_noise = " << sensor.sensor_noise << " m\n";
  if (!o.stroke_length.empty())
    comments << "strokes = " << o.strokes << " of " << o.stroke_length << " (dwell " << o.dwell << " s)\n";
  if (!o.program.empty()) {
    comments << "program (speed / v : seconds) =";
    for (const DriveStretch& stretch : sensor.program)
      comments << " " << util::format_number(stretch.speed_factor) << ":" << util::format_number(stretch.duration);
    comments << "\n";
  }
  if (sensor.load_point && !sensor.program.empty())
    comments << "note: each speed's mean force is the model's steady friction F_kin + (speed / v) (F_drive - F_kin); "
                "in a hold the load point and the slider stand and the force stands at its last value (the model does "
                "not relax it)\n";
  comments << "columns: t (s), x (" << to_string(parse_length_unit(o.units)) << ")"
           << (sensor.load_point ? ", F (N)" : "") << "\n";
  return comments.str();
}

void add_synth_options(CLI::App& synth, SynthOptions& o) {
  // The model's three options, with synth's own help.
  synth.add_option("--case", o.model.case_name, "named case (default reference)");
  synth.add_option("--set", o.model.overrides, "override a parameter, KEY=VALUE (repeatable)");
  synth.add_option("--params", o.model.parameter_file,
                   "JSON file of parameter overrides (as for run: a run's output JSON or its parameters block)");
  const SensorRequest sensor_default{};
  synth.add_option("--sample-interval", o.sensor.sample_interval,
                   with_default("sensor sampling interval [s]", sensor_default.sample_interval));
  synth.add_option("--duration", o.sensor.duration, with_default("record length [s]", sensor_default.duration));
  synth.add_option("--resolution", o.resolution,
                   with_default("sensor resolution q, bare in m or with a unit (0.5um), 0 for exact readings",
                                sensor_default.resolution));
  synth.add_option("--sensor-noise", o.sensor_noise,
                   with_default("rms noise before quantization, bare in m or with a unit (0.25um), which dithers "
                                "the quantizer",
                                sensor_default.sensor_noise));
  synth.add_option("--seed", o.sensor.seed, with_default("random seed", static_cast<double>(sensor_default.seed)));
  CLI::Option* strokes =
      synth.add_option("--strokes", o.strokes,
                       "a reciprocating record: K strokes of --stroke-length at the case's v, alternating in "
                       "direction (the record's length follows; no --duration)");
  CLI::Option* length =
      synth.add_option("--stroke-length", o.stroke_length, "a stroke's length, bare in m or with a unit (2mm)");
  CLI::Option* dwell = synth.add_option("--dwell", o.dwell, "a hold of T seconds at each reversal (default 0)");
  CLI::Option* program = synth.add_option(
      "--program", o.program,
      "the drive, stretch after stretch: F1:T1,F2:T2,... (F x the case's v for T seconds; 0 a hold, negative "
      "backwards; each speed the case at that speed), e.g. 1:100,0:2,1:100,3:100,0:10,0.3:290 (no --duration)");
  strokes->needs(length);
  length->needs(strokes);
  dwell->needs(strokes);
  for (CLI::Option* drive : {strokes, program}) drive->excludes(synth.get_option("--duration"));
  strokes->excludes(program);
  synth.add_option("--units", o.units, "unit of the x column: m|mm|um (default um)");
  synth.add_flag(
      "--load-point", o.sensor.load_point,
      "with drive = spring, what a rig records: x the load point's position, F (N) the spring's force "
      "(analyze with --machine-stiffness k_drive); with a program, each speed's mean force is the model's steady "
      "friction F_kin + N m eta1 v, and in a hold the force stands");
  synth.add_option("--out", o.out, "output prefix: PREFIX.csv (default record)");
}

class SynthCommand final : public Command {
 public:
  explicit SynthCommand(CLI::App& app)
      : Command(app.add_subcommand("synth", "a synthetic displacement-sensor record of a simulated slider (CSV)")) {
    add_synth_options(subcommand(), options_);
  }

  Files files() const override {
    Files files;
    options_.model.add_inputs(files);
    files.outputs_of(options_.out, "--out", {".csv"});
    return files;
  }

  int run() override {
    synthesize(options_);
    return 0;
  }

 private:
  SynthOptions options_;
};

}  // namespace

void synthesize(const SynthOptions& o) {
  io::check_output_prefix(o.out);
  const LengthUnit unit = parse_length_unit(o.units);
  const Parameters p = o.model.build();
  SensorRequest sensor = o.sensor;
  if (!o.resolution.empty()) sensor.resolution = parse_length(o.resolution, LengthUnit::m, "--resolution");
  if (!o.sensor_noise.empty()) sensor.sensor_noise = parse_length(o.sensor_noise, LengthUnit::m, "--sensor-noise");
  sensor.program = drive_of(o, p);
  const Record record = synthesize_record(p, sensor);
  io::write_atomically(o.out + ".csv", record_csv(record, unit, synth_comments(o, p, sensor)));
  std::cerr << "slidespec: wrote " << o.out << ".csv (" << record.displacement.size()
            << " samples); analyse it with: slidespec analyze " << o.out << ".csv --resolution "
            << util::format_number(sensor.resolution) << "m --sensor-noise " << util::format_number(sensor.sensor_noise)
            << "m" << (sensor.load_point ? " --machine-stiffness " + util::format_number(p.k_drive) : "") << "\n";
}

std::unique_ptr<Command> make_synth_command(CLI::App& app) { return std::make_unique<SynthCommand>(app); }

}  // namespace slidespec::cli
