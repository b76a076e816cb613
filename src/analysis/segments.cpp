// Steady sliding inside a record: velocity steps and holds split it, and a spectrum belongs
// to one steady stretch (a step's transient is not stationary noise).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "analysis/line_fit.hpp"
#include "analysis/names.hpp"
#include "analysis/sampling.hpp"
#include "slidespec/analysis.hpp"

namespace slidespec {

namespace {

// About 2048 blocks a record, at least 32 samples each (a speed above the sensor's noise): a hold of 2 s in a record of
// an hour at 10 Hz spans several blocks (at 1/48 of the record it was one block, smoothed away).
constexpr std::size_t kBlocksPerRecord = 2048;
constexpr std::size_t kFewestBlockSamples = 32;
// Speeds within this factor of their group's median belong together (a velocity step in a
// rock-friction test is 3x..10x).
constexpr double kSteadyFactor = 1.6;
// A hold: slower than this share of the fastest block (a velocity step of 10x is sliding).
constexpr double kHoldShare = 0.02;
// Block speeds (or forces) closer than this many of their scatter are the same.
constexpr double kScatters = 4;
// The slowest sliding to tell from a hold (twice the scatters it needs), as a share of the
// fastest, and the fewest blocks
// of a record in the search for blocks long enough to tell it.
constexpr double kSlowShare = 0.1;
constexpr std::size_t kCoarsestBlocks = 48;
// A segment needs this many blocks to count as sliding or a hold.
constexpr std::size_t kSteadyBlocks = 3;

constexpr std::array<detail::Word<SegmentKind>, 5> kKindWords{{{"sliding", SegmentKind::sliding},
                                                               {"hold", SegmentKind::hold},
                                                               {"loading", SegmentKind::loading},
                                                               {"step", SegmentKind::step},
                                                               {"reversal", SegmentKind::reversal}}};

double block_speed(const std::vector<double>& x, std::size_t first, std::size_t last, double dt) {
  return detail::fit_line(x, first, last, dt).slope;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The scatter of one block's value from its neighbour's in steady sliding, from successive
// blocks' differences (a step is one outlier among them: the median ignores it).
double successive_scatter(const std::vector<double>& values, std::size_t first, std::size_t last) {
  std::vector<double> differences;
  for (std::size_t b = first + 1; b < last; ++b) differences.push_back(std::fabs(values[b] - values[b - 1]));
  return differences.empty() ? 0 : 1.4826 * median(differences) / std::sqrt(2.0);
}

// A stroke keeps this many blocks: coarser blocks would straddle the reversals of a noisy
// slider's strokes and merge them (twice the blocks a sliding stretch needs).
constexpr std::size_t kStrokeBlocks = 2 * kSteadyBlocks;

/// Stretches of one sliding direction among the blocks sliding at half the fastest speed or
/// more: 1 for a slide, the strokes of a reciprocating record.
std::size_t direction_runs(const std::vector<double>& speed, double fastest) {
  std::size_t runs = 0;
  double direction = 0;
  for (double v : speed) {
    if (std::fabs(v) < 0.5 * fastest || v * direction > 0) continue;
    direction = v;
    ++runs;
  }
  return runs;
}

struct Group {
  std::size_t first, last;  // blocks [first, last)
  SegmentKind kind;
};

// The blocks at the start of a sliding group where the force has not settled: its block means
// beyond kScatters of the level of the group's second half. 0 without a force channel.
std::size_t unsettled_blocks(const std::vector<double>& force, std::size_t block, const Group& g) {
  if (force.empty() || g.last - g.first < 2 * kSteadyBlocks) return 0;
  std::vector<double> means(g.last - g.first);
  for (std::size_t b = g.first; b < g.last; ++b) {
    double sum = 0;
    for (std::size_t i = b * block; i < (b + 1) * block; ++i) sum += force[i];
    means[b - g.first] = sum / double(block);
  }
  const std::size_t half = means.size() / 2;
  const double level = median(std::vector<double>(means.begin() + std::ptrdiff_t(half), means.end()));
  const double scatter = successive_scatter(means, half, means.size());
  std::size_t settled = 0;
  while (settled < means.size() && std::fabs(means[settled] - level) > kScatters * scatter) ++settled;
  // Settling that never ends, or leaves too little, is not a transient but the stretch itself.
  return settled + kSteadyBlocks <= means.size() ? settled : 0;
}

}  // namespace

const char* to_string(SegmentKind kind) { return detail::name_of(kKindWords, kind); }

namespace {

/// A record's speed block by block, and what tells a hold, and two speeds apart, at the
/// blocks' scatter.
struct BlockSpeeds {
  std::size_t block = 0;           // samples a block
  std::vector<double> raw, speed;  // each block's speed [m/s], and the median of three around it
  double scatter = 0, fastest = 0;

  bool is_hold(double v) const {
    return fastest > kScatters * scatter && std::fabs(v) < std::max(kHoldShare * fastest, kScatters * scatter);
  }
  bool together(double v, double group) const {
    if (is_hold(v) || is_hold(group)) return is_hold(v) && is_hold(group);
    if (std::fabs(v - group) < kScatters * scatter) return true;  // a difference the noise makes
    return v * group > 0 && std::fabs(std::log(v / group)) < std::log(kSteadyFactor);
  }
};

/// The finest blocks whose speeds tell a tenth of the fastest speed from a hold: a noisy
/// sensor needs longer blocks (down to the 48 of a record that were once the only choice).
/// None when the record is too short for kSteadyBlocks blocks.
std::optional<BlockSpeeds> block_speeds(const std::vector<double>& x, double dt) {
  BlockSpeeds s;
  for (s.block = std::max(kFewestBlockSamples, x.size() / kBlocksPerRecord);; s.block *= 2) {
    const std::size_t blocks = x.size() / s.block;
    if (blocks < kSteadyBlocks) return std::nullopt;
    s.raw.assign(blocks, 0);
    for (std::size_t b = 0; b < blocks; ++b) s.raw[b] = block_speed(x, b * s.block, (b + 1) * s.block, dt);
    // A median of three blocks: one block of a slip burst or a sensor glitch does not end a
    // segment; a step, lasting, does.
    s.speed = s.raw;
    for (std::size_t b = 1; b + 1 < blocks; ++b) s.speed[b] = median({s.raw[b - 1], s.raw[b], s.raw[b + 1]});
    // The scatter of a block's speed in steady sliding (xi's own motion, the sensor's noise).
    s.scatter = successive_scatter(s.raw, 0, blocks);
    s.fastest = std::fabs(*std::max_element(s.speed.begin(), s.speed.end(),
                                            [](double a, double b) { return std::fabs(a) < std::fabs(b); }));
    if (2 * kScatters * s.scatter <= kSlowShare * s.fastest || blocks / 2 < kCoarsestBlocks) return s;
    if (blocks / 2 < kStrokeBlocks * direction_runs(s.speed, s.fastest)) return s;
  }
}

/// Groups of consecutive blocks of one speed; the blocks between groups of kSteadyBlocks or
/// more straddle a step or a reversal.
std::vector<Group> speed_runs(const BlockSpeeds& s) {
  const std::size_t blocks = s.raw.size();
  std::vector<Group> runs;
  std::size_t first = 0;
  std::vector<double> members = {s.speed[0]};
  for (std::size_t b = 1; b < blocks; ++b) {
    const double level = median(members);
    if (s.together(s.speed[b], level)) {
      members.push_back(s.speed[b]);
      continue;
    }
    // A block that does not fit, between blocks that do, is a burst inside the stretch.
    bool returns = false;
    for (std::size_t a = b + 1; a < std::min(blocks, b + kSteadyBlocks) && !returns; ++a)
      returns = s.together(s.speed[a], level);
    if (returns) continue;
    runs.push_back({first, b, SegmentKind::sliding});
    first = b;
    members = {s.speed[b]};
  }
  runs.push_back({first, blocks, SegmentKind::sliding});
  return runs;
}

/// The runs long enough to be steady, sliding or holds, trimmed of the blocks that straddle
/// their steps; neighbours of one speed split by a short glitch joined.
std::vector<Group> steady_groups(const std::vector<double>& x, double dt, const BlockSpeeds& s,
                                 const std::vector<Group>& runs) {
  const std::size_t block = s.block;
  std::vector<Group> steady;
  for (Group g : runs) {
    if (g.last - g.first < kSteadyBlocks) continue;
    // A block at the edge whose own speed is off the stretch's straddles the step (the median
    // of three took it in): the step's.
    const double level =
        median(std::vector<double>(s.raw.begin() + std::ptrdiff_t(g.first), s.raw.begin() + std::ptrdiff_t(g.last)));
    const auto off = [&](std::size_t b) { return std::fabs(s.raw[b] - level) > kScatters * s.scatter; };
    while (g.last - g.first > kSteadyBlocks && off(g.first)) ++g.first;
    while (g.last - g.first > kSteadyBlocks && off(g.last - 1)) --g.last;
    g.kind = s.is_hold(block_speed(x, g.first * block, g.last * block, dt)) ? SegmentKind::hold : SegmentKind::sliding;
    // Stretches of one speed split by a glitch too long for the median are one stretch.
    const auto group_speed = [&](const Group& h) { return block_speed(x, h.first * block, h.last * block, dt); };
    if (!steady.empty() && steady.back().kind == g.kind && steady.back().last + kSteadyBlocks > g.first &&
        (g.kind == SegmentKind::hold || s.together(group_speed(g), group_speed(steady.back())))) {
      steady.back().last = g.last;
      continue;
    }
    steady.push_back(g);
  }
  return steady;
}

}  // namespace

std::vector<SteadySegment> steady_segments(const Record& record) {
  const std::vector<double>& x = record.displacement;
  if (x.empty()) return {};  // a force record without a displacement: no speed to find steps by
  const auto segment = [&](std::size_t from, std::size_t to, SegmentKind kind) {
    SteadySegment s;
    s.start = record.start_time + double(from) * record.dt;
    s.end = record.start_time + double(to - 1) * record.dt;
    s.samples = to - from;
    s.mean_speed = block_speed(x, from, to, record.dt);
    s.kind = kind;
    s.hold = kind == SegmentKind::hold;
    return s;
  };
  const std::optional<BlockSpeeds> speeds = block_speeds(x, record.dt);
  if (!speeds) return {segment(0, x.size(), SegmentKind::sliding)};
  const std::size_t block = speeds->block, blocks = speeds->raw.size();
  const std::vector<Group> steady = steady_groups(x, record.dt, *speeds, speed_runs(*speeds));

  std::vector<Group> all;
  std::size_t next = 0;  // first block not yet labelled
  for (std::size_t k = 0; k < steady.size(); ++k) {
    Group g = steady[k];
    const Group* before = k > 0 ? &steady[k - 1] : nullptr;
    if (g.first > next) {  // the blocks between two steady stretches
      const bool reversal = before && before->kind == SegmentKind::sliding && g.kind == SegmentKind::sliding &&
                            block_speed(x, before->first * block, before->last * block, record.dt) *
                                    block_speed(x, g.first * block, g.last * block, record.dt) <
                                0;
      all.push_back({next, g.first,
                     reversal ? SegmentKind::reversal
                     : before ? SegmentKind::step
                              : SegmentKind::loading});
    }
    if (g.kind == SegmentKind::sliding) {
      const std::size_t unsettled = unsettled_blocks(record.force, block, g);
      if (unsettled > 0) {
        const bool after_sliding =
            before && before->kind == SegmentKind::sliding && before->last + kSteadyBlocks > g.first;
        all.push_back({g.first, g.first + unsettled, after_sliding ? SegmentKind::step : SegmentKind::loading});
        g.first += unsettled;
      }
    }
    all.push_back(g);
    next = steady[k].last;
  }
  if (next < blocks) all.push_back({next, blocks, steady.empty() ? SegmentKind::sliding : SegmentKind::step});

  std::vector<SteadySegment> segments;
  for (const Group& g : all)
    segments.push_back(segment(g.first * block, g.last == blocks ? x.size() : g.last * block, g.kind));
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
  const auto by_length = [](const auto& a, const auto& b) {
    const bool a_sliding = a.kind == SegmentKind::sliding, b_sliding = b.kind == SegmentKind::sliding;
    if (a_sliding != b_sliding) return b_sliding;
    return a.end - a.start < b.end - b.start;
  };
  const auto longest = std::max_element(segments.begin(), segments.end(), by_length);
  const auto count = [&](SegmentKind kind) {
    return std::count_if(segments.begin(), segments.end(), [&](const SteadySegment& s) { return s.kind == kind; });
  };
  char note[400];
  std::snprintf(note, sizeof note,
                "the record holds %zu segment(s): %td sliding, %td hold(s), %td loading, %td step(s), %td reversal(s) "
                "({segments} lists them); analyzing the longest %s one, %.10g:%.10g s at %.3g m/s; {window} T0:T1 "
                "picks another",
                segments.size(), count(SegmentKind::sliding), count(SegmentKind::hold), count(SegmentKind::loading),
                count(SegmentKind::step), count(SegmentKind::reversal),
                longest->kind == SegmentKind::sliding ? "sliding" : "(no sliding stretch: not steady)", longest->start,
                longest->end, longest->mean_speed);
  notes.push_back(note);
  Record window = record_window(record, longest->start, longest->end);
  if (window.resampled && window.interpolation_cut != record.interpolation_cut)
    notes.push_back("in the segment, " + detail::interpolation_cut_words(window));
  return window;
}

std::optional<Strokes> find_strokes(const std::vector<SteadySegment>& segments, double dt) {
  std::vector<const SteadySegment*> sliding;
  double sliding_time = 0;
  for (const SteadySegment& s : segments)
    if (s.kind == SegmentKind::sliding) sliding.push_back(&s), sliding_time += s.end - s.start;
  if (sliding.size() < kFewestStrokes) return std::nullopt;
  // The longest run of sliding stretches alternating in direction, each after a reversal.
  std::size_t best_first = 0, best_count = 1, first = 0;
  for (std::size_t k = 1; k <= sliding.size(); ++k) {
    const bool alternates = k < sliding.size() && sliding[k]->mean_speed * sliding[k - 1]->mean_speed < 0;
    if (alternates) continue;
    if (k - first > best_count) best_first = first, best_count = k - first;
    first = k;
  }
  if (best_count < kFewestStrokes) return std::nullopt;
  Strokes strokes;
  double stroke_time = 0, speed_sum = 0;
  for (std::size_t k = best_first; k < best_first + best_count; ++k) {
    SteadySegment middle = *sliding[k];
    const double trim = kStrokeEndShare * (middle.end - middle.start);
    middle.start += trim, middle.end -= trim;
    middle.samples = std::size_t(std::floor((middle.end - middle.start) / dt + 1e-9)) + 1;
    stroke_time += sliding[k]->end - sliding[k]->start;
    speed_sum += std::fabs(middle.mean_speed);
    strokes.middles.push_back(middle);
  }
  // Strokes are most of the sliding, or the record is a slide with a few turns in it.
  if (stroke_time < 0.5 * sliding_time) return std::nullopt;
  strokes.speed = speed_sum / double(best_count);
  strokes.middle_duration =
      std::min_element(strokes.middles.begin(), strokes.middles.end(),
                       [](const auto& a, const auto& b) { return a.end - a.start < b.end - b.start; })
          ->samples *
      dt;
  strokes.lowest_omega = 2 * 2 * std::numbers::pi / strokes.middle_duration;
  return strokes;
}

}  // namespace slidespec
