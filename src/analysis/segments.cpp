// Steady sliding inside a record: velocity steps and holds split it, and a spectrum belongs
// to one steady stretch (a step's transient is not stationary noise).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "analysis/line_fit.hpp"
#include "analysis/sampling.hpp"
#include "slidespec/analysis.hpp"

namespace slidespec {

namespace {

// About 48 blocks a record: enough to place a step to 2% of the record, each block long
// enough (>= 32 samples) for its speed to stand above the sensor's noise.
constexpr std::size_t kBlocksPerRecord = 48;
constexpr std::size_t kFewestBlockSamples = 32;
// Speeds within this factor of their group's median belong together (a velocity step in a
// rock-friction test is 3x..10x).
constexpr double kSteadyFactor = 1.6;
// A hold: slower than this share of the fastest block (a velocity step of 10x is sliding).
constexpr double kHoldShare = 0.02;
// Block speeds closer than this many of their scatter are the same speed.
constexpr double kScatters = 4;
// A segment needs this many blocks to count as steady.
constexpr std::size_t kSteadyBlocks = 3;

double block_speed(const std::vector<double>& x, std::size_t first, std::size_t last, double dt) {
  return detail::fit_line(x, first, last, dt).slope;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

std::vector<SteadySegment> steady_segments(const Record& record) {
  const std::vector<double>& x = record.displacement;
  if (x.empty()) return {};  // a force record without a displacement: no speed to find steps by
  const std::size_t block = std::max(kFewestBlockSamples, x.size() / kBlocksPerRecord);
  const std::size_t blocks = x.size() / block;
  if (blocks < kSteadyBlocks) {
    const double v = block_speed(x, 0, x.size(), record.dt);
    return {{record.start_time, record.start_time + double(x.size() - 1) * record.dt, v, x.size(), false}};
  }
  std::vector<double> raw(blocks);
  for (std::size_t b = 0; b < blocks; ++b) raw[b] = block_speed(x, b * block, (b + 1) * block, record.dt);
  // A median of three blocks: one block of a slip burst or a sensor glitch does not end a
  // segment; a step, lasting, does.
  std::vector<double> speed = raw;
  for (std::size_t b = 1; b + 1 < blocks; ++b) speed[b] = median({raw[b - 1], raw[b], raw[b + 1]});
  // The scatter of a block's speed in steady sliding (xi's own motion, the sensor's noise),
  // from successive blocks' differences (a step is one outlier among them: the median ignores it).
  std::vector<double> differences;
  for (std::size_t b = 1; b < blocks; ++b) differences.push_back(std::fabs(raw[b] - raw[b - 1]));
  const double scatter = 1.4826 * median(differences) / std::sqrt(2.0);
  const double fastest = std::fabs(
      *std::max_element(speed.begin(), speed.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); }));
  const auto is_hold = [&](double v) {
    return fastest > kScatters * scatter && std::fabs(v) < std::max(kHoldShare * fastest, kScatters * scatter);
  };
  const auto together = [&](double v, double group) {
    if (is_hold(v) || is_hold(group)) return is_hold(v) && is_hold(group);
    if (std::fabs(v - group) < kScatters * scatter) return true;  // a difference the noise makes
    return v * group > 0 && std::fabs(std::log(v / group)) < std::log(kSteadyFactor);
  };

  // Groups of consecutive blocks; a block that fits neither its group nor the next one is a
  // transition (it straddles the step) and belongs to none.
  std::vector<std::pair<std::size_t, std::size_t>> groups;  // [first, last) blocks
  std::size_t first = 0;
  std::vector<double> members = {speed[0]};
  for (std::size_t b = 1; b < blocks; ++b) {
    if (together(speed[b], median(members))) {
      members.push_back(speed[b]);
      continue;
    }
    groups.push_back({first, b});
    first = b;
    members = {speed[b]};
  }
  groups.push_back({first, blocks});

  std::vector<SteadySegment> segments;
  for (const auto& [a, b] : groups) {
    if (b - a < kSteadyBlocks) continue;
    const std::size_t from = a * block, to = b == blocks ? x.size() : b * block;
    SteadySegment s;
    s.start = record.start_time + double(from) * record.dt;
    s.end = record.start_time + double(to - 1) * record.dt;
    s.samples = to - from;
    s.mean_speed = block_speed(x, from, to, record.dt);
    s.hold = is_hold(s.mean_speed);
    segments.push_back(s);
  }
  return segments;
}

Record record_window(const Record& record, double start, double end) {
  Record window = record;
  const double a = std::max(0.0, std::ceil((start - record.start_time) / record.dt - 1e-9));
  const double b = std::min(double(record.samples() - 1), std::floor((end - record.start_time) / record.dt + 1e-9));
  if (!(b >= a))
    throw InputError("record_window: no sample between " + std::to_string(start) + " and " + std::to_string(end) +
                     " s");
  detail::keep_samples(window, std::size_t(a), std::size_t(b) + 1);
  window.start_time = record.start_time + a * record.dt;
  if (window.resampled) detail::set_interpolation_cut(window);  // the parts this stretch overlaps
  return window;
}

Record longest_steady(const Record& record, const std::vector<SteadySegment>& segments,
                      std::vector<std::string>& notes) {
  if (segments.empty() || (segments.size() == 1 && segments.front().samples >= record.samples())) return record;
  const auto longest = std::max_element(segments.begin(), segments.end(),
                                        [](const auto& a, const auto& b) { return a.end - a.start < b.end - b.start; });
  char note[320];
  std::snprintf(note, sizeof note,
                "the record holds %zu steady segment(s) ({segments} lists them); analyzing the longest, %.10g:%.10g s "
                "at %.3g m/s; {window} T0:T1 picks another",
                segments.size(), longest->start, longest->end, longest->mean_speed);
  notes.push_back(note);
  Record window = record_window(record, longest->start, longest->end);
  if (window.resampled && window.interpolation_cut != record.interpolation_cut)
    notes.push_back("in the segment, " + detail::interpolation_cut_words(window));
  return window;
}

}  // namespace slidespec
