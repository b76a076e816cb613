// The compared case on a record's terms and the joint fit of its parameters
// (docs/analysis.md, "Comparing and fitting a model").
#include <algorithm>
#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>

#include "analysis/names.hpp"
#include "analysis/report.hpp"
#include "util/numbers.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/input_error.hpp"
#include "slidespec/parameters.hpp"
#include "slidespec/theory.hpp"
#include "util/suggest.hpp"

namespace slidespec {

namespace {

using detail::key_of;
using detail::sets;

using detail::short_number;

double& field(Parameters& p, const std::string& name) {
  if (name == "alpha") return p.alpha;
  if (name == "a") return p.a;
  if (name == "k0") return p.k0;
  return p.k_drive;
}
double value_of(Parameters p, const std::string& name) { return field(p, name); }

/// "alpha, a, k0": names as a sentence lists them.
std::string listed(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  return list;
}

// The iteration stops when chi2 changes by less than this share.
constexpr double kSettled = 1e-9;
constexpr int kMaxSteps = 60;
// Central differences in log theta: well above rounding, well below any feature's width.
constexpr double kLogStep = 1e-4;
// A parameter whose relative error exceeds this is reported as not determined.
constexpr double kUndeterminedRelativeError = 0.5;
// How far a fitted parameter may go from its start, either way [factor].
constexpr double kSearchRange = 1e4;
// Two parameters correlated beyond this are determined only in a combination.
constexpr double kDegenerateCorrelation = 0.98;

}  // namespace

std::vector<std::string> record_terms(const std::vector<std::string>& overrides, double measured_speed,
                                      double machine_stiffness, std::vector<std::string>& notes) {
  std::vector<std::string> terms = overrides;
  if (measured_speed > 0 && !sets(overrides, "v") && !sets(overrides, "eta1")) {
    terms.push_back("v=" + util::format_number(measured_speed));
    notes.push_back("the model's v is the record's measured mean speed, " + short_number(measured_speed) +
                    " m/s ({set} v=... to change it)");
  }
  // A k_drive given with --set is kept (docs/analysis.md): the spring is the machine's still.
  if (machine_stiffness > 0 && !sets(overrides, "drive")) {
    terms.insert(terms.begin(), "drive=spring");
    if (!sets(overrides, "k_drive")) terms.push_back("k_drive=" + util::format_number(machine_stiffness));
    notes.push_back("the model is driven as the machine drives the record: drive = spring, k_drive = " +
                    (sets(overrides, "k_drive") ? std::string("as {set} gives it")
                                                : "the machine stiffness " + short_number(machine_stiffness) + " N/m"));
  }
  return terms;
}

Parameters record_model(const std::string& case_name, const std::vector<std::string>& overrides, double measured_speed,
                        double machine_stiffness, std::vector<std::string>& notes) {
  return build_case(case_name, record_terms(overrides, measured_speed, machine_stiffness, notes));
}

double measured_speed(const Record& record, const RecordSpectrum& s) {
  if (s.observable != Observable::force) return s.sliding.v;
  if (record.displacement.empty()) return 0;
  Record displacement = record;
  displacement.observable = Observable::displacement;
  return fit_sliding(displacement).v;
}

std::vector<std::string> parse_fit_parameters(const std::string& list) {
  std::vector<std::string> names;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    const auto& known = fittable_parameters();
    if (std::find(known.begin(), known.end(), name) == known.end())
      throw InputError("{fit}: '" + name + "' is not a model parameter a fit can vary; known: " + listed(known) +
                       util::did_you_mean(name, known) + " (or power-law)");
    if (std::find(names.begin(), names.end(), name) != names.end())
      throw InputError("{fit}: '" + name + "' is named twice");
    names.push_back(name);
    start = comma + 1;
  }
  return names;
}

namespace {

/// A joint fit's data and model: the points inside the band, what each sees of a white floor,
/// each point's error, and the theory at theta = (log model parameters, floor).
struct FitProblem {
  FitProblem(const RecordSpectrum& s, const Parameters& p, const std::vector<std::string>& n, ModelOrder o)
      : spectrum(s), start(p), names(n), order(o) {}
  const RecordSpectrum& spectrum;
  const Parameters& start;
  const std::vector<std::string>& names;
  ModelOrder order;
  int model_count = 0;
  bool floor_given = false;
  bool floor_fitted = false;  // the floor enters theta linearly, after the model parameters
  std::vector<std::size_t> inside;
  std::vector<double> white;  // the white floor as each point sees it: a constant through its bins
  std::vector<double> sigma;

  int points() const { return static_cast<int>(inside.size()); }
  int unknowns() const { return model_count + (floor_fitted ? 1 : 0); }
  Parameters parameters_at(const Eigen::VectorXd& u) const {
    Parameters p = start;
    for (int i = 0; i < model_count; ++i) field(p, names[std::size_t(i)]) = std::exp(u(i));
    return p;
  }
  std::vector<double> theory_at(const Eigen::VectorXd& u) const {
    return model_spectrum(spectrum, parameters_at(u), order);
  }
  double floor_at(const Eigen::VectorXd& theta, std::size_t k) const {
    return floor_fitted ? theta(model_count) * white[k] : floor_given ? spectrum.points[k].noise_floor : 0;
  }
  Eigen::VectorXd residuals_at(const Eigen::VectorXd& theta, const std::vector<double>& theory) const {
    Eigen::VectorXd r(points());
    for (int i = 0; i < points(); ++i) {
      const std::size_t k = inside[std::size_t(i)];
      r(i) = (spectrum.points[k].C_x - theory[k] - floor_at(theta, k)) / sigma[k];
    }
    return r;
  }
  Eigen::MatrixXd jacobian_at(const Eigen::VectorXd& theta) const {
    Eigen::MatrixXd j(points(), unknowns());
    for (int m = 0; m < model_count; ++m) {
      Eigen::VectorXd up = theta, down = theta;
      up(m) += kLogStep, down(m) -= kLogStep;
      const std::vector<double> high = theory_at(up), low = theory_at(down);
      for (int i = 0; i < points(); ++i) {
        const std::size_t k = inside[std::size_t(i)];
        j(i, m) = (high[k] - low[k]) / (2 * kLogStep) / sigma[k];
      }
    }
    if (floor_fitted)
      for (int i = 0; i < points(); ++i)
        j(i, model_count) = white[inside[std::size_t(i)]] / sigma[inside[std::size_t(i)]];
    return j;
  }
};

/// Refuses a band that is none (saying why when it is the default, the usable band) and a
/// start a logarithm cannot begin from.
void check_model_fit(const RecordSpectrum& spectrum, const Parameters& start, const std::vector<std::string>& names,
                     double omega_low, double omega_high) {
  if (!(omega_low > 0 && omega_high > omega_low)) {
    // The default band, the usable one, is empty: say why, not that a band given is malformed.
    const bool usable_band = omega_low == spectrum.usable_low && omega_high == spectrum.usable_high;
    if (usable_band && !(spectrum.usable_high > spectrum.usable_low)) {
      std::string fitted;
      for (const std::string& name : names) fitted += (fitted.empty() ? "" : ",") + name;
      throw InputError(detail::no_usable_band_for_fit(fitted));
    }
    throw InputError("{fit_band}: need 0 < LO < HI in rad/s");
  }
  for (const std::string& name : names)
    if (!(value_of(start, name) > 0))
      throw InputError("{fit} " + name + ": the compared case's " + name + " must be > 0 to start from");
}

/// One Levenberg-Marquardt descent from theta at the current weights; true when it settled.
bool descend(const FitProblem& f, Eigen::VectorXd& theta, std::vector<double>& theory, double& chi2,
             const Eigen::VectorXd& lowest, const Eigen::VectorXd& highest) {
  double lambda = 1e-3;
  chi2 = f.residuals_at(theta, theory).squaredNorm();
  bool converged = false;
  for (int step = 0; step < kMaxSteps && !converged; ++step) {
    const Eigen::MatrixXd j = f.jacobian_at(theta);
    const Eigen::VectorXd r = f.residuals_at(theta, theory);
    const Eigen::MatrixXd jtj = j.transpose() * j;
    const Eigen::VectorXd gradient = j.transpose() * r;
    for (int tries = 0; tries < 12; ++tries) {
      Eigen::MatrixXd damped = jtj;
      damped.diagonal() += lambda * jtj.diagonal();
      Eigen::VectorXd trial = theta + damped.ldlt().solve(gradient);
      if (f.floor_fitted && trial(f.model_count) < 0) trial(f.model_count) = 0;  // a floor below zero is none
      for (int i = 0; i < f.model_count; ++i) trial(i) = std::clamp(trial(i), lowest(i), highest(i));
      std::vector<double> trial_theory;
      double trial_chi2 = std::numeric_limits<double>::infinity();
      try {
        trial_theory = f.theory_at(trial);
        trial_chi2 = f.residuals_at(trial, trial_theory).squaredNorm();
      } catch (const InputError&) {  // outside the parameters' ranges or the theory's
      }
      if (std::isfinite(trial_chi2) && trial_chi2 <= chi2) {
        converged = chi2 - trial_chi2 <= kSettled * chi2;
        theta = trial, theory = std::move(trial_theory), chi2 = trial_chi2;
        lambda = std::max(lambda / 10, 1e-12);
        break;
      }
      lambda *= 10;
      if (tries == 11) converged = true;  // no step lowers chi2: at the minimum
    }
  }
  return converged;
}

/// The fitted values, their covariance (of the parameters, from that of their logarithms),
/// the search's edges reached, and the model and residuals per point.
Eigen::MatrixXd fill_fit(const FitProblem& f, const Eigen::VectorXd& theta, const std::vector<double>& theory,
                         const Eigen::VectorXd& lowest, const Eigen::VectorXd& highest, ModelFit& fit) {
  const int model_count = f.model_count;
  const Eigen::MatrixXd j = f.jacobian_at(theta);
  Eigen::MatrixXd covariance = (j.transpose() * j).inverse() * std::max(1.0, fit.chi2_per_dof);
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(f.unknowns());
  for (int i = 0; i < model_count; ++i) scale(i) = std::exp(theta(i));
  covariance = scale.asDiagonal() * covariance * scale.asDiagonal();
  for (int i = 0; i < model_count; ++i)
    if (theta(i) <= lowest(i) + 1e-9 || theta(i) >= highest(i) - 1e-9)
      fit.at_search_edge.push_back(f.names[std::size_t(i)]);
  fit.fitted = f.parameters_at(theta);
  fit.names = f.names;
  if (f.floor_fitted) fit.names.push_back("floor");
  for (int i = 0; i < f.unknowns(); ++i) {
    fit.values.push_back(i < model_count ? std::exp(theta(i)) : theta(i));
    fit.errors.push_back(std::sqrt(covariance(i, i)));
    fit.covariance.emplace_back();
    for (int k = 0; k < f.unknowns(); ++k) fit.covariance.back().push_back(covariance(i, k));
  }
  if (f.floor_fitted) fit.floor = theta(model_count), fit.floor_error = fit.errors.back();
  if (fit.floor_given) fit.floor = f.spectrum.points[f.inside.front()].noise_floor;
  fit.theory_order = model_order(fit.fitted, f.order);
  const double n = static_cast<double>(fit.fitted.N);
  fit.amplitude = fit.fitted.alpha * fit.fitted.alpha / n;
  const auto alpha_at = std::find(f.names.begin(), f.names.end(), "alpha");
  if (alpha_at != f.names.end())
    fit.amplitude_error = 2 * fit.fitted.alpha / n * fit.errors[std::size_t(alpha_at - f.names.begin())];
  fit.theory = theory;
  fit.model.assign(f.spectrum.points.size(), std::numeric_limits<double>::quiet_NaN());
  fit.residuals = fit.model;
  for (std::size_t k : f.inside) {
    const AnalysisPoint& p = f.spectrum.points[k];
    fit.model[k] = theory[k] + (f.floor_fitted ? fit.floor * f.white[k] : fit.floor_given ? p.noise_floor : 0);
    fit.residuals[k] = (p.C_x - fit.model[k]) / f.sigma[k];
  }
  return covariance;
}

// Why an error is not a number: the curvature of chi2 vanishes along some direction (a
// parameter the band's spectrum does not depend on), and the covariance has no inverse.
constexpr const char* kSingular = "singular covariance: the band does not depend on it";

/// What the band leaves open, in words.
std::string undetermined(const ModelFit& fit, const std::vector<std::string>& names, const Eigen::MatrixXd& covariance,
                         Observable observable) {
  const int model_count = static_cast<int>(names.size());
  std::string said;
  const auto say = [&](const std::string& sentence) { said += (said.empty() ? "" : "; ") + sentence; };
  for (int i = 0; i < model_count; ++i) {
    const std::string why =
        detail::undetermined_parameter(names[std::size_t(i)], fit.values[std::size_t(i)], fit.errors[std::size_t(i)]);
    if (!why.empty()) say(why);
  }
  for (int i = 0; i < model_count; ++i)
    for (int k = i + 1; k < model_count; ++k) {
      const double c = covariance(i, k) / std::sqrt(covariance(i, i) * covariance(k, k));
      if (std::fabs(c) > kDegenerateCorrelation)
        say("only a combination of " + names[std::size_t(i)] + " and " + names[std::size_t(k)] +
            " is determined (correlation " + short_number(c) + ")");
    }
  if (!fit.floor_given && !std::isfinite(fit.floor_error))
    say("the white floor is not determined (" + std::string(kSingular) + ")");
  else if (!fit.floor_given && !(fit.floor > 2 * fit.floor_error))
    say("the white floor is not determined (at most " + short_number(fit.floor + 2 * fit.floor_error) + " " +
        spectrum_unit(observable) + ")");
  say("N and alpha are not separated: the spectrum's level is alpha^2/N = " + short_number(fit.amplitude) +
      (fit.amplitude_error > 0 ? " +- " + short_number(fit.amplitude_error) : std::string()) +
      ", and alpha is alpha at N = " + std::to_string(fit.fitted.N));
  // Every real parameter of the model the fit did not vary, as parameters.def lists them; eta1
  // follows from v and the forces, and k_drive is a spring's.
  std::vector<std::string> held;
  for (const ParameterInfo& row : parameter_table())
    if (row.kind == "real" && row.key != "eta1" && row.shown(fit.fitted) &&
        std::find(names.begin(), names.end(), row.key) == names.end())
      held.push_back(row.key);
  say("held at the case's values, not measured by this fit: " + listed(held));
  return said;
}

}  // namespace

namespace detail {

std::string undetermined_parameter(const std::string& name, double value, double error) {
  if (!std::isfinite(error)) return name + " is not determined by the band (" + kSingular + ")";
  if (error < kUndeterminedRelativeError * value) return "";
  return name + " is not determined by the band (relative error " + short_number(error / value) + ")";
}

}  // namespace detail

ModelFit fit_model(const RecordSpectrum& spectrum, const Parameters& start, const std::vector<std::string>& names,
                   double omega_low, double omega_high, ModelOrder order) {
  check_model_fit(spectrum, start, names, omega_low, omega_high);
  ModelFit fit;
  fit.omega_low = omega_low, fit.omega_high = omega_high;
  fit.floor_given = spectrum.quantization_variance + spectrum.sensor_noise_variance > 0;
  FitProblem f(spectrum, start, names, order);
  f.model_count = static_cast<int>(names.size());
  f.floor_given = fit.floor_given;
  f.floor_fitted = !fit.floor_given;
  for (std::size_t k = 0; k < spectrum.points.size(); ++k) {
    const AnalysisPoint& p = spectrum.points[k];
    if (p.omega >= omega_low && p.omega <= omega_high && !p.leaky && p.C_x > 0) f.inside.push_back(k);
  }
  fit.points = f.points();
  if (fit.points < f.unknowns() + 1)
    throw InputError("{fit}: the band " + util::format_number(omega_low) + " .. " + util::format_number(omega_high) +
                     " rad/s holds " + std::to_string(fit.points) + " usable points, too few for " +
                     std::to_string(f.model_count) + " parameters" + (f.floor_fitted ? " and the floor" : ""));
  f.white = expected_points(spectrum, [](double) { return 1.0; });
  f.sigma.assign(spectrum.points.size(), 0.0);
  for (std::size_t k : f.inside) f.sigma[k] = spectrum.points[k].standard_error;

  Eigen::VectorXd theta(f.unknowns());
  for (int i = 0; i < f.model_count; ++i) theta(i) = std::log(value_of(start, names[std::size_t(i)]));
  if (f.floor_fitted) theta(f.model_count) = 0;
  // The search stays within kSearchRange of the start, both ways: a parameter the band does not
  // bound would otherwise run away along a valley of chi2.
  const Eigen::VectorXd lowest = theta.array() - std::log(kSearchRange);
  const Eigen::VectorXd highest = theta.array() + std::log(kSearchRange);
  std::vector<double> theory = f.theory_at(theta);
  double chi2 = 0;
  for (int reweighting = 0; reweighting < 4; ++reweighting) {
    fit.converged = descend(f, theta, theory, chi2, lowest, highest);
    // Weights from the model's level: a point that happens to be low has a small error bar.
    for (std::size_t k : f.inside) {
      const AnalysisPoint& p = spectrum.points[k];
      f.sigma[k] = p.standard_error / p.C_x * (theory[k] + f.floor_at(theta, k));
    }
  }
  chi2 = f.residuals_at(theta, theory).squaredNorm();
  if (f.floor_fitted && !(theta(f.model_count) > 0)) {
    f.floor_fitted = false;  // held at zero: not a fitted value
    theta.conservativeResize(f.model_count);
  }
  fit.dof = fit.points - f.unknowns();
  fit.chi2_per_dof = fit.dof > 0 ? chi2 / fit.dof : 0;
  const Eigen::MatrixXd covariance = fill_fit(f, theta, theory, lowest, highest, fit);
  fit.undetermined = undetermined(fit, names, covariance, spectrum.observable);
  return fit;
}

}  // namespace slidespec
