// `slidespec sweep`: a grid of parameter values (lists and ranges of several keys), the
// planned work of many runs for one progress bar, and the combined table of all runs.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "slidespec/parameters.hpp"
#include "slidespec/run.hpp"

namespace slidespec::cli {

/// One key and the values it takes.
struct SweepAxis {
  std::string key;
  std::vector<std::string> values;
};

/// Parses the sweep's words: KEY=V1,V2,... | KEY=FIRST:LAST:STEP (linear, LAST included
/// when on the grid) | KEY=FIRST..LAST followed by "log K" or "lin K" (K values, both
/// ends included). Integer keys (N, levels, N_l) round and drop repeats. Throws InputError.
std::vector<SweepAxis> parse_sweep(const std::vector<std::string>& words);

/// Every combination of the axes' values, the first key slowest: KEY=VALUE lists.
std::vector<std::vector<std::pair<std::string, std::string>>> sweep_grid(const std::vector<SweepAxis>& axes);

/// The planned work of a run [block-steps per realization over its sub-bands]: a weight
/// that makes the progress of several runs one bar with an honest time left.
double planned_work(const Parameters& p, const RunRequest& request);

/// The planned work of each sub-band of a run, the same measure as planned_work.
std::vector<double> sub_band_work(const Parameters& p, const RunRequest& request);

/// A run's progress, reported as (b + f_b) / B over its B sub-bands, as the fraction of
/// its planned work: the bands before b and f_b of band b, weighted by `band_work`.
double weighted_fraction(double fraction, const std::vector<double>& band_work);

/// One finished run of a sweep, for the combined table.
struct SweepRun {
  std::vector<std::pair<std::string, std::string>> values;  ///< KEY=VALUE of this run
  std::string label;                                        ///< "reference + alpha=0.5"
  std::string table;                                        ///< its own PREFIX_....tsv
  Parameters parameters;
  RunResult result;
};

/// All runs in one TSV: '#' lines, a '#' column line "run KEY..." and a run point's columns
/// (io::run_point_header), one row per point of every run; a word-valued KEY's column
/// holds the index of the value in its "# sweep_KEY = ..." line.
std::string sweep_table(const std::vector<SweepAxis>& axes, const std::vector<SweepRun>& runs);
/// The same as JSON: {"keys": [...], "runs": [{"values", "label", "table", "complete",
/// "measured_mean_speed", "reached_precision", "points": [...]}]}, each point as in the
/// run's own JSON (io::run_point_json).
std::string sweep_json(const std::vector<SweepAxis>& axes, const std::vector<SweepRun>& runs);

}  // namespace slidespec::cli
