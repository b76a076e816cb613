// slidespec._core: the core library for Python. It converts arrays, exceptions and the
// GIL and nothing else; the interface users meet is python/slidespec/__init__.py.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <variant>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/many_records.hpp"
#include "slidespec/options.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"
#include "util/numbers.hpp"

namespace py = pybind11;
using namespace slidespec;

namespace {

using Overrides = std::vector<std::pair<std::string, std::string>>;
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// The case with its overrides, as the command line's --case and --set build it.
Parameters build(const std::string& case_name, const Overrides& overrides) {
  std::vector<std::string> assignments;
  for (const auto& [key, value] : overrides) assignments.push_back(key + "=" + value);
  return build_case(case_name, assignments);
}

Array to_array(const std::vector<double>& values) {
  Array out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

std::vector<double> to_vector(const Array& values) {
  return std::vector<double>(values.data(), values.data() + values.size());
}

/// A number as a PREFIX.json field holds it: None where the JSON writes null (inf, nan).
py::object number(double value) { return std::isfinite(value) ? py::object(py::float_(value)) : py::none(); }

template <class T>
py::object field(const T& value) {
  return py::cast(value);
}
py::object field(double value) { return number(value); }

/// One value of each point [double], inf and nan as NaN: as a column read back from the
/// JSON's nulls.
template <class Point, class Value>
Array column(const std::vector<Point>& points, Value value) {
  Array out(static_cast<py::ssize_t>(points.size()));
  double* data = out.mutable_data();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double v = value(points[k]);
    data[k] = std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN();
  }
  return out;
}

/// A column of counts or flags, in the type the JSON gives them.
template <class T, class Point, class Value>
py::array_t<T> typed_column(const std::vector<Point>& points, Value value) {
  py::array_t<T> out(static_cast<py::ssize_t>(points.size()));
  T* data = out.mutable_data();
  for (std::size_t k = 0; k < points.size(); ++k) data[k] = static_cast<T>(value(points[k]));
  return out;
}

/// The parameters as PREFIX.json's "parameters" holds them: numbers typed as it types them.
py::dict parameters_dict(const Parameters& p) {
  py::dict d;
  for (const auto& [key, value] : io::parameter_values(p))
    std::visit([&d, &key = key](const auto& v) { d[py::str(key)] = field(v); }, value);
  return d;
}

/// A run's fields, named and ordered as PREFIX.json names them (io::run_json).
py::dict run_fields(const RunSession& session, const RunResult& result) {
  const Parameters& p = session.parameters();
  const RunRequest& request = session.request();
  py::dict d;
  d["slidespec_version"] = SLIDESPEC_VERSION;
  d["versions"] = io::versions();
  d["case"] = io::case_of(session.case_name());
  d["label"] = session.case_name();
  d["parameters"] = parameters_dict(p);
  py::dict landmarks;
  for (const Landmark& mark : shown_landmarks(p, LandmarkOutput::json))
    std::visit([&](const auto& value) { landmarks[mark.row->key] = field(value); }, mark.value);
  d["landmarks"] = landmarks;
  d["request"] =
      py::dict(py::arg("omega_min") = request.omega_min, py::arg("omega_max") = request.omega_max,
               py::arg("points_per_decade") = request.points_per_decade, py::arg("precision") = request.precision,
               py::arg("duration") = request.duration, py::arg("realizations") = request.realizations,
               py::arg("seed") = request.seed, py::arg("control_variate") = request.control_variate ? "shadow" : "off");
  d["complete"] = result.complete;
  d["stationary"] = result.stationary;
  if (!result.stationary) d["stationarity"] = result.stationarity;
  d["reached_precision"] = number(result.reached_precision);
  if (!result.theory2_note.empty()) d["theory2_note"] = result.theory2_note;
  d["theory_kind"] = theory_kind_name(result.theory_kind);
  if (!result.theory_kind_note.empty()) d["theory_kind_note"] = result.theory_kind_note;
  d["measured_mean_speed"] = py::dict(py::arg("value") = number(result.mean_speed),
                                      py::arg("standard_error") = number(result.mean_speed_error));
  d["simulated_time"] = number(result.simulated_time);
  d["wall_seconds"] = number(result.wall_seconds);
  d["realization_steps"] = number(result.realization_steps);
  d["miniblock_steps"] = number(result.miniblock_steps);
  d["throughput_miniblock_steps_per_second"] =
      number(result.wall_seconds > 0 ? result.miniblock_steps / result.wall_seconds : 0.0);
  d["simd_path"] = to_string(result.simd_path);
  d["threads"] = result.threads;
  py::list bands;
  for (const SubBand& b : result.sub_bands)
    bands.append(py::dict(py::arg("omega_low") = number(b.omega_low), py::arg("omega_high") = number(b.omega_high),
                          py::arg("dt") = number(b.dt), py::arg("duration") = number(b.duration),
                          py::arg("warm_up") = number(b.warm_up), py::arg("warm_up_dt") = number(b.warm_up_dt),
                          py::arg("shadow") = b.shadow, py::arg("realizations") = b.realizations,
                          py::arg("rounds") = b.rounds));
  if (!result.sub_bands.empty()) d["sub_bands"] = bands;
  return d;
}

/// A run's points as columns, named and ordered as PREFIX.json's points.
py::dict run_columns(const Parameters& p, const std::vector<RunPoint>& points) {
  py::dict c;
  c["omega"] = column(points, [](const RunPoint& q) { return q.omega; });
  c["C_x"] = column(points, [](const RunPoint& q) { return q.C_x; });
  c["stderr"] = column(points, [](const RunPoint& q) { return q.standard_error; });
  c["n_avg"] = column(points, [](const RunPoint& q) { return q.n_avg; });
  c["bandwidth"] = column(points, [](const RunPoint& q) { return q.bandwidth; });
  c["theory"] = column(points, [](const RunPoint& q) { return q.theory; });
  c["theory_at_omega"] = column(points, [](const RunPoint& q) { return q.theory_at_omega; });
  c["bins"] =
      py::dict(py::arg("first") = column(points, [](const RunPoint& q) { return q.bins.first; }),
               py::arg("last") = column(points, [](const RunPoint& q) { return q.bins.last; }),
               py::arg("spacing") = column(points, [](const RunPoint& q) { return q.bins.spacing; }),
               py::arg("count") = typed_column<std::int64_t>(points, [](const RunPoint& q) { return q.bins.count; }));
  c["theory2"] = column(points, [](const RunPoint& q) { return q.theory2; });
  c["variance_ratio"] = column(points, [](const RunPoint& q) { return q.variance_ratio; });
  py::list estimators, kinds;
  for (const RunPoint& q : points) {
    estimators.append(q.estimator);
    kinds.append(theory_kind_name(q.theory_kind));
  }
  c["estimator"] = estimators;
  c["theory_kind"] = kinds;
  c["correction"] = column(points, [](const RunPoint& q) { return q.C_x / q.theory - 1; });
  c["correction_stderr"] = column(points, [](const RunPoint& q) { return q.standard_error / q.theory; });
  if (p.drive == Drive::spring) {
    c["C_F_spring"] = column(points, [&](const RunPoint& q) { return spring_force_spectrum(p, q.C_x); });
    c["C_F_spring_stderr"] =
        column(points, [&](const RunPoint& q) { return spring_force_spectrum(p, q.standard_error); });
    c["C_F_spring_theory"] = column(points, [&](const RunPoint& q) { return spring_force_spectrum(p, q.theory); });
  }
  return c;
}

/// A run advanced by its own thread, so that the caller's thread keeps the interpreter
/// (signals, progress bars) and can ask it to stop. Python never runs on the worker.
class Run {
 public:
  explicit Run(RunSession session) : session_(std::move(session)) {}
  ~Run() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();  // the workers never take the GIL: no deadlock
  }
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  void start(int threads, const std::string& simd) {
    if (thread_.joinable()) throw std::logic_error("the run was started already");
    RunRequest execution = session_.request();  // the thread count checked as the command line checks it
    execution.threads = threads;
    validate_request(session_.parameters(), execution);
    const SimdPath path = parse_simd_path(simd);
    resolve_simd_path(path);
    session_.set_execution(threads, path);
    done_ = false;
    thread_ = std::thread([this] {
      RunSession::Control control;
      control.stop = &stop_;
      control.progress = [this](double fraction, const std::string& what) {
        const std::lock_guard<std::mutex> lock(mutex_);
        fraction_ = fraction;
        what_ = what;
      };
      bool finished = false;
      std::exception_ptr error;
      try {
        finished = session_.advance(control);
      } catch (...) {
        error = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex_);
      finished_ = finished;
      error_ = error;
      done_ = true;
      ended_.notify_all();
    });
  }

  /// Waits up to `seconds` for the run to end, without the GIL; true when it has.
  bool wait(double seconds) {
    py::gil_scoped_release release;
    std::unique_lock<std::mutex> lock(mutex_);
    return ended_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return done_; });
  }

  std::pair<double, std::string> progress() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return {fraction_, what_};
  }

  void stop() { stop_ = true; }

  /// Ends the thread (after stop(), at its next batch); true when the run reached its end.
  bool join() {
    {
      py::gil_scoped_release release;
      if (thread_.joinable()) thread_.join();
    }
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
    return finished_;
  }

  /// The result as (fields, columns): what `slidespec run` writes to PREFIX.json, its
  /// points as numpy columns.
  py::tuple result() const {
    RunResult result;
    {
      py::gil_scoped_release release;
      result = session_.result();
    }
    return py::make_tuple(run_fields(session_, result), run_columns(session_.parameters(), result.points));
  }

  py::bytes save() const { return py::bytes(session_.save()); }
  bool finished() const { return session_.finished(); }

 private:
  RunSession session_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable ended_;
  double fraction_ = 0;
  std::string what_;
  bool done_ = true, finished_ = false;
  std::exception_ptr error_;
};

std::unique_ptr<Run> new_run(const std::string& case_name, const Overrides& overrides, const py::dict& request) {
  RunRequest r;
  r.omega_min = request["omega_min"].cast<double>();
  r.omega_max = request["omega_max"].cast<double>();
  r.points_per_decade = request["points_per_decade"].cast<int>();
  r.precision = request["precision"].cast<double>();
  r.duration = request["duration"].cast<double>();
  r.realizations = request["realizations"].cast<std::uint64_t>();
  r.seed = request["seed"].cast<std::uint64_t>();
  r.control_variate = request["control_variate"].cast<bool>();
  const Parameters params = build(case_name, overrides);
  // Labelled as the command line labels it ("reference + N=12, alpha=0.4").
  return std::make_unique<Run>(RunSession(params, r, io::run_label(case_name, params)));
}

/// How a format dict reads a record (its units, when None, from each file's header).
RecordFormat format_of(const py::dict& format) {
  RecordFormat f;
  f.dt = format["dt"].cast<double>();
  if (!format["units"].is_none()) f.unit = parse_length_unit(format["units"].cast<std::string>());
  f.time_tolerance = format["time_tolerance"].cast<double>();
  if (!format["window"].is_none()) {
    const auto window = format["window"].cast<std::pair<double, double>>();
    if (!(window.second > window.first)) throw InputError("window: need (t0, t1) with t0 < t1 [s]");
    f.window = window;
  }
  const std::string resample = format["resample"].cast<std::string>();
  const std::optional<Resampling> named = resample == "auto"     ? std::optional(Resampling::automatic)
                                          : resample == "off"    ? std::optional(Resampling::off)
                                          : resample == "median" ? std::optional(Resampling::median)
                                                                 : std::nullopt;
  f.resample = named.value_or(Resampling::interval);
  if (!named) {
    f.resample_interval = format["resample_interval"].cast<double>();
    if (!(f.resample_interval > 0)) throw InputError("resample: 'auto', 'off', 'median' or an interval > 0 [s]");
  }
  f.observable = parse_observable(format["observable"].cast<std::string>());
  if (!format["force_units"].is_none()) f.force_unit = parse_force_unit(format["force_units"].cast<std::string>());
  f.contact_area = format["contact_area"].cast<double>();
  f.normal_force = format["normal_force"].cast<double>();
  if (const double stress = format["normal_stress_value"].cast<double>(); stress != 0)
    f.normal_stress = parse_stress(util::format_number(stress) + format["normal_stress_units"].cast<std::string>(),
                                   "{normal_stress}");
  f.machine_stiffness = format["machine_stiffness"].cast<double>();
  return f;
}

/// The record a format dict describes: its channels as named columns, read as a file with
/// that header is (units from the format).
Record record_of(const Array& time, const Array& x, const py::dict& format) {
  RecordFormat f = format_of(format);
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  if (time.size() > 0) names.push_back("t"), columns.push_back(to_vector(time));
  if (x.size() > 0) names.push_back("x"), columns.push_back(to_vector(x));
  if (!format["force"].is_none())
    names.push_back("channel"), columns.push_back(to_vector(format["force"].cast<Array>()));
  if (!format["normal_stress"].is_none()) {
    names.push_back("normal_stress (" + format["normal_stress_units"].cast<std::string>() + ")");
    columns.push_back(to_vector(format["normal_stress"].cast<Array>()));
  }
  if (f.observable != Observable::displacement || f.machine_stiffness > 0)
    f.force_column = format["force"].is_none() ? "" : "channel";
  py::gil_scoped_release release;
  return record_from_columns(names, columns, f);
}

std::optional<std::pair<double, double>> band_of(const py::handle& band) {
  if (band.is_none()) return std::nullopt;
  return band.cast<std::pair<double, double>>();
}

/// The plan a dict asks for; lengths in metres whatever the record's unit.
AnalysisPlan plan_of(const py::dict& plan, bool windowed) {
  AnalysisPlan p;
  p.request.omega_min = plan["omega_min"].cast<double>();
  p.request.omega_max = plan["omega_max"].cast<double>();
  p.request.points_per_decade = plan["points_per_decade"].cast<int>();
  p.request.resolution = plan["resolution"].cast<double>();
  p.request.sensor_noise = plan["sensor_noise"].cast<double>();
  p.request.estimator = parse_estimator(plan["estimator"].cast<std::string>());
  p.windowed = windowed;
  p.slope_band = band_of(plan["fit_slope"]);
  p.compare_case = plan["compare_case"].cast<std::string>();
  for (const auto& [key, value] : plan["overrides"].cast<Overrides>()) p.overrides.push_back(key + "=" + value);
  p.fit = plan["fit"].cast<std::string>();
  p.fit_band = band_of(plan["fit_band"]);
  p.rig.friction_force = plan["friction_force"].cast<double>();
  p.rig.slider_mass = plan["slider_mass"].cast<double>();
  const int order = plan["theory_order"].cast<int>();
  if (order != 1 && order != 2) throw InputError("theory_order: 1 or 2");
  p.order = order == 2 ? ModelOrder::best : ModelOrder::first;
  p.bare_lengths_in_record_unit = false;
  return p;
}

const char* kind_name(AnalysisMessage::Kind kind) {
  switch (kind) {
    case AnalysisMessage::Kind::note:
      return "note";
    case AnalysisMessage::Kind::warning:
      return "warning";
    case AnalysisMessage::Kind::failed_fit:
      return "failed_fit";
    case AnalysisMessage::Kind::no_spectrum:
      return "no_spectrum";
  }
  return "?";
}

/// A fit's dict with its verdict: ok, and why not (worded for Python).
py::dict with_verdict(py::dict d, const Verdict& verdict) {
  d["ok"] = verdict.ok;
  d["failure"] = worded(verdict.reason, FrontEnd::python);
  return d;
}

py::dict value_and_error(double value, double error) {
  return py::dict(py::arg("value") = number(value), py::arg("standard_error") = number(error));
}

/// A matrix of doubles as lists of numbers (None for inf and nan), as the JSON writes it.
template <class Rows>
py::list matrix(const Rows& rows) {
  py::list out;
  for (const auto& row : rows) {
    py::list values;
    for (double value : row) values.append(number(value));
    out.append(values);
  }
  return out;
}

py::dict slope_fit_fields(const SlopeFit& f, const Verdict& verdict) {
  return with_verdict(
      py::dict(py::arg("omega_low") = number(f.omega_low), py::arg("omega_high") = number(f.omega_high),
               py::arg("points") = f.points, py::arg("slope") = number(f.slope),
               py::arg("standard_error") = number(f.slope_error), py::arg("chi2_per_dof") = number(f.chi2_per_dof),
               py::arg("amplitude") = number(f.amplitude), py::arg("force_slope") = number(f.force_slope()),
               py::arg("reaches_floor") = f.reaches_floor),
      verdict);
}

py::dict power_law_fields(const PowerLawFit& p, const Verdict& verdict) {
  return with_verdict(
      py::dict(py::arg("omega_low") = number(p.omega_low), py::arg("omega_high") = number(p.omega_high),
               py::arg("pivot") = number(p.pivot), py::arg("points") = p.points, py::arg("dof") = p.dof,
               py::arg("amplitude") = number(p.amplitude), py::arg("amplitude_error") = number(p.amplitude_error),
               py::arg("slope") = number(p.slope), py::arg("slope_error") = number(p.slope_error),
               py::arg("floor") = number(p.floor), py::arg("floor_error") = number(p.floor_error),
               py::arg("floor_given") = p.floor_given, py::arg("correlation") = matrix(p.correlation),
               py::arg("chi2_per_dof") = number(p.chi2_per_dof),
               py::arg("slope_at_search_edge") = p.slope_at_search_edge,
               py::arg("undetermined") = worded(p.undetermined, FrontEnd::python)),
      verdict);
}

py::dict alpha_fit_fields(const AlphaFit& f, const Verdict& verdict) {
  return with_verdict(
      py::dict(py::arg("omega_low") = number(f.omega_low), py::arg("omega_high") = number(f.omega_high),
               py::arg("points") = f.points, py::arg("alpha") = number(f.alpha),
               py::arg("standard_error") = number(f.alpha_error), py::arg("chi2_per_dof") = number(f.chi2_per_dof),
               py::arg("theory_order") = f.theory_order),
      verdict);
}

py::dict model_fit_fields(const ModelFit& m, const Verdict& verdict) {
  py::dict values;
  for (std::size_t i = 0; i < m.names.size(); ++i)
    values[py::str(m.names[i])] = value_and_error(m.values[i], m.errors[i]);
  return with_verdict(py::dict(py::arg("omega_low") = number(m.omega_low), py::arg("omega_high") = number(m.omega_high),
                               py::arg("points") = m.points, py::arg("dof") = m.dof, py::arg("parameters") = values,
                               py::arg("names") = m.names, py::arg("covariance") = matrix(m.covariance),
                               py::arg("floor") = number(m.floor), py::arg("floor_error") = number(m.floor_error),
                               py::arg("floor_given") = m.floor_given,
                               py::arg("alpha2_over_N") = value_and_error(m.amplitude, m.amplitude_error),
                               py::arg("chi2_per_dof") = number(m.chi2_per_dof), py::arg("converged") = m.converged,
                               py::arg("theory_order") = m.theory_order,
                               py::arg("undetermined") = worded(m.undetermined, FrontEnd::python)),
                      verdict);
}

/// The record's stretches and strokes, as analysis_json lists them.
void add_segments(py::dict& d, const RecordSpectrum& s) {
  py::list segments;
  for (const SteadySegment& g : s.segments)
    segments.append(py::dict(py::arg("start") = number(g.start), py::arg("end") = number(g.end),
                             py::arg("kind") = to_string(g.kind), py::arg("mean_speed") = number(g.mean_speed),
                             py::arg("hold") = g.hold));
  d["segments"] = segments;
  if (s.strokes)
    d["strokes"] = py::dict(py::arg("count") = s.strokes->middles.size(), py::arg("speed") = number(s.strokes->speed),
                            py::arg("middle_duration") = number(s.strokes->middle_duration),
                            py::arg("lowest_omega") = number(s.strokes->lowest_omega));
}

/// How the spectrum was estimated, with Welch's segments and choices.
py::dict estimator_fields(const RecordSpectrum& s) {
  py::dict e(py::arg("name") = to_string(s.estimator),
             py::arg("reason") = worded(s.estimator_reason, FrontEnd::python));
  if (s.estimator == Estimator::welch) {
    e["window"] = kWelchWindow;
    e["overlap"] = kWelchOverlap;
    e["prewhitening"] = kWelchPrewhitening;
    e["segment_samples"] = s.welch.segment_samples;
    e["segments"] = s.welch.segments;
    e["bin_spacing"] = number(s.welch.bin_spacing);
    e["leaky_points"] = s.leaky_points;
  }
  return e;
}

/// The spectrum's own fields, named and ordered as analysis_json's (its points apart).
void add_spectrum_fields(py::dict& d, const AnalysisReport& r) {
  const RecordSpectrum& s = r.spectrum;
  add_segments(d, s);
  py::dict observable(py::arg("name") = to_string(s.observable), py::arg("spectrum") = spectrum_name(s.observable),
                      py::arg("unit") = spectrum_unit(s.observable), py::arg("channel") = s.channel);
  if (s.observable != Observable::displacement) observable["force_channel"] = r.record.force_channel;
  if (s.observable == Observable::slip) observable["machine_stiffness"] = number(r.record.machine_stiffness);
  d["observable"] = observable;
  d["spectrum_ok"] = r.spectrum_verdict.ok;
  if (!r.spectrum_verdict.ok) d["spectrum_failure"] = worded(r.spectrum_verdict.reason, FrontEnd::python);
  if (s.observable == Observable::force) {
    d["mean_force"] = number(s.mean_force());
    d["force_trend"] = value_and_error(s.sliding.v, s.sliding.v_error);
    d["F_rms"] = number(s.sliding.xi_rms);
  } else {
    py::dict speed = value_and_error(s.sliding.v, s.sliding.v_error);
    speed["blocks"] = s.sliding.blocks;
    d["measured_mean_speed"] = speed;
    d["xi_rms"] = number(s.sliding.xi_rms);
  }
  d["quantization_variance"] = number(s.quantization_variance);
  d["top_to_floor"] = number(s.top_to_floor);
  d["readings_off_grid"] = s.readings_off_grid;
  d["usable_band"] =
      py::dict(py::arg("omega_low") = number(s.usable_low), py::arg("omega_high") = number(s.usable_high),
               py::arg("empty") = !s.has_usable_band(), py::arg("floor_above_spectrum") = s.floor_above_spectrum,
               py::arg("top_set_by") = top_set_by(s));
  d["estimator"] = estimator_fields(s);
}

/// An analysis's fields, named and ordered as `slidespec analyze`'s PREFIX.json (analysis_json)
/// but its points: `file` in the record's fields unless empty, `model_parameters` the
/// compared case's parameters.
py::dict analysis_fields(const AnalysisReport& r, const std::string& file, const std::string& compare_case) {
  const RecordSpectrum& s = r.spectrum;
  py::dict d;
  d["slidespec_version"] = SLIDESPEC_VERSION;
  d["ok"] = r.ok();
  py::dict record;
  if (!file.empty()) record["file"] = file;
  record["column"] = r.record.column;
  record["units"] = to_string(r.record.unit);
  record["units_from"] = worded(r.record.unit_source, FrontEnd::python);
  record["samples"] = s.samples;
  record["dt"] = number(s.dt);
  record["duration"] = number(s.duration);
  record["start_time"] = number(r.record.start_time);
  record["end_time"] = number(r.end_time());
  d["record"] = record;
  add_spectrum_fields(d, r);
  if (r.mu) d["mu"] = number(*r.mu);
  d["resolution"] = number(r.request.resolution);
  d["sensor_noise"] = number(r.request.sensor_noise);
  py::list notes;
  for (const AnalysisMessage& note : r.notes) notes.append(worded(note.text, FrontEnd::python));
  d["notes"] = notes;
  if (r.slope) d["slope_fit"] = slope_fit_fields(*r.slope, r.slope_verdict);
  if (r.power_law) d["power_law_fit"] = power_law_fields(*r.power_law, r.power_law_verdict);
  if (r.model_fit) d["model_fit"] = model_fit_fields(*r.model_fit, r.model_fit_verdict);
  if (r.model) {
    d["compare_case"] = compare_case;
    d["model_parameters"] = parameters_dict(*r.model);
    d["theory_order"] = r.model_order;
  }
  if (r.alpha) d["alpha_fit"] = alpha_fit_fields(*r.alpha, r.alpha_verdict);
  return d;
}

/// An analysis's points as columns, named and ordered as `slidespec analyze`'s PREFIX.json
/// names them, with each point's fit and residual when a power law or a model was fitted.
py::dict analysis_columns(const AnalysisReport& report) {
  const RecordSpectrum& s = report.spectrum;
  const std::vector<AnalysisPoint>& points = s.points;
  py::dict c;
  c["omega"] = column(points, [](const AnalysisPoint& q) { return q.omega; });
  c[spectrum_name(s.observable)] = column(points, [](const AnalysisPoint& q) { return q.C_x; });
  c["stderr"] = column(points, [](const AnalysisPoint& q) { return q.standard_error; });
  c["n_avg"] = column(points, [](const AnalysisPoint& q) { return q.n_avg; });
  c["bandwidth"] = column(points, [](const AnalysisPoint& q) { return q.bandwidth; });
  c["floor"] = column(points, [](const AnalysisPoint& q) { return q.noise_floor; });
  c["below_floor"] = typed_column<bool>(points, [](const AnalysisPoint& q) { return q.below_floor; });
  c["dof"] = column(points, [](const AnalysisPoint& q) { return q.dof; });
  c["segment_samples"] = typed_column<std::int64_t>(points, [](const AnalysisPoint& q) { return q.segment_samples; });
  c["leaky"] = typed_column<bool>(points, [](const AnalysisPoint& q) { return q.leaky; });
  c["C_low"] = column(points, [](const AnalysisPoint& q) { return q.lower; });
  c["C_high"] = column(points, [](const AnalysisPoint& q) { return q.upper; });
  if (s.estimator == Estimator::welch) {
    c["first_bin"] = typed_column<std::int64_t>(s.welch.points, [](const WelchPoint& q) { return q.first_bin; });
    c["bins"] = typed_column<std::int64_t>(s.welch.points, [](const WelchPoint& q) { return q.bins; });
  }
  // Per point, NaN past the end of a shorter list (as a point the JSON gives no value reads).
  const auto values = [&points](const std::vector<double>& v) {
    std::vector<double> padded(points.size(), std::numeric_limits<double>::quiet_NaN());
    std::copy_n(v.begin(), std::min(v.size(), padded.size()), padded.begin());
    return column(padded, [](double x) { return x; });
  };
  if (!report.model_values.empty()) c["theory"] = values(report.model_values);
  const PowerLawFit* power_law = report.power_law ? &*report.power_law : nullptr;
  const ModelFit* model_fit = report.model_fit ? &*report.model_fit : nullptr;
  if (power_law || model_fit) {
    c["fit"] = values(power_law ? power_law->model : model_fit->model);
    c["residual"] = values(power_law ? power_law->residuals : model_fit->residuals);
  }
  return c;
}

/// An analysis as (fields, columns, warnings): PREFIX.json's fields but its points, the
/// points as columns, and each warning as (kind, topic, text) worded for Python.
py::tuple analysis_result(const AnalysisReport& report, const std::string& file, const std::string& compare_case) {
  py::list messages;
  for (const AnalysisMessage& m : report.warnings)
    messages.append(py::make_tuple(kind_name(m.kind), m.topic, worded(m.text, FrontEnd::python)));
  return py::make_tuple(analysis_fields(report, file, compare_case), analysis_columns(report), messages);
}

bool on_main_thread() {
  const py::module_ threading = py::module_::import("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}

/// `work(stop)` on a thread of its own while this one waits without the GIL, taking it back
/// every tenth of a second to let Python's signal handlers run: when one raises (Ctrl-C),
/// `stop` is set, which the library hears within a second, and the error is raised once the
/// work has ended. Off the main thread no handler runs: the work runs there, without the GIL.
template <class Work>
auto interruptible(const Work& work) -> decltype(work(nullptr)) {
  if (!on_main_thread()) {
    py::gil_scoped_release release;
    return work(nullptr);
  }
  std::atomic<bool> stop{false};
  std::optional<decltype(work(nullptr))> result;
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable ended;
  bool done = false;
  std::thread worker([&] {
    try {
      result.emplace(work(&stop));
    } catch (...) {
      failure = std::current_exception();
    }
    const std::lock_guard<std::mutex> lock(mutex);
    done = true;
    ended.notify_all();
  });
  bool interrupted = false;
  for (bool finished = false; !finished;) {
    {
      py::gil_scoped_release release;
      std::unique_lock<std::mutex> lock(mutex);
      finished = ended.wait_for(lock, std::chrono::milliseconds(100), [&] { return done; });
    }
    if (!interrupted && PyErr_CheckSignals() != 0) {
      interrupted = true;
      stop = true;
    }
  }
  worker.join();
  if (interrupted) throw py::error_already_set();
  if (failure) std::rethrow_exception(failure);
  return std::move(*result);
}

/// `slidespec analyze` of a record given as arrays.
py::tuple analyze_record(const Array& time, const Array& x, const py::dict& format, const py::dict& plan) {
  Record record = record_of(time, x, format);
  const AnalysisPlan p = plan_of(plan, !format["window"].is_none());
  const AnalysisReport report = interruptible([&](const std::atomic<bool>* stop) {
    AnalysisPlan heard = p;
    heard.request.stop = stop;
    return analyze(std::move(record), heard);
  });
  return analysis_result(report, "", p.compare_case);
}

/// A row of the combined table, named as `slidespec analyze A B C`'s OUT.json names it (None
/// for a number not found, and for the segment of a record refused).
py::dict row_dict(const RecordRow& r) {
  return py::dict(py::arg("file") = r.file,
                  py::arg("segment") = r.segment.empty() ? py::object(py::none()) : py::object(py::str(r.segment)),
                  py::arg("start") = number(r.start), py::arg("end") = number(r.end), py::arg("v") = number(r.v),
                  py::arg("v_err") = number(r.v_error), py::arg("usable_low") = number(r.usable_low),
                  py::arg("usable_high") = number(r.usable_high), py::arg("slope") = number(r.slope),
                  py::arg("slope_err") = number(r.slope_error), py::arg("alpha") = number(r.alpha),
                  py::arg("alpha_err") = number(r.alpha_error), py::arg("strokes") = r.strokes, py::arg("ok") = r.ok,
                  py::arg("reason") = worded(r.reason, FrontEnd::python));
}

/// `slidespec analyze A B C`: each record file analysed in order, as ([(result or None when it
/// was refused, its row)], interrupted): a KeyboardInterrupt ends the list early, with every
/// record finished before it. A plan no record satisfies is refused before any file is read.
py::tuple analyze_files(const std::vector<std::string>& paths, const py::dict& format, const py::dict& plan) {
  const RecordFormat f = format_of(format);
  const AnalysisPlan p = plan_of(plan, f.window.has_value());
  check_band(p.request);
  check_plan(p, f.machine_stiffness);
  py::list out;
  for (const std::string& path : paths) {
    try {
      const RecordOfMany one = interruptible([&](const std::atomic<bool>* stop) {
        AnalysisPlan heard = p;
        heard.request.stop = stop;
        return analyze_one_of_many(path, f, heard);
      });
      const py::object result =
          one.report ? py::object(analysis_result(*one.report, path, p.compare_case)) : py::none();
      out.append(py::make_tuple(result, row_dict(one.row)));
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_KeyboardInterrupt)) throw;
      return py::make_tuple(out, true);
    }
  }
  return py::make_tuple(out, false);
}

py::dict landmarks_dict(const std::string& case_name, const Overrides& overrides) {
  py::dict d;
  for (const Landmark& mark : shown_landmarks(build(case_name, overrides), LandmarkOutput::python))
    std::visit([&](const auto& value) { d[mark.row->key] = value; }, mark.value);
  return d;
}

const char* shown_name(LandmarkShown shown) {
  return shown == LandmarkShown::always ? "always" : shown == LandmarkShown::with_spring ? "with_spring" : "never";
}

}  // namespace

namespace {

/// The Python functions' keyword defaults, from the structs the command line starts from.
void bind_defaults(py::module_& m) {
  const RunRequest run_default{};
  py::dict run_defaults;
  run_defaults["omega_min"] = run_default.omega_min;
  run_defaults["omega_max"] = run_default.omega_max;
  run_defaults["points"] = run_default.points_per_decade;
  run_defaults["precision"] = run_default.precision;
  run_defaults["seed"] = run_default.seed;
  m.attr("run_defaults") = run_defaults;
  const SensorRequest sensor_default{};
  py::dict sensor_defaults;
  sensor_defaults["sample_interval"] = sensor_default.sample_interval;
  sensor_defaults["duration"] = sensor_default.duration;
  sensor_defaults["resolution"] = sensor_default.resolution;
  sensor_defaults["sensor_noise"] = sensor_default.sensor_noise;
  sensor_defaults["seed"] = sensor_default.seed;
  m.attr("sensor_defaults") = sensor_defaults;
}

/// Cases and parameters.
void bind_parameters(py::module_& m) {
  m.def(
      "cases",
      [] {
        std::vector<std::tuple<std::string, std::string, Overrides>> out;
        for (const Case& c : cases()) out.emplace_back(c.name, c.description, c.changes);
        return out;
      },
      "The named cases: (name, description, [(key, value) changed from the reference]).");
  m.def("parameter_keys", &parameter_keys, "Every settable parameter key (KEY_l for level l).");
  m.def(
      "parameter_table",
      [] {
        py::list table;
        for (const ParameterInfo& info : parameter_table())
          table.append(py::dict(py::arg("key") = info.key, py::arg("kind") = info.kind, py::arg("unit") = info.unit,
                                py::arg("symbol") = info.symbol, py::arg("allowed") = info.allowed,
                                py::arg("per_level") = info.per_level, py::arg("doc") = info.doc,
                                py::arg("words") = info.words, py::arg("reference") = info.reference));
        return table;
      },
      "The model's parameters, one dict each: key, kind (count|real|word|levels), unit, symbol (the figures' "
      "markup: *italic*, _{subscript}), allowed, per_level, doc, words, reference.");
  m.def(
      "describe",
      [](const std::string& case_name, const Overrides& overrides) { return describe(build(case_name, overrides)); },
      "Every (key, value text) of a case with overrides; ValueError names a bad key.");
}

/// As `slidespec theory` computes C_x, or C_x2 with --order 2, at `omega` [rad/s].
Array theory_values(const std::string& case_name, const Overrides& overrides, const Array& omega, int order) {
  const Parameters p = build(case_name, overrides);
  if (order != 1 && order != 2) throw InputError("order: need 1 or 2");
  const std::function<double(double)> second =
      order == 2 ? theory_beyond_first_order(p).C_x : std::function<double(double)>();
  const std::vector<double> omegas = to_vector(omega);
  check_theory_omegas(p, omegas);
  // In chunks of about a tenth of a second, between which Ctrl-C is heard.
  constexpr std::size_t kChunk = 10000;
  std::vector<double> values;
  values.reserve(omegas.size());
  for (std::size_t first = 0; first < omegas.size(); first += kChunk) {
    const std::vector<double> chunk(
        omegas.begin() + static_cast<std::ptrdiff_t>(first),
        omegas.begin() + static_cast<std::ptrdiff_t>(std::min(first + kChunk, omegas.size())));
    {
      py::gil_scoped_release release;
      if (second) {
        for (double frequency : chunk) values.push_back(second(frequency));
      } else {
        const std::vector<double> part = exact_spectrum(p, chunk);
        values.insert(values.end(), part.begin(), part.end());
      }
    }
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
  return to_array(values);
}

/// The theory of a parameter set.
void bind_theory(py::module_& m) {
  m.def("landmarks", &landmarks_dict, "The theory's landmarks of a parameter set, SI units.");
  m.def(
      "landmark_table",
      [] {
        py::list table;
        for (const LandmarkRow& row : landmark_table())
          table.append(py::dict(py::arg("key") = row.key, py::arg("unit") = row.unit,
                                py::arg("tsv") = shown_name(row.tsv), py::arg("json") = shown_name(row.json),
                                py::arg("python") = shown_name(row.python), py::arg("doc") = row.doc));
        return table;
      },
      "The landmarks, one dict each: key, unit, when the table, the JSON and Python show it, doc.");
  m.def(
      "log_spaced_omegas",
      [](double low, double high, int per_decade) { return to_array(log_spaced_omegas(low, high, per_decade)); },
      "Log-spaced omegas [rad/s], per_decade a decade, both ends included.");
  m.def("theory", &theory_values,
        "The exact first-order C_x (order 1) or the theory beyond it that theory_kind names (order 2) [m^2 s] at "
        "omegas [rad/s], without the GIL.");
  m.def(
      "long_time_motion",
      [](const std::string& case_name, const Overrides& overrides, const std::string& theory) {
        const Parameters p = build(case_name, overrides);
        const MotionTheory kind =
            theory == "first_order"    ? MotionTheory::first_order
            : theory == "second_order" ? MotionTheory::second_order
            : theory == "quasi_static"
                ? MotionTheory::quasi_static
                : throw InputError("theory: '" + theory + "' is not first_order, second_order or quasi_static");
        const LongTimeMotion motion = long_time_motion(p, kind);
        return py::dict(py::arg("mean_speed") = motion.mean_speed, py::arg("diffusion") = motion.diffusion);
      },
      "The block's mean speed [m/s] and diffusion constant [m^2/s] in a theory (docs/model.md section 7).");
  m.def(
      "eq1",
      [](const std::string& case_name, const Overrides& overrides, const Array& omega) {
        const Parameters p = build(case_name, overrides);
        const std::vector<double> omegas = to_vector(omega);
        check_theory_omegas(p, omegas);
        std::vector<double> values;
        for (double w : omegas) values.push_back(eq1_asymptote(p, w));
        return to_array(values);
      },
      "The paper's Eq. (1) asymptote [m^2 s] at omegas [rad/s].");
}

/// Runs, advanced on their own thread.
void bind_run(py::module_& m) {
  py::class_<Run>(m, "Run", "A run advanced on its own thread; Python stays on the caller's.")
      .def("start", &Run::start, "Starts the run with threads (0 = all cores) and a SIMD path name.")
      .def("wait", &Run::wait, "Waits up to seconds without the GIL; True once the run has ended.")
      .def("progress", &Run::progress, "The latest (fraction, message) the run reported.")
      .def("stop", &Run::stop, "Asks the run to end at its next block of steps.")
      .def("join", &Run::join, "Waits for the run's thread; True when the run reached its end.")
      .def("result", &Run::result,
           "(fields, columns): PREFIX.json's fields but its points, and the points as {name: numpy array}.")
      .def("save", &Run::save, "The run's saved state (bytes), for load_run.")
      .def("finished", &Run::finished, "True when every sub-band is done.");
  m.def("new_run", &new_run, "A run of a case with overrides and a request dict; ValueError before any work.");
  m.def(
      "load_run", [](const py::bytes& state) { return std::make_unique<Run>(RunSession::load(state)); },
      "A run from its saved state (Run.save), to continue.");
}

/// Measured records: their analysis, and synthetic ones.
void bind_analysis(py::module_& m) {
  m.def("analyze", &analyze_record,
        "`slidespec analyze` of a record: (PREFIX.json's fields but its points, the points as {name: numpy "
        "array}, [(kind, topic, text) of each warning]).");
  m.def("analyze_files", &analyze_files,
        "`slidespec analyze A B C`: per file, (analyze's triple, or None when the file was refused; its row of "
        "the combined table as a dict).");
  m.def(
      "synthesize",
      [](const std::string& case_name, const Overrides& overrides, const py::dict& sensor) {
        SensorRequest s;
        s.sample_interval = sensor["sample_interval"].cast<double>();
        s.duration = sensor["duration"].cast<double>();
        s.resolution = sensor["resolution"].cast<double>();
        s.sensor_noise = sensor["sensor_noise"].cast<double>();
        s.seed = sensor["seed"].cast<std::uint64_t>();
        s.load_point = sensor["load_point"].cast<bool>();
        for (const auto& [speed_factor, duration] : sensor["program"].cast<std::vector<std::pair<double, double>>>())
          s.program.push_back({speed_factor, duration});
        const Parameters p = build(case_name, overrides);
        if (!sensor["strokes"].is_none())
          s.program = stroke_program(sensor["strokes"].cast<double>(), sensor["stroke_length"].cast<double>(), p.v,
                                     sensor["dwell"].cast<double>());
        Record record;
        {
          py::gil_scoped_release release;
          record = synthesize_record(p, s);
        }
        return py::make_tuple(record.dt, record.start_time, to_array(record.displacement), to_array(record.force));
      },
      "A synthetic sensor record of a case: (dt [s], t0 [s], x [m], F [N], empty but for a load point's record).");
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "slidespec's core library (use the slidespec package, not this module)";
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const FileError& e) {  // before InputError, which it is
      PyErr_SetString(PyExc_OSError, worded(e.what(), FrontEnd::python).c_str());
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, worded(e.what(), FrontEnd::python).c_str());
    } catch (const io::WriteError& e) {
      PyErr_SetString(PyExc_OSError, worded(e.what(), FrontEnd::python).c_str());
    } catch (const std::bad_alloc&) {
      PyErr_SetString(PyExc_MemoryError, "out of memory: the work needs more than this machine has");
    }
  });
  m.attr("version") = SLIDESPEC_VERSION;

  bind_defaults(m);
  bind_parameters(m);
  bind_theory(m);
  bind_run(m);
  bind_analysis(m);
}
