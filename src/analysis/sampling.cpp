// Sampling as records come: uniform, jittered, or at a rate that changes inside the record.
// Nothing is made uniform silently: every choice leaves a note in the record (docs/analysis.md).
#include "analysis/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace slidespec::detail {

namespace {

// A part of the record ends where the median of 15 intervals moves this far from the part's
// (jitter of +-40% moves it by far less).
constexpr double kRateChange = 1.5;
constexpr std::size_t kRateMedianIntervals = 15;
// Fewest samples of a window or part that can give a spectrum.
constexpr std::size_t kFewestSamples = 64;
// The most samples a resampled grid may have: as many as the largest record analyze reads.
constexpr std::size_t kMostResampledSamples = 50'000'000;
// Linear interpolation at offsets spread evenly over an interval d passes power
// 1 - (1 - cos(omega d)) / 3 on average: the band is cut where that loses 5%.
constexpr double kInterpolationLoss = 0.05;
// An interval this many medians long has lost a sample: a gap, not jitter.
constexpr double kGap = 1.5;

std::string shortest(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

double median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

std::vector<double> intervals(const std::vector<double>& time, std::size_t first, std::size_t last) {
  std::vector<double> d;
  for (std::size_t i = first + 1; i < last; ++i) d.push_back(time[i] - time[i - 1]);
  return d;
}

/// Parts of constant rate: [first, last) sample ranges.
std::vector<std::pair<std::size_t, std::size_t>> rate_parts(const std::vector<double>& time) {
  std::vector<std::pair<std::size_t, std::size_t>> parts;
  const std::vector<double> d = intervals(time, 0, time.size());
  if (d.size() < 2 * kRateMedianIntervals) return {{0, time.size()}};
  std::size_t start = 0;
  double reference = median({d.begin(), d.begin() + kRateMedianIntervals});
  for (std::size_t i = 0; i + kRateMedianIntervals <= d.size(); ++i) {
    const double local = median({d.begin() + std::ptrdiff_t(i), d.begin() + std::ptrdiff_t(i + kRateMedianIntervals)});
    if (std::fabs(std::log(local / reference)) > std::log(kRateChange)) {
      // The change lies inside the five intervals: it begins at the first one of the new rate.
      std::size_t boundary = i;
      while (boundary < i + kRateMedianIntervals &&
             std::fabs(std::log(d[boundary] / reference)) < std::fabs(std::log(d[boundary] / local)))
        ++boundary;
      parts.push_back({start, boundary + 1});
      start = boundary + 1;
      reference = local;
      i = boundary;
    }
  }
  parts.push_back({start, time.size()});
  return parts;
}

/// A record time [s] as a user reads it off the file and gives it back to --window.
std::string seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", t);
  return text;
}

std::string describe_parts(const std::vector<double>& time,
                           const std::vector<std::pair<std::size_t, std::size_t>>& parts) {
  std::string text;
  for (const auto& [first, last] : parts) {
    const std::vector<double> d = intervals(time, first, last);
    text += (text.empty() ? "" : ", ") + seconds(time[first]) + ".." + seconds(time[last - 1]) + " s every " +
            (d.empty() ? std::string("?") : shortest(median(d))) + " s (" + std::to_string(last - first) + " samples)";
  }
  return text;
}

/// The longest run [first, last) of samples in time with no interval over kGap medians.
std::pair<std::size_t, std::size_t> longest_without_gap(const std::vector<double>& time, double typical) {
  std::pair<std::size_t, std::size_t> best{0, 1};
  std::size_t start = 0;
  for (std::size_t i = 1; i <= time.size(); ++i)
    if (i == time.size() || time[i] - time[i - 1] > kGap * typical) {
      if (time[i - 1] - time[start] > time[best.second - 1] - time[best.first]) best = {start, i};
      start = i;
    }
  return best;
}

}  // namespace

void keep_samples(Record& record, std::size_t first, std::size_t last) {
  for (std::vector<double>* channel : {&record.displacement, &record.force})
    if (!channel->empty())
      *channel = {channel->begin() + std::ptrdiff_t(first), channel->begin() + std::ptrdiff_t(last)};
}

namespace {

/// The part of `parts` with the longest interval among those [start, end] overlaps.
std::size_t coarsest_part(const std::vector<SamplingPart>& parts, double start, double end) {
  std::size_t coarsest = parts.size();
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const bool before_next = k + 1 == parts.size() || start < parts[k + 1].start;
    const bool after_start = k == 0 || end >= parts[k].start;
    if (before_next && after_start && (coarsest == parts.size() || parts[k].interval > parts[coarsest].interval))
      coarsest = k;
  }
  return coarsest;
}

}  // namespace

void set_interpolation_cut(Record& record) {
  const double end = record.start_time + double(record.samples() - 1) * record.dt;
  const std::size_t k = coarsest_part(record.parts, record.start_time, end);
  record.interpolation_interval = k < record.parts.size() ? record.parts[k].interval : record.dt;
  record.interpolation_cut =
      std::min(std::acos(1 - 3 * kInterpolationLoss) / record.interpolation_interval, std::numbers::pi / record.dt);
}

std::string interpolation_cut_words(const Record& record) {
  const double end = record.start_time + double(record.samples() - 1) * record.dt;
  if (record.interpolation_cut >= std::numbers::pi / record.dt)
    return "the band is cut at the grid's Nyquist, " + shortest(record.interpolation_cut) + " rad/s";
  std::string interval = "the median input interval " + shortest(record.interpolation_interval) + " s";
  if (record.parts.size() > 1) {
    const SamplingPart& part = record.parts[coarsest_part(record.parts, record.start_time, end)];
    interval = "the input interval " + shortest(part.interval) + " s of the part " + seconds(part.start) + ".." +
               seconds(part.end) + " s, the coarsest that " + seconds(record.start_time) + ".." + seconds(end) +
               " s overlaps";
  }
  return "interpolation filters the spectrum above " + shortest(record.interpolation_cut) +
         " rad/s, where the band is cut (acos(0.85) / d, d " + interval + ")";
}

/// The samples of `time` within the format's window, [first, last); all of them without one.
std::pair<std::size_t, std::size_t> window_span(const std::vector<double>& time, const RecordFormat& format) {
  std::size_t first = 0, last = time.size();
  if (format.window) {
    const auto [t0, t1] = *format.window;
    while (first < last && time[first] < t0) ++first;
    while (last > first && time[last - 1] > t1) --last;
    if (last - first < std::min(kFewestSamples, time.size()))
      throw InputError("{window} " + shortest(t0) + ":" + shortest(t1) + ": holds " + std::to_string(last - first) +
                       " samples, fewer than the " + std::to_string(kFewestSamples) +
                       " a spectrum needs; the record runs from " + shortest(time.front()) + " to " +
                       shortest(time.back()) + " s (record time)");
  }
  return {first, last};
}

/// A record whose sampling rate changes: its longest part in time (docs/analysis.md: the
/// length sets the lowest omega and the scatter at every omega), said so in a note that lists
/// the others and names the part with the most samples when it is another. Returns the part.
std::pair<std::size_t, std::size_t> longest_part(Record& record, const std::vector<double>& t,
                                                 const std::vector<std::pair<std::size_t, std::size_t>>& parts) {
  const auto duration = [&](const auto& p) { return t[p.second - 1] - t[p.first]; };
  const auto longest = std::max_element(parts.begin(), parts.end(),
                                        [&](const auto& p, const auto& q) { return duration(p) < duration(q); });
  const auto most = std::max_element(
      parts.begin(), parts.end(), [](const auto& p, const auto& q) { return p.second - p.first < q.second - q.first; });
  const auto span = [&](const auto& p) { return seconds(t[p.first]) + ".." + seconds(t[p.second - 1]) + " s"; };
  std::string note = "the sampling rate changes inside the record (parts: " + describe_parts(t, parts) +
                     "); analyzing the longest part in time, " + span(*longest) + " (" + shortest(duration(*longest)) +
                     " s: the length sets the lowest omega and the scatter at every omega); ";
  if (most != longest)
    note += "the part " + span(*most) + " holds the most samples (" + std::to_string(most->second - most->first) +
            ") and reaches higher omega: {window} " + seconds(t[most->first]) + ":" + seconds(t[most->second - 1]) +
            " picks it";
  else
    note += "{window} T0:T1 picks another";
  record.notes.push_back(note + ", {resample} DT interpolates the whole record");
  return *longest;
}

/// Every channel interpolated linearly onto a grid every `grid` seconds from t[0], said in a note.
void resample(Record& record, const std::vector<double>& t, const std::vector<double>& d, double typical, double grid) {
  // Checked before anything is allocated: a grid far finer than the record would not fit
  // in memory, and one coarser than the record holds no spectrum.
  const double count = std::floor((t.back() - t.front()) / grid) + 1;
  if (!(count >= double(kFewestSamples)) || count > double(kMostResampledSamples))
    throw InputError("{resample} " + shortest(grid) + ": a grid every " + shortest(grid) + " s over the record's " +
                     shortest(t.back() - t.front()) + " s gives " + shortest(count) + " samples; it needs " +
                     std::to_string(kFewestSamples) + " to " + shortest(double(kMostResampledSamples)) +
                     " (the record's median interval is " + shortest(typical) + " s)");
  const auto samples = static_cast<std::size_t>(count);
  for (std::vector<double>* channel : {&record.displacement, &record.force}) {
    if (channel->empty()) continue;
    const std::vector<double>& x = *channel;
    std::vector<double> resampled(samples);
    std::size_t j = 0;
    for (std::size_t k = 0; k < samples; ++k) {
      const double tk = t.front() + double(k) * grid;
      while (j + 2 < t.size() && t[j + 1] <= tk) ++j;
      const double f = (tk - t[j]) / (t[j + 1] - t[j]);
      resampled[k] = (1 - f) * x[j] + f * x[j + 1];
    }
    *channel = std::move(resampled);
  }
  record.dt = grid;
  record.resampled = true;
  // The loss is set by the input intervals (the offsets' spread), the grid's Nyquist by dt.
  set_interpolation_cut(record);
  record.notes.push_back(
      "resampled onto a uniform grid every " + shortest(grid) + " s by linear interpolation (intervals " +
      shortest(*std::min_element(d.begin(), d.end())) + ".." + shortest(*std::max_element(d.begin(), d.end())) +
      " s, median " + shortest(typical) + " s); " + interpolation_cut_words(record) +
      (grid > 1.5 * typical ? "; a grid coarser than the samples aliases what lies above its Nyquist" : ""));
}

/// Refuses sampling beyond the tolerance with only what would be accepted: a tolerance below
/// the limit, and for a gap the longest stretch without one.
[[noreturn]] void refuse_jitter(const std::string& where, const std::vector<double>& t, const std::vector<double>& d,
                                double typical, std::size_t worst, double jitter, bool gap,
                                const RecordFormat& format) {
  const double longest_interval = *std::max_element(d.begin(), d.end());
  std::string advice = "give {resample} median to interpolate onto a uniform grid";
  if (gap) {
    const auto [from, to] = longest_without_gap(t, typical);
    if (to - from >= kFewestSamples)
      advice = "give {window} " + seconds(t[from]) + ":" + seconds(t[to - 1]) +
               " to analyze the longest stretch without a gap (" + std::to_string(to - from) +
               " samples), or {resample} median to interpolate across the gap";
    else
      advice += " (across the gap)";
  }
  const double accepting = std::ceil(jitter * 100 + 1e-9) / 100;
  if (accepting < kLoosestTimeTolerance)
    advice += ", or {time_tolerance} " + shortest(accepting) + " to treat it as uniform";
  throw InputError(where + "sampling is not uniform: interval " + shortest(d[worst - 1]) + " s where the median is " +
                   shortest(typical) + " s (intervals " + shortest(*std::min_element(d.begin(), d.end())) + ".." +
                   shortest(*std::max_element(d.begin(), d.end())) + " s, " + shortest(jitter * 100) +
                   "% off; tolerance " + shortest(format.time_tolerance * 100) + "%" +
                   (gap ? ", a gap of " + shortest(longest_interval / typical) + " intervals" : "") + "); " + advice);
}

void make_uniform(Record& record, const std::vector<double>& time, const std::vector<int>& where,
                  const std::string& source, const std::string& place, const RecordFormat& format) {
  const auto at = [&](std::size_t i) { return source + ": " + place + " " + std::to_string(where[i]) + ": "; };
  const auto [first, last] = window_span(time, format);
  std::vector<double> t(time.begin() + std::ptrdiff_t(first), time.begin() + std::ptrdiff_t(last));
  keep_samples(record, first, last);
  std::size_t offset = first;  // of t[0] in `time`, for the messages

  auto parts = rate_parts(t);
  record.parts.clear();
  for (const auto& [a, b] : parts) {
    const std::vector<double> d = intervals(t, a, b);
    record.parts.push_back({t[a], t[b - 1], d.empty() ? 0 : median(d), b - a});
  }
  const bool forced = format.resample == Resampling::median || format.resample == Resampling::interval;
  if (parts.size() > 1 && !forced) {
    if (format.window)
      throw InputError(source + ": the sampling rate changes inside {window} (parts: " + describe_parts(t, parts) +
                       "); give a {window} inside one part, or {resample} DT (or median) to interpolate");
    const auto [from, to] = longest_part(record, t, parts);
    t = {t.begin() + std::ptrdiff_t(from), t.begin() + std::ptrdiff_t(to)};
    keep_samples(record, from, to);
    offset += from;
  }

  const std::vector<double> d = intervals(t, 0, t.size());
  const double typical = median(d);
  // The largest deviation of an interval, and of the cumulative clock (a slow drift or a
  // single gap shows in the second although jitter averages out of it).
  std::size_t worst = 1;
  double jitter = 0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double local = std::fabs(d[i - 1] - typical) / typical;
    const double cumulative = std::fabs((t[i] - t[0]) / double(i) - typical) / typical;
    if (std::max(local, cumulative) > jitter) jitter = std::max(local, cumulative), worst = i;
  }
  record.jitter = jitter;
  record.start_time = t.front();
  const bool gap = *std::max_element(d.begin(), d.end()) > kGap * typical;
  const bool jittered = jitter > format.time_tolerance;
  if (forced || (jittered && !gap && format.resample == Resampling::automatic))
    return resample(record, t, d, typical,
                    format.resample == Resampling::interval ? format.resample_interval : typical);
  if (jittered) refuse_jitter(at(offset + worst), t, d, typical, worst, jitter, gap, format);
  record.dt = (t.back() - t.front()) / double(t.size() - 1);
  if (jitter > RecordFormat{}.time_tolerance)
    record.notes.push_back("treated as uniform every " + shortest(record.dt) +
                           " s although intervals deviate by up to " + shortest(jitter * 100) +
                           "% ({time_tolerance}); the jitter adds noise at high omega");
}

void apply_window(Record& record, const RecordFormat& format, const std::string& source) {
  if (!format.window) return;
  const auto [t0, t1] = *format.window;
  const double end = record.start_time + double(record.samples() - 1) * record.dt;
  const double a = std::max(0.0, std::ceil((t0 - record.start_time) / record.dt - 1e-9));
  const double b = std::min(double(record.samples() - 1), std::floor((t1 - record.start_time) / record.dt + 1e-9));
  if (!(b >= a) || b - a + 1 < double(kFewestSamples))
    throw InputError(source + ": {window} " + shortest(t0) + ":" + shortest(t1) + " holds " +
                     std::to_string(b >= a ? std::size_t(b - a + 1) : 0) + " samples, fewer than the " +
                     std::to_string(kFewestSamples) + " a spectrum needs; the record runs from " +
                     shortest(record.start_time) + " to " + shortest(end) + " s (record time)");
  keep_samples(record, std::size_t(a), std::size_t(b) + 1);
  record.start_time += a * record.dt;
}

}  // namespace slidespec::detail
