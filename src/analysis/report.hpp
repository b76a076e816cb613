// The JSON of a record's spectrum: one writer for `slidespec analyze` and Python's ss.analyze,
// so that both give the same fields under the same names.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slidespec/analysis.hpp"

namespace slidespec::detail {

/// What sets the top of the usable band, in words: the sensor floor, the interpolation
/// filter of a resampled record, the estimator's top or the omega_max asked for.
std::string top_set_by(const RecordSpectrum& spectrum);

/// The refusal of a fit over the default band, the usable one, when there is none: "--fit
/// `fit`: no usable band (why); give --fit-band LO HI".
std::string no_usable_band_for_fit(const std::string& fit);

/// The usable band as the table's `# usable_band =` line gives it: "LO .. HI  # [rad/s], top set
/// by ...", or "none  # ..." when the floor leaves no band.
std::string usable_band_line(const RecordSpectrum& spectrum);

/// The table's header lines on the record's segments and strokes: "# segment = START END KIND
/// SPEED" per segment, "# strokes = ..." when the spectrum is of a reciprocating record's strokes.
std::vector<std::string> segment_lines(const RecordSpectrum& spectrum);

/// The spectrum's own fields: observable, the mean motion (or force) removed, the floor's
/// variance, usable band, estimator, whether it is a spectrum at all (`spectrum_ok`, and
/// `spectrum_failure` saying why not), and every point (with `theory` per point when given).
nlohmann::ordered_json spectrum_json(const RecordSpectrum& spectrum, const std::vector<double>& theory = {});

/// Whether a fit describes the data (docs/analysis.md, "Judging a fit"): chi2/dof within a few
/// of its standard deviations sqrt(2/dof) of 1, at least 3 allowed for correlated neighbours;
/// an alpha or model fit also where a theory holds, and a model fit only once it settled.
struct Verdict {
  bool ok = true;
  std::string reason;  ///< why not, in words ("" when ok)
};
Verdict judge_chi2(double chi2_per_dof, int dof);
Verdict judge_alpha(const AlphaFit& fit, const Parameters& fitted);
Verdict judge_model(const ModelFit& fit);
/// A power-law fit also fails where its slope ran to the end of the range searched.
Verdict judge_power_law(const PowerLawFit& fit);
/// Whether the spectrum is one: not where a point holds inf or nan (a sampling interval or
/// stiffness beyond a double's range), nor where it is 0 at every point (a constant record,
/// or values below a double's resolution): no fluctuation was measured there.
Verdict judge_spectrum(const RecordSpectrum& spectrum);

/// Each fit's JSON object, with its verdict's ok and failure.
nlohmann::ordered_json slope_fit_json(const SlopeFit& fit, const Verdict& verdict);
nlohmann::ordered_json power_law_json(const PowerLawFit& fit, const Verdict& verdict);
nlohmann::ordered_json alpha_fit_json(const AlphaFit& fit, const Verdict& verdict);
nlohmann::ordered_json model_fit_json(const ModelFit& fit, const Verdict& verdict);

}  // namespace slidespec::detail
