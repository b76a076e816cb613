// From the sample times a record was read with to a uniformly sampled record: the parts of a
// record whose rate changes, the window asked for, and jitter accepted, resampled or refused.
#pragma once

#include <string>
#include <vector>

#include "slidespec/analysis.hpp"

namespace slidespec::detail {

/// Keeps samples [first, last) of every channel of `record` (its time is the caller's).
void keep_samples(Record& record, std::size_t first, std::size_t last);

/// Makes `record` (displacement as read, at `time` [s]) uniformly sampled as `format` asks.
/// `where[i]` names sample i in messages as "<place> <where[i]>" (a line of the file).
void make_uniform(Record& record, const std::vector<double>& time, const std::vector<int>& where,
                  const std::string& source, const std::string& place, const RecordFormat& format);

/// For a resampled record: the cut of its band where linear interpolation filters, set by the
/// coarsest input interval among the parts (record.parts) its time span overlaps, a part
/// reaching to the next part's first sample; never above the grid's Nyquist.
void set_interpolation_cut(Record& record);

/// The cut of a resampled record in words: where, and which input interval set it.
std::string interpolation_cut_words(const Record& record);

/// Keeps the samples of a uniform record (dt > 0) inside the window; refuses a window
/// outside the record or holding fewer than a spectrum needs.
void apply_window(Record& record, const RecordFormat& format, const std::string& source);

}  // namespace slidespec::detail
