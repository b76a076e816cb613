#include "cli/analyze.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "analysis/report.hpp"
#include "cli/analysis_text.hpp"
#include "cli/analyze_many.hpp"
#include "cli/command.hpp"
#include "cli/outputs.hpp"
#include "cli/plot.hpp"
#include "cli/run_and_write.hpp"
#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

struct AnalysisCommands::Options {
  // analyze
  std::vector<std::string> files;  // as given: records or glob patterns
  std::string file;                // the record analysed
  RecordFormat format;
  std::string units;  // empty: from the header, else m
  std::string observable = "auto";
  std::string force_units;                            // empty: from the force column's header
  std::string contact_area, normal_force, stiffness;  // with their units, or bare in m^2, N, N/m
  std::string normal_stress, friction_force;          // with their units, or bare in Pa, N
  std::string estimator = "auto";
  std::string window;             // T0:T1 in record time [s]
  std::string resample = "auto";  // auto, off, median or DT [s]
  bool segments = false;
  std::string resolution, sensor_noise;  // lengths, in the record's unit or with their own
  AnalysisRequest request;               // resolution and sensor_noise: from the two above, once the record is read
  std::vector<double> slope_band;        // LO HI [rad/s]
  std::string compare_case;
  std::vector<std::string> overrides;
  std::string fit;
  std::vector<double> fit_band;  // LO HI [rad/s]
  int theory_order = 2;          // 2: the second order where it applies
  double normal_mass = 0, driving_mass = 0;
  double slider_mass = 0;  // [kg]
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
  double strokes = 0;                                // with --stroke-length
  std::string stroke_length;                         // bare in m or with a unit
  double dwell = 0;                                  // [s]
  std::string program;                               // F1:T1,F2:T2,...
  std::string synth_units = "um";
  std::string synth_out = "record";
};

namespace {

using Options = AnalysisCommands::Options;

using util::short_number;

/// A record time [s] as a user reads it off the file.
std::string seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", t);
  return text;
}

/// "T0:T1" in seconds of record time.
std::pair<double, double> parse_window(const std::string& text) {
  const auto colon = text.find(':');
  std::string problem;
  const auto t0 = colon == std::string::npos ? std::nullopt : util::parse_decimal(text.substr(0, colon), problem);
  const auto t1 = colon == std::string::npos ? std::nullopt : util::parse_decimal(text.substr(colon + 1), problem);
  if (!t0 || !t1 || !(*t1 > *t0))
    throw InputError("--window: '" + text + "' is not T0:T1 with T0 < T1 in seconds of record time (e.g. 20100:21000)");
  return {*t0, *t1};
}

/// "auto", "off", "median" or an interval in seconds, into `format`.
void parse_resample(const std::string& text, RecordFormat& format) {
  if (text == "auto") return void(format.resample = Resampling::automatic);
  if (text == "off") return void(format.resample = Resampling::off);
  if (text == "median") return void(format.resample = Resampling::median);
  std::string problem;
  const std::optional<double> dt = util::parse_decimal(text, problem);
  if (!dt || !(*dt > 0))
    throw InputError("--resample: '" + text + "' is none of auto, off, median or an interval > 0 in seconds");
  format.resample = Resampling::interval;
  format.resample_interval = *dt;
}

void print_segments(const std::vector<SteadySegment>& steady) {
  for (const SteadySegment& s : steady)
    std::cout << seconds(s.start) << "\t" << seconds(s.end) << "\t" << s.samples << "\t" << short_number(s.mean_speed)
              << "\t" << to_string(s.kind) << "\n";
}

/// analyze --segments: the steady stretches, one a line, on standard output; no file written.
/// A record whose sampling rate changes is listed part by part (each read as its own
/// --window), since an analysis can take any one of them.
int list_segments(const Options& o, const Record& record) {
  const std::vector<SteadySegment> steady = steady_segments(record);
  const bool by_parts = record.parts.size() > 1 && !record.resampled && !o.format.window;
  if (!by_parts)
    for (const std::string& note : record.notes)
      std::cerr << "slidespec: note: " << worded(note, FrontEnd::command_line) << "\n";
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
        std::cerr << "slidespec: note: part " << k + 1 << ": " << worded(note, FrontEnd::command_line) << "\n";
      print_segments(steady_segments(piece));
    } catch (const InputError& e) {
      std::cout << "# part " << k + 1 << " not listed: " << worded(e.what(), FrontEnd::command_line) << "\n";
    }
  }
  return 0;
}

/// The plan the options ask for; the floor's lengths are read once the record gives their unit.
AnalysisPlan plan_of(const Options& o) {
  AnalysisPlan plan;
  plan.request = o.request;
  plan.request.estimator = parse_estimator(o.estimator);
  plan.windowed = !o.window.empty();
  if (!o.slope_band.empty()) plan.slope_band = std::pair{o.slope_band[0], o.slope_band[1]};
  plan.compare_case = o.compare_case;
  plan.overrides = o.overrides;
  plan.fit = o.fit;
  if (!o.fit_band.empty()) plan.fit_band = std::pair{o.fit_band[0], o.fit_band[1]};
  plan.order = o.theory_order == 2 ? ModelOrder::best : ModelOrder::first;
  plan.normal_mass = o.normal_mass;
  plan.driving_mass = o.driving_mass;
  if (!o.friction_force.empty()) plan.rig.friction_force = parse_force(o.friction_force, "--friction-force");
  plan.rig.slider_mass = o.slider_mass;
  return plan;
}

/// The record's format, from the options that read it.
void parse_format(Options& o) {
  if (!o.units.empty()) o.format.unit = parse_length_unit(o.units);
  o.format.observable = parse_observable(o.observable);
  if (!o.force_units.empty()) o.format.force_unit = parse_force_unit(o.force_units);
  if (!o.contact_area.empty()) o.format.contact_area = parse_area(o.contact_area, "--contact-area");
  if (!o.normal_force.empty()) o.format.normal_force = parse_force(o.normal_force, "--normal-force");
  if (!o.normal_stress.empty()) o.format.normal_stress = parse_stress(o.normal_stress, "--normal-stress");
  if (!o.stiffness.empty())
    o.format.machine_stiffness = parse_stiffness(o.stiffness, o.format.contact_area, "--machine-stiffness");
}

/// PREFIX.tsv, .json and the figure, all or none; then the messages and the summary.
int write_analysis(const Options& o, const AnalysisReport& report) {
  const AnalysisSource source{o.file, o.compare_case};
  std::string title = o.title;
  if (!report.ok()) {
    const std::string reason = worded(report.failure(), FrontEnd::command_line);
    title = (title.empty() ? literal_title(o.file) : title) +
            (report.spectrum_verdict.ok ? " - fit FAILED: " : " - no spectrum: ") + reason.substr(0, reason.find(':'));
  }
  io::OutputSet outputs;  // the table, the JSON and the picture appear together or not at all
  outputs.add(o.out + ".tsv", analysis_table(source, report));
  const nlohmann::ordered_json model_parameters = report.model ? io::parameters_json(*report.model) : nullptr;
  outputs.add(o.out + ".json", io::json_file_text(analysis_json(report, o.file, o.compare_case, model_parameters,
                                                                FrontEnd::command_line)));
  const std::string figure = o.figure.path(o.out);
  // A spectrum of nothing has no figure: its table and JSON say why, and an old figure at
  // this prefix goes with them.
  const bool drawn = !o.no_plot && report.spectrum_verdict.ok;
  const std::string figure_temporary =
      o.no_plot ? "" : outputs.add_written_by_other(figure, std::filesystem::path(figure).extension().string());
  if (!o.no_plot && !drawn) outputs.drop(figure);
  // As for run: a set without its figure is not the set asked for, so none of it is written.
  if (drawn && plot({outputs.temporary(o.out + ".tsv")}, figure_temporary, title, o.figure) != 0)
    throw io::WriteError(figure + " not drawn; no output written (--no-plot writes the table and JSON alone)");
  outputs.commit();
  print_messages(report);
  const int status = report.ok() ? 0 : kNotWhatItClaims;
  if (o.quiet) return status;
  print_summary(source, report);
  std::cerr << "slidespec: wrote " << o.out << ".tsv, .json"
            << (drawn       ? ", ." + o.figure.format
                : o.no_plot ? ""
                            : " (no figure: no spectrum to draw)")
            << (report.ok() ? "" : " (marked ok = false)") << "\n";
  return status;
}

/// Every option read and checked, before any record is: the plan they ask for.
AnalysisPlan prepare(Options& o) {
  o.figure.check();
  io::check_output_prefix(o.out);
  parse_format(o);
  AnalysisPlan plan = plan_of(o);
  check_plan(plan, o.format.machine_stiffness);
  if (!o.window.empty()) o.format.window = parse_window(o.window);
  parse_resample(o.resample, o.format);
  return plan;
}

/// The analysis of a record read: the floor's lengths in its unit, then the plan.
AnalysisReport analyze_read(const Options& o, AnalysisPlan plan, Record record) {
  if (!o.resolution.empty()) plan.request.resolution = parse_length(o.resolution, record.unit, "--resolution");
  if (!o.sensor_noise.empty()) plan.request.sensor_noise = parse_length(o.sensor_noise, record.unit, "--sensor-noise");
  return analyze(std::move(record), plan);
}

/// analyze A B C: each record analysed as one is, into its own OUT_STEM outputs, with a line
/// each on stderr; a record refused is reported and the rest go on. The combined OUT.tsv and
/// .json list the records done, also when a signal stops the command between two.
int analyze_many(Options o) {
  if (o.segments) throw InputError("--segments lists one record's segments: give one record");
  const AnalysisPlan plan = prepare(o);
  const std::vector<std::string> records = expand_record_paths(o.files);
  const std::vector<std::string> prefixes = record_prefixes(o.out, records);
  for (const std::string& prefix : prefixes) io::check_output_prefix(prefix);
  catch_stop_signals();
  if (!o.no_plot) start_plotter();
  std::vector<ListedRecord> rows;
  bool written = true;
  for (std::size_t k = 0; k < records.size() && !stop_asked(); ++k) {
    if (!o.quiet) std::cerr << "slidespec: analyze " << k + 1 << "/" << records.size() << ": " << records[k] << "\n";
    Options one = o;
    one.file = records[k];
    one.out = prefixes[k];
    one.quiet = true;
    try {
      refuse_unreadable_record(records[k]);
      const AnalysisReport report = analyze_read(one, plan, read_record_file(one.file, one.format));
      write_analysis(one, report);
      rows.push_back({record_row(records[k], report, !o.window.empty()), prefixes[k]});
    } catch (const InputError& e) {
      rows.push_back({refused_row(records[k], e.what()), ""});
      const std::string reason = worded(e.what(), FrontEnd::command_line);
      // The reader's refusals name the file already.
      const bool named = reason.rfind(records[k] + ":", 0) == 0;
      std::cerr << "slidespec: error: " << (named ? "" : records[k] + ": ") << reason << "\n";
    } catch (const io::WriteError& e) {
      rows.push_back({refused_row(records[k], std::string("not written: ") + e.what()), ""});
      std::cerr << "slidespec: failed: " << records[k] << ": " << rows.back().row.reason << "\n";
      written = false;
    }
  }
  io::OutputSet combined;
  combined.add(o.out + ".tsv", records_table(rows, records.size()));
  combined.add(o.out + ".json", records_json(rows, records.size()));
  combined.commit();
  const auto failed = std::count_if(rows.begin(), rows.end(), [](const ListedRecord& r) { return !r.row.ok; });
  if (!o.quiet)
    std::cerr << "slidespec: wrote " << o.out << ".tsv, .json (" << rows.size() << " of " << records.size()
              << " records, " << failed << " not ok)\n";
  if (stop_asked()) return stopped_status();
  if (!written) return 1;
  return failed > 0 ? kNotWhatItClaims : 0;
}

int command_analyze(Options o) {
  if (many_records(o.files)) return analyze_many(std::move(o));
  if (!o.files.empty()) o.file = o.files.front();
  AnalysisPlan plan = prepare(o);  // before any reading
  Record record = read_record_file(o.file, o.format);
  if (o.segments) return list_segments(o, record);
  return write_analysis(o, analyze_read(o, std::move(plan), std::move(record)));
}

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

/// The drive synth's options ask for: strokes, a program, or none (the case's v throughout).
std::vector<DriveStretch> drive_of(const Options& o, const Parameters& p) {
  if (!o.program.empty()) return parse_program(o.program);
  // --strokes and --stroke-length come together: a length given means strokes asked for,
  // and stroke_program refuses a count of 0 that would otherwise read as none.
  if (o.stroke_length.empty()) return {};
  return stroke_program(o.strokes, parse_length(o.stroke_length, LengthUnit::m, "--stroke-length"), p.v, o.dwell);
}

/// The CSV's '#' lines: what made the record, enough to make it again.
std::string synth_comments(const Options& o, const Parameters& p, const SensorRequest& sensor) {
  std::ostringstream comments;
  comments << "slidespec " << SLIDESPEC_VERSION << " synth: a simulated slider read by a displacement sensor\n"
           << "case = " << o.synth_case << "\n"
           << "label = " << io::run_label(o.synth_case, p) << "\n";
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
  comments << "columns: t (s), x (" << to_string(parse_length_unit(o.synth_units)) << ")"
           << (sensor.load_point ? ", F (N)" : "") << "\n";
  return comments.str();
}

int command_synth(const Options& o) {
  io::check_output_prefix(o.synth_out);
  const LengthUnit unit = parse_length_unit(o.synth_units);
  const Parameters p = build_case(o.synth_case, o.synth_params, o.synth_overrides);
  SensorRequest sensor = o.sensor;
  if (!o.synth_resolution.empty()) sensor.resolution = parse_length(o.synth_resolution, LengthUnit::m, "--resolution");
  if (!o.synth_sensor_noise.empty())
    sensor.sensor_noise = parse_length(o.synth_sensor_noise, LengthUnit::m, "--sensor-noise");
  sensor.program = drive_of(o, p);
  const Record record = synthesize_record(p, sensor);
  io::write_atomically(o.synth_out + ".csv", record_csv(record, unit, synth_comments(o, p, sensor)));
  std::cerr << "slidespec: wrote " << o.synth_out << ".csv (" << record.displacement.size()
            << " samples); analyse it with: slidespec analyze " << o.synth_out << ".csv --resolution "
            << util::format_number(sensor.resolution) << "m --sensor-noise " << util::format_number(sensor.sensor_noise)
            << "m" << (sensor.load_point ? " --machine-stiffness " + util::format_number(p.k_drive) : "") << "\n";
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

namespace {

/// analyze's options that read the record: its columns, units, channels, sampling and window.
void add_record_options(CLI::App& analyze, Options& o) {
  analyze
      .add_option("file", o.files,
                  "CSV/TSV record ('-': stdin): a time column (or --dt) and a displacement column; several records "
                  "(or a quoted glob, 'runs/*.csv') are each analysed into PREFIX_STEM.tsv/.json/.png, and listed "
                  "in PREFIX.tsv/.json")
      ->required();
  analyze.add_option("--column", o.format.column, "displacement column (default: x, or the only other column)");
  analyze.add_option("--time-column", o.format.time_column, "time column [s] (default: t or time)");
  analyze.add_option("--dt", o.format.dt, "fixed sampling interval [s] instead of a time column");
  analyze.add_option("--units", o.units,
                     "unit of a displacement column whose header names none: m|cm|mm|um|nm|in (default: from its "
                     "header, e.g. x (mm), else m)");
  analyze.add_option("--observable", o.observable,
                     "the spectrum asked for: auto (default: slip with --machine-stiffness, force with "
                     "--force-column, else displacement) | displacement (C_x) | force (C_F [N^2 s] of the force "
                     "channel) | slip (C_x of x - F/K)");
  analyze.add_option("--force-column", o.format.force_column,
                     "force, stress or friction column (default: the first naming one, e.g. Friction, shear_MPa, "
                     "F (N); never a normal one)");
  analyze.add_option("--force-units", o.force_units,
                     "unit of a force column whose header names none: uN|mN|N|kN|MN|gf|kgf|lbf|Pa|kPa|MPa|psi|mu "
                     "(default: from its header; Friction or mu is mu)");
  analyze.add_option("--contact-area", o.contact_area,
                     "contact area A (m^2, or 25cm2, 2500mm2): a stress x A is a force, and K in MPa/um x A is N/m");
  analyze.add_option("--normal-force", o.normal_force, "normal force for a friction column: F = mu x FN (N, or kN)");
  analyze.add_option("--normal-stress", o.normal_stress,
                     "constant normal stress sigma_n (Pa, or 74MPa), with --contact-area: mu's normal load, and "
                     "the rig case's");
  analyze.add_option("--normal-stress-column", o.format.normal_stress_column,
                     "normal-stress column for a friction column: F = mu x sigma_n x A (default: a column naming a "
                     "normal stress, with --contact-area)");
  analyze.add_option("--machine-stiffness", o.stiffness,
                     "K: the slider's slip is x - F/K (N/m, kN/mm, or MPa/um with --contact-area); the observable "
                     "becomes the slip");
  analyze.add_option("--time-tolerance", o.format.time_tolerance,
                     "largest relative deviation of a sampling interval from the median accepted as uniform "
                     "(default 0.01; beyond it: refused, or --resample)");
  analyze.add_option("--resample", o.resample,
                     "sampling beyond --time-tolerance: auto (default: jitter is interpolated linearly onto the "
                     "median interval, a gap refused), off (refuse), median or DT [s] (interpolate everything, "
                     "gaps and rate changes too); the band is cut where interpolation filters it");
  analyze.add_option("--window", o.window,
                     "T0:T1: analyze only the samples with T0 <= t <= T1, in record time [s] (default: the "
                     "longest steady segment)");
  analyze.add_flag("--segments", o.segments,
                   "list the record's steady segments (start, end, mean speed; velocity steps and holds split "
                   "them) on standard output and stop");
}

/// analyze's options of the analysis itself: the floor, band, estimator, fits and outputs.
void add_analysis_options(CLI::App& analyze, Options& o) {
  analyze.add_option("--resolution", o.resolution,
                     "sensor resolution q (record's unit, or with one: 0.5um): draws the q^2/12 floor");
  analyze.add_option("--sensor-noise", o.sensor_noise,
                     "rms sensor noise before quantization (record's unit, or 0.25um): adds sigma^2 to the floor");
  analyze.add_option("--omega-min", o.request.omega_min, "lowest omega [rad/s] (default: the record allows)");
  analyze.add_option("--omega-max", o.request.omega_max,
                     "highest omega [rad/s] (default: Nyquist for welch, half of it for streaming)");
  analyze.add_option("--points", o.request.points_per_decade, "points per decade (default 8)");
  analyze.add_option("--estimator", o.estimator,
                     "auto (default: welch up to 1e7 samples, streaming beyond) | welch (Hann, 50% overlap, "
                     "8 segments, from 9 x 2 pi / T to Nyquist) | streaming (the run's estimator)");
  analyze.add_option("--fit-slope", o.slope_band, "fit C_x ~ omega^-n over LO HI [rad/s]")->expected(2);
  analyze.add_option("--compare-case", o.compare_case,
                     "overlay this model case's theory on the record's terms: its v the measured one, and with "
                     "--machine-stiffness K driven through a spring k_drive = K (--set keeps what it sets); rig: "
                     "the case built from the record and the rig (K, the mean friction, dF/dv across a velocity "
                     "step), on the rig's scale");
  analyze.add_option("--friction-force", o.friction_force,
                     "the rig case's mean friction (N, or 15kN; default: the force channel's mean)");
  analyze.add_option("--slider-mass", o.slider_mass, "the rig case's slider mass M [kg] (default: held at 1 kg)")
      ->check(CLI::Validator(
          [](const std::string& text) {
            // 0 is the library's "not known" (the mass held): given, it would be ignored.
            const auto mass = util::parse_number(text);
            return mass && *mass > 0 ? std::string() : "must be a mass > 0 in kg (leave it out when not known)";
          },
          ""));
  analyze.add_option("--set", o.overrides, "override a parameter of the compared case, KEY=VALUE");
  analyze.add_option("--fit", o.fit,
                     "alpha: fit the compared case's alpha; alpha,a (any of alpha, a, k_drive, k0): fit these model "
                     "parameters jointly with the floor, with covariance and what the band cannot determine; "
                     "power-law: C_x = A (omega/pivot)^s + floor jointly, with errors and correlations (the floor "
                     "fitted unless --resolution/--sensor-noise give it)");
  analyze
      .add_option(
          "--fit-band", o.fit_band,
          "band of the fit, LO HI [rad/s] (default: every point for power-law, the usable band for a model fit, "
          "for alpha the usable band within 5 v/a .. omega_c/3)")
      ->expected(2);
  analyze
      .add_option("--theory-order", o.theory_order,
                  "2 (default): compare and fit with the second-order theory where it can be computed (one "
                  "touching level, a constant force, periodic renewal to eps 0.25), else the first; 1: the "
                  "first order always (theory_kind in the output says whether either holds)")
      ->check(CLI::IsMember({1, 2}));
  analyze.add_option("--normal-mass", o.normal_mass, "M, mass loading the slider [kg], for mu = M'/M");
  analyze.add_option("--driving-mass", o.driving_mass, "M', hanging mass driving it [kg], for mu = M'/M");
  analyze.add_option("--out", o.out, "output prefix: PREFIX.tsv, .json, .png (default analysis)");
  analyze.add_flag("--quiet", o.quiet, "no summary");
  analyze.add_flag("--no-plot", o.no_plot, "skip the figure PREFIX.png");
  o.figure.add_to(analyze);
  // --segments lists the record's segments and stops: an output, a fit or a figure would be ignored.
  for (const char* ignored : {"--out", "--fit", "--fit-slope", "--fit-band", "--compare-case", "--set",
                              "--theory-order", "--no-plot", "--format", "--size", "--dpi", "--omega-min",
                              "--omega-max", "--points", "--estimator", "--resolution", "--sensor-noise"})
    if (CLI::Option* option = analyze.get_option_no_throw(ignored)) analyze.get_option("--segments")->excludes(option);
}

void add_synth_options(CLI::App& synth, Options& o) {
  synth.add_option("--case", o.synth_case, "named case (default reference)");
  synth.add_option("--set", o.synth_overrides, "override a parameter, KEY=VALUE (repeatable)");
  synth.add_option("--params", o.synth_params,
                   "JSON file of parameter overrides (as for run: a run's output JSON or its parameters block)");
  const SensorRequest sensor_default{};
  synth.add_option("--sample-interval", o.sensor.sample_interval,
                   with_default("sensor sampling interval [s]", sensor_default.sample_interval));
  synth.add_option("--duration", o.sensor.duration, with_default("record length [s]", sensor_default.duration));
  synth.add_option("--resolution", o.synth_resolution,
                   with_default("sensor resolution q, bare in m or with a unit (0.5um), 0 for exact readings",
                                sensor_default.resolution));
  synth.add_option("--sensor-noise", o.synth_sensor_noise,
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
  synth.add_option("--units", o.synth_units, "unit of the x column: m|mm|um (default um)");
  synth.add_flag(
      "--load-point", o.sensor.load_point,
      "with drive = spring, what a rig records: x the load point's position, F (N) the spring's force "
      "(analyze with --machine-stiffness k_drive); with a program, each speed's mean force is the model's steady "
      "friction F_kin + N m eta1 v, and in a hold the force stands");
  synth.add_option("--out", o.synth_out, "output prefix: PREFIX.csv (default record)");
}

}  // namespace

AnalysisCommands::AnalysisCommands(CLI::App& app) : options_(std::make_shared<Options>()) {
  analyze_ = app.add_subcommand("analyze", "spectrum, slope and model fit of a measured sliding-distance record");
  add_record_options(*analyze_, *options_);
  add_analysis_options(*analyze_, *options_);
  synth_ = app.add_subcommand("synth", "a synthetic displacement-sensor record of a simulated slider (CSV)");
  add_synth_options(*synth_, *options_);
}

std::optional<int> AnalysisCommands::run() const {
  if (*analyze_) return command_analyze(*options_);
  if (*synth_) return command_synth(*options_);
  return std::nullopt;
}

}  // namespace slidespec::cli
