// `slidespec analyze`: a measured record's spectrum, slope and model fit (docs/analysis.md).
#include "cli/analyze_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>

#include "analysis/report.hpp"
#include "cli/analysis_text.hpp"
#include "cli/analyze_many.hpp"
#include "cli/command.hpp"
#include "cli/outputs.hpp"
#include "cli/plot.hpp"
#include "cli/run_and_write.hpp"
#include "cli/synth_command.hpp"
#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

namespace {

/// analyze's options, as parsed.
struct AnalyzeOptions {
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
};

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
int list_segments(const AnalyzeOptions& o, const Record& record) {
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
AnalysisPlan plan_of(const AnalyzeOptions& o) {
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
void parse_format(AnalyzeOptions& o) {
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
int write_analysis(const AnalyzeOptions& o, const AnalysisReport& report) {
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
AnalysisPlan prepare(AnalyzeOptions& o) {
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
AnalysisReport analyze_read(const AnalyzeOptions& o, AnalysisPlan plan, Record record) {
  if (!o.resolution.empty()) plan.request.resolution = parse_length(o.resolution, record.unit, "--resolution");
  if (!o.sensor_noise.empty()) plan.request.sensor_noise = parse_length(o.sensor_noise, record.unit, "--sensor-noise");
  return analyze(std::move(record), plan);
}

/// analyze A B C: each record analysed as one is, into its own OUT_STEM outputs, with a line
/// each on stderr; a record refused is reported and the rest go on. The combined OUT.tsv and
/// .json list the records done, also when a signal stops the command between two.
int analyze_many(AnalyzeOptions o) {
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
    AnalyzeOptions one = o;
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

int command_analyze(AnalyzeOptions o) {
  if (many_records(o.files)) return analyze_many(std::move(o));
  if (!o.files.empty()) o.file = o.files.front();
  AnalysisPlan plan = prepare(o);  // before any reading
  Record record = read_record_file(o.file, o.format);
  if (o.segments) return list_segments(o, record);
  return write_analysis(o, analyze_read(o, std::move(plan), std::move(record)));
}

/// analyze's options that read the record: its columns, units, channels, sampling and window.
void add_record_options(CLI::App& analyze, AnalyzeOptions& o) {
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
void add_analysis_options(CLI::App& analyze, AnalyzeOptions& o) {
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
  std::string fittable;
  for (const std::string& name : fittable_parameters()) fittable += (fittable.empty() ? "" : ", ") + name;
  analyze.add_option("--fit", o.fit,
                     "alpha: fit the compared case's alpha; alpha,a (any of " + fittable +
                         "): fit these model parameters jointly with the floor, with covariance and what the band "
                         "cannot determine; power-law: C_x = A (omega/pivot)^s + floor jointly, with errors and "
                         "correlations (the floor fitted unless --resolution/--sensor-noise give it)");
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

/// analyze: the files it reads and writes, from its options, and the analysis.
class AnalyzeCommand final : public Command {
 public:
  explicit AnalyzeCommand(CLI::App& app)
      : Command(app.add_subcommand("analyze", "spectrum, slope and model fit of a measured sliding-distance record")) {
    add_record_options(subcommand(), options_);
    add_analysis_options(subcommand(), options_);
  }

  Files files() const override {
    Files files;
    if (many_records(options_.files)) {
      many_files(files);
    } else {
      for (const std::string& path : options_.files) files.input(path, "analyze");
      files.outputs_of(options_.out, "--out", {".tsv", ".json", "." + options_.figure.format});
    }
    return files;
  }

  int run() override {
    // A sampling interval of 0 reads as "from the time column": refused when given, in the
    // words the user typed (the option holds it parsed).
    const CLI::Option* dt = subcommand().get_option("--dt");
    for (const std::string& text : dt->count() == 0 ? std::vector<std::string>{} : dt->results())
      if (const auto seconds = util::parse_number(text); !seconds || !(*seconds > 0) || !std::isnormal(*seconds))
        throw InputError("--dt: need a positive sampling interval in seconds, at least " +
                         util::format_number(std::numeric_limits<double>::min()) + " (got " + text + ")");
    return command_analyze(options_);
  }

 private:
  /// analyze A B C: each record's outputs and the combined table. A record that cannot be
  /// read is not refused here but reported as the records are analysed, and the rest go on;
  /// the records that can are inputs, which no output may replace.
  void many_files(Files& files) const {
    const std::vector<std::string> records = expand_record_paths(options_.files);
    const std::vector<std::string> prefixes = record_prefixes(options_.out, records);
    for (std::size_t k = 0; k < records.size(); ++k) {
      std::error_code ignored;
      if (std::filesystem::is_regular_file(records[k], ignored) && access(records[k].c_str(), R_OK) == 0)
        files.input(records[k], "analyze");
      files.outputs_of(prefixes[k], "--out", {".tsv", ".json", "." + options_.figure.format});
    }
    files.outputs_of(options_.out, "--out", {".tsv", ".json"});
  }

  AnalyzeOptions options_;
};

}  // namespace

int paper_fig6(const std::string& record, const std::string& directory, const FigureStyle& figure, bool quiet) {
  figure.check();
  AnalyzeOptions o;
  o.out = directory + "/fig6";
  io::check_output_prefix(o.out);
  o.file = record;
  if (record.empty()) {
    // A measured-like record: the concrete-fit slider read by the paper's sensor.
    SynthOptions synth;
    synth.model.case_name = "concrete-fit";
    synth.out = directory + "/fig6_record";
    io::check_output_prefix(synth.out);
    synthesize(synth);
    o.file = synth.out + ".csv";
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

std::unique_ptr<Command> make_analyze_command(CLI::App& app) { return std::make_unique<AnalyzeCommand>(app); }

}  // namespace slidespec::cli
