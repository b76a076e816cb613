// The analysis document: one JSON writer for `slidespec analyze` and Python's ss.analyze, so
// that both give the same fields under the same names; and the verdicts on each fit.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slidespec/analysis.hpp"
#include "slidespec/options.hpp"

namespace slidespec {

/// The analysis as `slidespec analyze` writes PREFIX.json: the record (`file` when not
/// empty), the spectrum's fields, each fit with its verdict, the compared case (its
/// parameters as `model_parameters` gives them) and every point; notes worded for `reader`.
nlohmann::ordered_json analysis_json(const AnalysisReport& report, const std::string& file,
                                     const std::string& compare_case, const nlohmann::ordered_json& model_parameters,
                                     FrontEnd reader);

}  // namespace slidespec

namespace slidespec::detail {

/// The refusal of a fit over the default band, the usable one, when there is none: "--fit
/// `fit`: no usable band (why); give --fit-band LO HI".
std::string no_usable_band_for_fit(const std::string& fit);

/// The spectrum's own fields: observable, the mean motion (or force) removed, the floor's
/// variance, usable band, estimator, whether it is a spectrum at all (`spectrum_ok`, and
/// `spectrum_failure` saying why not, from `verdict`), and every point (with `theory` per
/// point when given).
nlohmann::ordered_json spectrum_json(const RecordSpectrum& spectrum, const Verdict& verdict,
                                     const std::vector<double>& theory = {});

/// Whether a fit describes the data (docs/analysis.md, "Judging a fit"): chi2/dof within a few
/// of its standard deviations sqrt(2/dof) of 1, at least 3 allowed for correlated neighbours;
/// an alpha or model fit also where a theory holds, and a model fit only once it settled.
Verdict judge_chi2(double chi2_per_dof, int dof);
Verdict judge_alpha(const AlphaFit& fit, const Parameters& fitted);
Verdict judge_model(const ModelFit& fit);
/// A power-law fit also fails where its slope ran to the end of the range searched.
Verdict judge_power_law(const PowerLawFit& fit);
/// Whether the spectrum is one: not where a point holds inf or nan (a sampling interval or
/// stiffness beyond a double's range), nor where it is 0 at every point (a constant record,
/// or values below a double's resolution): no fluctuation was measured there.
Verdict judge_spectrum(const RecordSpectrum& spectrum);

/// Why a model fit's parameter `name` is not determined by its band, in words ("" when it is):
/// a relative error above one half, or an error that is not a number (a singular covariance).
std::string undetermined_parameter(const std::string& name, double value, double error);

/// Each fit's JSON object, with its verdict's ok and failure.
nlohmann::ordered_json slope_fit_json(const SlopeFit& fit, const Verdict& verdict);
nlohmann::ordered_json power_law_json(const PowerLawFit& fit, const Verdict& verdict);
nlohmann::ordered_json alpha_fit_json(const AlphaFit& fit, const Verdict& verdict);
nlohmann::ordered_json model_fit_json(const ModelFit& fit, const Verdict& verdict);

}  // namespace slidespec::detail
