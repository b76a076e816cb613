// The JSON of one spectrum point, shared by a run's points and an analysis's: apart from
// tables.hpp so that the analysis of a record needs nothing of a run.
#pragma once

#include <nlohmann/json.hpp>

namespace slidespec::io {

/// The fields every spectrum point carries in JSON, in this order: omega [rad/s], the
/// spectrum under `spectrum_name` (C_x [m^2 s] or C_F [N^2 s]), stderr, n_avg and bandwidth
/// [rad/s]. Run and analysis points add their own fields after these.
inline nlohmann::ordered_json point_json(double omega, const char* spectrum_name, double value, double standard_error,
                                         double n_avg, double bandwidth) {
  return {
      {"omega", omega}, {spectrum_name, value}, {"stderr", standard_error}, {"n_avg", n_avg}, {"bandwidth", bandwidth}};
}

}  // namespace slidespec::io
