// slidespec._core: the core library for Python. It converts arrays, exceptions and the
// GIL and nothing else; the interface users meet is python/slidespec/__init__.py.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <new>
#include <optional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/tables.hpp"
#include "analysis/report.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"
#include "slidespec/theory.hpp"

namespace py = pybind11;
using namespace slidespec;

namespace {

using Overrides = std::vector<std::pair<std::string, std::string>>;
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

Parameters build(const std::string& case_name, const Overrides& overrides) {
  ParameterBuilder builder(case_name);
  for (const auto& [key, value] : overrides) builder.set(key, value);
  return builder.build();
}

Array to_array(const std::vector<double>& values) {
  Array out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

std::vector<double> to_vector(const Array& values) {
  return std::vector<double>(values.data(), values.data() + values.size());
}

/// The command line's options in a library message, as the Python keywords that set the same
/// thing ("--omega-max" -> "omega_max", "--column" -> "x"): the one place Python's messages
/// are worded for Python.
std::string python_names(const std::string& message) {
  // Options named as their keyword with '_' for '-', and those named otherwise; the rest
  // (--out, --resume, ...) Python does not have, and they are left as they are.
  static const std::vector<std::string> same = {"omega-min",
                                                "omega-max",
                                                "points",
                                                "precision",
                                                "duration",
                                                "realizations",
                                                "seed",
                                                "control-variate",
                                                "threads",
                                                "simd",
                                                "order",
                                                "dt",
                                                "units",
                                                "window",
                                                "resample",
                                                "time-tolerance",
                                                "observable",
                                                "force-units",
                                                "contact-area",
                                                "normal-force",
                                                "machine-stiffness",
                                                "resolution",
                                                "sensor-noise",
                                                "estimator",
                                                "fit",
                                                "fit-band",
                                                "fit-slope",
                                                "theory-order",
                                                "sample-interval"};
  static const std::vector<std::pair<std::string, std::string>> renamed = {{"column", "x"},
                                                                           {"time-column", "t"},
                                                                           {"force-column", "force"},
                                                                           {"compare-case", "compare"},
                                                                           {"normal-stress-column", "normal_stress"},
                                                                           {"case", "the case"},
                                                                           {"set", "Parameters(KEY=VALUE)"},
                                                                           {"params", "Parameters(KEY=VALUE)"}};
  const auto keyword = [](const std::string& option) -> std::optional<std::string> {
    if (std::find(same.begin(), same.end(), option) != same.end()) {
      std::string name = option;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    }
    const auto other = std::find_if(renamed.begin(), renamed.end(), [&](const auto& r) { return r.first == option; });
    return other == renamed.end() ? std::nullopt : std::optional<std::string>(other->second);
  };
  // Options given with their value's form, in the words of a Python call.
  static const std::vector<std::pair<std::string, std::string>> phrases = {
      {"--window T0:T1", "window=(T0, T1)"}, {"--resample DT", "resample=DT"}, {"--segments", "the field segments"}};
  std::string text = message;
  for (const auto& [option, call] : phrases)
    for (std::size_t found = text.find(option); found != std::string::npos;
         found = text.find(option, found + call.size()))
      text.replace(found, option.size(), call);
  std::string out;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t dashes = text.find("--", at);
    const bool starts_word =
        dashes != std::string::npos && (dashes == 0 || !std::isalnum(static_cast<unsigned char>(text[dashes - 1])));
    if (dashes == std::string::npos) {
      out += text.substr(at);
      break;
    }
    std::size_t end = dashes + 2;
    while (end < text.size() &&
           (std::isalnum(static_cast<unsigned char>(text[end])) ||
            (text[end] == '-' && end + 1 < text.size() && std::isalpha(static_cast<unsigned char>(text[end + 1])))))
      ++end;
    const std::string option = text.substr(dashes + 2, end - dashes - 2);
    const std::optional<std::string> known = starts_word ? keyword(option) : std::nullopt;
    out += text.substr(at, dashes - at);
    if (!known) {
      out += text.substr(dashes, end - dashes);
    } else if (option == "set" && end + 1 < text.size() && text[end] == ' ' &&
               text.find('=', end) < text.find_first_of(" ,;)", end + 1)) {
      ++end;  // "--set k_drive=K" reads as the keyword "k_drive=K"
    } else {
      out += *known;
    }
    at = end;
  }
  return out;
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

  /// The result as `slidespec run` writes PREFIX.json.
  std::string result_json() const {
    py::gil_scoped_release release;
    return io::run_json(session_.parameters(), session_.case_name(), session_.request(), session_.result());
  }

  /// The points' doubles as computed, to check that the JSON form carries them exactly.
  py::dict raw_points() const {
    const RunResult result = session_.result();
    std::vector<double> omega, C_x, stderr_, theory, theory2;
    for (const RunPoint& p : result.points) {
      omega.push_back(p.omega);
      C_x.push_back(p.C_x);
      stderr_.push_back(p.standard_error);
      theory.push_back(p.theory);
      theory2.push_back(p.theory2);
    }
    py::dict out;
    out["omega"] = to_array(omega);
    out["C_x"] = to_array(C_x);
    out["stderr"] = to_array(stderr_);
    out["theory"] = to_array(theory);
    out["theory2"] = to_array(theory2);
    return out;
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

/// A record's spectrum (analyze_record), kept for the fits that read it.
class Spectrum {
 public:
  Spectrum(const Array& time, const Array& x, const py::dict& format, const py::dict& request) {
    RecordFormat f;
    f.dt = format["dt"].cast<double>();
    f.unit = parse_length_unit(format["units"].cast<std::string>());
    f.time_tolerance = format["time_tolerance"].cast<double>();
    if (!format["window"].is_none()) {
      const auto window = format["window"].cast<std::pair<double, double>>();
      if (!(window.second > window.first)) throw InputError("window: need (t0, t1) with t0 < t1 [s]");
      f.window = window;
    }
    const std::string resample = format["resample"].cast<std::string>();
    if (resample == "auto")
      f.resample = Resampling::automatic;
    else if (resample == "off")
      f.resample = Resampling::off;
    else if (resample == "median")
      f.resample = Resampling::median;
    else {
      f.resample = Resampling::interval;
      f.resample_interval = format["resample_interval"].cast<double>();
      if (!(f.resample_interval > 0)) throw InputError("resample: 'auto', 'off', 'median' or an interval > 0 [s]");
    }
    AnalysisRequest r;
    r.omega_min = request["omega_min"].cast<double>();
    r.omega_max = request["omega_max"].cast<double>();
    r.points_per_decade = request["points_per_decade"].cast<int>();
    r.resolution = request["resolution"].cast<double>();
    r.sensor_noise = request["sensor_noise"].cast<double>();
    r.estimator = parse_estimator(request["estimator"].cast<std::string>());
    // Channels as named columns, read as a file with that header is (units from the format).
    f.observable = parse_observable(format["observable"].cast<std::string>());
    if (!format["force_units"].is_none()) f.force_unit = parse_force_unit(format["force_units"].cast<std::string>());
    f.contact_area = format["contact_area"].cast<double>();
    f.normal_force = format["normal_force"].cast<double>();
    f.machine_stiffness = format["machine_stiffness"].cast<double>();
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
    Record record = record_from_columns(names, columns, f);
    notes_ = record.notes;
    const std::vector<SteadySegment> steady = steady_segments(record);
    const std::optional<Strokes> strokes = f.window ? std::nullopt : find_strokes(steady, record.dt);
    if (!f.window && !strokes) record = longest_steady(record, steady, notes_);
    spectrum_ = strokes ? analyze_strokes(record, *strokes, r, notes_) : analyze_record(record, r);
    spectrum_.segments = steady;
    record_ = std::move(record);
    request_ = r;
  }

  /// The fields of `slidespec analyze`'s JSON (the spectrum's from the same writer).
  py::dict to_dict() const {
    const RecordSpectrum& s = spectrum_;
    nlohmann::ordered_json doc;
    doc["slidespec_version"] = SLIDESPEC_VERSION;
    doc["record"] = {{"samples", s.samples}, {"dt", s.dt}, {"duration", s.duration}};
    doc.update(detail::spectrum_json(s));
    doc["resolution"] = request_.resolution;
    doc["sensor_noise"] = request_.sensor_noise;
    doc["notes"] = nlohmann::ordered_json::array();
    for (const std::string& note : notes_) doc["notes"].push_back(python_names(note));
    return as_dict(doc);
  }

  static py::dict as_dict(const nlohmann::ordered_json& doc) {
    return py::module_::import("json").attr("loads")(doc.dump()).cast<py::dict>();
  }

  py::dict slope(double low, double high) const {
    const SlopeFit f = fit_slope(spectrum_, low, high);
    return as_dict(detail::slope_fit_json(f, detail::judge_chi2(f.chi2_per_dof, f.points - 2)));
  }

  py::dict power_law(double low, double high) const {
    PowerLawFit f;
    {
      py::gil_scoped_release release;
      f = fit_power_law(spectrum_, low, high);
    }
    py::dict d = as_dict(detail::power_law_json(f, detail::judge_power_law(f)));
    d["fit"] = to_array(f.model);
    d["residual"] = to_array(f.residuals);
    return d;
  }

  /// The compared case on the record's terms (its measured v, a spring for a machine).
  Overrides record_terms(const std::string& case_name, const Overrides& overrides) const {
    build(case_name, overrides);  // refused before any change
    std::vector<std::string> assignments, notes;
    for (const auto& [key, value] : overrides) assignments.push_back(key + "=" + value);
    Overrides terms;
    for (const std::string& assignment :
         slidespec::record_terms(assignments, measured_speed(record_, spectrum_), record_.machine_stiffness, notes)) {
      const auto equals = assignment.find('=');
      terms.emplace_back(assignment.substr(0, equals), assignment.substr(equals + 1));
    }
    return terms;
  }

  py::dict model_fit(const std::string& case_name, const Overrides& overrides, const std::vector<std::string>& names,
                     double low, double high, int theory_order) const {
    const Parameters p = build(case_name, overrides);
    ModelFit f;
    {
      py::gil_scoped_release release;
      f = fit_model(spectrum_, p, names, low, high, order_of(theory_order));
    }
    py::dict d = as_dict(detail::model_fit_json(f, detail::judge_model(f)));
    d["fit"] = to_array(f.model);
    d["residual"] = to_array(f.residuals);
    return d;
  }

  py::dict alpha(const std::string& case_name, const Overrides& overrides, double low, double high,
                 int theory_order) const {
    const Parameters p = build(case_name, overrides);
    AlphaFit f;
    {
      py::gil_scoped_release release;
      f = fit_alpha(spectrum_, p, low, high, order_of(theory_order));
    }
    Parameters fitted = p;
    fitted.alpha = f.alpha;
    return as_dict(detail::alpha_fit_json(f, detail::judge_alpha(f, fitted)));
  }

  int model_order_of(const std::string& case_name, const Overrides& overrides, int theory_order) const {
    return model_order(build(case_name, overrides), order_of(theory_order));
  }

  std::pair<double, double> alpha_band(const std::string& case_name, const Overrides& overrides) const {
    return default_alpha_band(spectrum_, build(case_name, overrides));
  }

  Array model(const std::string& case_name, const Overrides& overrides, int theory_order) const {
    const Parameters p = build(case_name, overrides);
    std::vector<double> values;
    {
      py::gil_scoped_release release;
      values = model_spectrum(spectrum_, p, order_of(theory_order));
    }
    return to_array(values);
  }

 private:
  static ModelOrder order_of(int theory_order) {
    if (theory_order != 1 && theory_order != 2) throw InputError("theory_order: 1 or 2");
    return theory_order == 2 ? ModelOrder::best : ModelOrder::first;
  }

  std::vector<std::string> notes_;
  Record record_;  // the samples analyzed: their channels give the compared case's terms
  RecordSpectrum spectrum_;
  AnalysisRequest request_;
};

py::dict landmarks_dict(const std::string& case_name, const Overrides& overrides) {
  const Parameters p = build(case_name, overrides);
  const Landmarks l = landmarks(p);
  py::dict d;
  d["renewal_rate"] = l.renewal_rate;
  d["omega_c"] = l.omega_c;
  d["diffusion_D"] = l.diffusion;
  d["eq1_prefactor"] = l.eq1_prefactor;
  d["coupling_eps"] = l.coupling_eps;
  d["forces_can_stall"] = l.forces_can_stall;
  const TheoryChoice holds = best_theory(p);
  // Under a spring best_theory names the first order exactly where it holds (its limits reach
  // far beyond the constant force's); otherwise the first order's own eps limit.
  d["outside_first_order"] =
      p.drive == Drive::spring
          ? holds.kind != TheoryKind::first_order
          : l.forces_can_stall ||
                l.coupling_eps > (p.renewal == Renewal::poisson ? kFirstOrderPoissonEpsMax : kFirstOrderPeriodicEpsMax);
  d["theory_kind"] = theory_kind_name(holds.kind);
  d["theory_kind_note"] = holds.reason;
  d["omega_resonance"] = l.omega_resonance;
  if (p.drive == Drive::spring) {
    d["omega_s"] = l.omega_s;
    d["C_x_zero"] = spring_low_frequency_limit(p);
  }
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "slidespec's core library (use the slidespec package, not this module)";
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const FileError& e) {  // before InputError, which it is
      PyErr_SetString(PyExc_OSError, python_names(e.what()).c_str());
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, python_names(e.what()).c_str());
    } catch (const io::WriteError& e) {
      PyErr_SetString(PyExc_OSError, python_names(e.what()).c_str());
    } catch (const std::bad_alloc&) {
      PyErr_SetString(PyExc_MemoryError, "out of memory: the work needs more than this machine has");
    }
  });
  m.attr("version") = SLIDESPEC_VERSION;
  m.attr("white_floor_shortfall") = kWhiteFloorShortfall;
  m.attr("implausible_speed") = kImplausibleSpeed;

  // The Python functions' keyword defaults, from the structs the command line starts from.
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
                                py::arg("allowed") = info.allowed, py::arg("per_level") = info.per_level,
                                py::arg("doc") = info.doc, py::arg("words") = info.words,
                                py::arg("reference") = info.reference));
        return table;
      },
      "The model's parameters, one dict each: key, kind (count|real|word|levels), unit, allowed, per_level, doc, "
      "words, reference.");
  m.def(
      "describe",
      [](const std::string& case_name, const Overrides& overrides) { return describe(build(case_name, overrides)); },
      "Every (key, value text) of a case with overrides; ValueError names a bad key.");
  m.def("parse_fit_parameters", &parse_fit_parameters,
        "The model parameters a --fit list names, checked as the command line checks them.");
  m.def("landmarks", &landmarks_dict, "The theory's landmarks of a parameter set, SI units.");
  m.def(
      "log_spaced_omegas",
      [](double low, double high, int per_decade) { return to_array(log_spaced_omegas(low, high, per_decade)); },
      "Log-spaced omegas [rad/s], per_decade a decade, both ends included.");
  m.def(
      "theory",
      [](const std::string& case_name, const Overrides& overrides, const Array& omega, int order) {
        const Parameters p = build(case_name, overrides);
        if (order != 1 && order != 2) throw InputError("order: need 1 or 2");
        // As `slidespec theory --order 2` computes C_x2.
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
      },
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

  py::class_<Run>(m, "Run", "A run advanced on its own thread; Python stays on the caller's.")
      .def("start", &Run::start, "Starts the run with threads (0 = all cores) and a SIMD path name.")
      .def("wait", &Run::wait, "Waits up to seconds without the GIL; True once the run has ended.")
      .def("progress", &Run::progress, "The latest (fraction, message) the run reported.")
      .def("stop", &Run::stop, "Asks the run to end at its next block of steps.")
      .def("join", &Run::join, "Waits for the run's thread; True when the run reached its end.")
      .def("result_json", &Run::result_json, "The result as `slidespec run` writes PREFIX.json.")
      .def("raw_points", &Run::raw_points, "omega, C_x, stderr, theory as computed (not through JSON).")
      .def("save", &Run::save, "The run's saved state (bytes), for load_run.")
      .def("finished", &Run::finished, "True when every sub-band is done.");
  m.def("new_run", &new_run, "A run of a case with overrides and a request dict; ValueError before any work.");
  m.def(
      "load_run", [](const py::bytes& state) { return std::make_unique<Run>(RunSession::load(state)); },
      "A run from its saved state (Run.save), to continue.");

  py::class_<Spectrum>(m, "Spectrum", "A record's spectrum: x in units at times t [s] (or every dt).")
      .def(py::init<const Array&, const Array&, const py::dict&, const py::dict&>())
      .def("default_alpha_band", &Spectrum::alpha_band, "The alpha fit's default band [rad/s].")
      .def("to_dict", &Spectrum::to_dict, "The fields of `slidespec analyze`'s JSON.")
      .def("fit_slope", &Spectrum::slope, "C_x ~ omega^slope over [low, high] rad/s.")
      .def("fit_alpha", &Spectrum::alpha, "alpha of a case fitted over [low, high] rad/s.")
      .def("fit_power_law", &Spectrum::power_law, "A (omega/pivot)^s + floor fitted over [low, high] rad/s.")
      .def("fit_model", &Spectrum::model_fit, "Model parameters fitted jointly over [low, high] rad/s.")
      .def("record_terms", &Spectrum::record_terms,
           "A case's overrides with the record's measured v and, for a machine, its spring drive.")
      .def("model", &Spectrum::model, "A case's spectrum seen through this estimator [m^2 s].")
      .def("model_order", &Spectrum::model_order_of, "The theory order a comparison uses (1 or 2).");
  m.def(
      "synthesize",
      [](const std::string& case_name, const Overrides& overrides, const py::dict& sensor) {
        SensorRequest s;
        s.sample_interval = sensor["sample_interval"].cast<double>();
        s.duration = sensor["duration"].cast<double>();
        s.resolution = sensor["resolution"].cast<double>();
        s.sensor_noise = sensor["sensor_noise"].cast<double>();
        s.seed = sensor["seed"].cast<std::uint64_t>();
        const Parameters p = build(case_name, overrides);
        Record record;
        {
          py::gil_scoped_release release;
          record = synthesize_record(p, s);
        }
        return py::make_tuple(record.dt, record.start_time, to_array(record.displacement));
      },
      "A synthetic sensor record of a case: (dt [s], t0 [s], x [m]).");
}
