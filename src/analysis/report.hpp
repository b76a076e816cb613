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

/// The spectrum's own fields: observable, the mean motion (or force) removed, the floor's
/// variance, usable band, estimator, and every point (with `theory` per point when given).
nlohmann::ordered_json spectrum_json(const RecordSpectrum& spectrum, const std::vector<double>& theory = {});

}  // namespace slidespec::detail
