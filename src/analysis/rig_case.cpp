// The compared case built from a rig's record (docs/analysis.md, "The model on a rig's
// scale"): the model's parameters from what the record measures and the user knows, each
// choice said, the rest held at stated values for the fit to start from.
#include <algorithm>
#include <cmath>

#include "analysis/names.hpp"
#include "slidespec/analysis.hpp"
#include "slidespec/input_error.hpp"
#include "slidespec/parameters.hpp"
#include "util/numbers.hpp"

namespace slidespec {

namespace {

using detail::short_number;

// Without a velocity step the viscous term is held at v dF/dv = this share of the friction:
// rate strengthening (a - b) ~ 0.006 at mu ~ 0.6, typical of rock and gouge at room temperature.
constexpr double kHeldRateShare = 0.01;
// The contacts are held this much stiffer than the machine (N k0 = this x K): the machine's
// spring, which the record measures, sets the compliance the band sees.
constexpr double kContactStiffnessRatio = 1e3;
// The miniblocks' mass as a share of the slider's, as in the reference case (1e-5 kg of 1 kg).
constexpr double kMiniblockMassShare = 1e-5;
// The slider's mass when not given [kg]: the reference's; its resonance lies far above the band.
constexpr double kHeldSliderMass = 1;
// The fit starts with the random forces at this share of the stall boundary alpha F_kin = 2 (F_drive - F_kin).
constexpr double kStartStallShare = 0.25;

using detail::sets;

/// The mean of the force channel over [start, end] of record time.
double mean_force(const Record& record, double start, double end) {
  const auto index = [&](double t) {
    const double n = std::round((t - record.start_time) / record.dt);
    return static_cast<std::size_t>(std::clamp(n, 0.0, double(record.force.size() - 1)));
  };
  const std::size_t first = index(start), last = index(end);
  double sum = 0;
  for (std::size_t n = first; n <= last; ++n) sum += record.force[n];
  return sum / double(last - first + 1);
}

/// dF/dv across the steps next to [start, end] (else all the record's), their mean; 0 when none.
double friction_slope(const RigTerms& t, std::vector<std::string>& notes) {
  // The step out of the stretch analysed or into it: its sliding ends or starts within it.
  const double slack = 1e-6 * (t.end - t.start);
  std::vector<FrictionStep> next;
  for (const FrictionStep& step : t.steps)
    if ((step.end_before >= t.start - slack && step.end_before <= t.end + slack) ||
        (step.start_after >= t.start - slack && step.start_after <= t.end + slack))
      next.push_back(step);
  if (next.empty()) next = t.steps;
  double sum = 0;
  for (const FrictionStep& step : next) {
    sum += step.slope();
    notes.push_back("velocity step " + short_number(step.speed_before) + " -> " + short_number(step.speed_after) +
                    " m/s: the steady friction " + short_number(step.force_before) + " -> " +
                    short_number(step.force_after) + " N, dF/dv = " + short_number(step.slope()) + " N s/m");
  }
  return next.empty() ? 0 : sum / double(next.size());
}

/// Whether the overrides set `key`, the note saying what the model's `key` is and why.
bool given(const std::vector<std::string>& overrides, const std::string& key, double value, const std::string& why,
           std::vector<std::string>& notes) {
  const bool kept = sets(overrides, key);
  notes.push_back("the model's " + key + (kept ? " as {set} gives it" : " = " + short_number(value) + ": " + why));
  return kept;
}

/// "KEY=VALUE" unless the overrides set KEY, with the note.
void add(std::vector<std::string>& terms, const std::vector<std::string>& overrides, const std::string& key,
         double value, const std::string& why, std::vector<std::string>& notes) {
  if (!given(overrides, key, value, why, notes)) terms.push_back(key + "=" + util::format_number(value));
}

/// A field of the built case set to `value` unless the overrides set it, with the note.
void start_at(double& field, const std::vector<std::string>& overrides, const std::string& key, double value,
              const std::string& why, std::vector<std::string>& notes) {
  if (!given(overrides, key, value, why, notes)) field = value;
}

/// F_kin = F - v dF/dv, dF/dv from the steps where they give one the model can be (> 0).
double kinetic_friction(const RigTerms& t, std::vector<std::string>& notes) {
  const double slope = friction_slope(t, notes);
  if (slope > 0 && t.friction_force - t.speed * slope >= 0) {
    notes.push_back("dF/dv = " + short_number(slope) + " N s/m across the velocity step is the model's viscous term " +
                    "N m eta1 (steady friction F_kin + N m eta1 v, docs/model.md §1): F_kin = F - v dF/dv");
    return t.friction_force - t.speed * slope;
  }
  const std::string why = t.steps.empty() ? "the record holds no velocity step"
                          : slope > 0
                              ? "v dF/dv across the step exceeds the friction"
                              : "the friction does not rise with speed across the step (velocity weakening, which the "
                                "model's viscous term cannot be)";
  notes.push_back(why + ": F - F_kin = v dF/dv is held at " + short_number(100 * kHeldRateShare) +
                  "% of the friction ({set} F_kin=... to change it)");
  return t.friction_force * (1 - kHeldRateShare);
}

}  // namespace

std::vector<FrictionStep> friction_steps(const Record& record, const std::vector<SteadySegment>& segments) {
  std::vector<FrictionStep> steps;
  if (record.force.empty()) return steps;
  const SteadySegment* before = nullptr;
  for (const SteadySegment& s : segments) {
    if (s.kind == SegmentKind::hold || s.kind == SegmentKind::reversal) before = nullptr;
    if (s.kind != SegmentKind::sliding) continue;
    if (before && before->mean_speed != s.mean_speed)
      steps.push_back({before->mean_speed, s.mean_speed, mean_force(record, before->start, before->end),
                       mean_force(record, s.start, s.end), before->end, s.start});
    before = &s;
  }
  return steps;
}

double stroke_friction(const Record& record, const Strokes& strokes) {
  double sum = 0;
  for (const SteadySegment& middle : strokes.middles)
    sum += (middle.mean_speed < 0 ? -1 : 1) * mean_force(record, middle.start, middle.end);
  return strokes.middles.empty() ? 0 : sum / double(strokes.middles.size());
}

Parameters rig_model(const RigTerms& t, const std::vector<std::string>& overrides, std::vector<std::string>& notes) {
  if (!(t.machine_stiffness > 0))
    throw InputError("{compare_case} rig: builds the case from the machine's spring; give {machine_stiffness} K");
  if (!(t.friction_force > 0))
    throw InputError("{compare_case} rig: the mean friction is " + short_number(t.friction_force) +
                     " N; the model needs one > 0 (a force channel, or {friction_force})");
  if (!(t.speed > 0))
    throw InputError("{compare_case} rig: the load point does not advance (mean speed " + short_number(t.speed) +
                     " m/s)");
  const double stiffness = t.machine_stiffness;
  if (t.normal_force > 0)
    notes.push_back("mean friction " + short_number(t.friction_force) + " N on a normal load of " +
                    short_number(t.normal_force) + " N: mu = " + short_number(t.friction_force / t.normal_force));
  std::vector<std::string> terms{"drive=spring"};
  add(terms, overrides, "k_drive", stiffness, "the machine stiffness K, through which the load point pulls", notes);
  add(terms, overrides, "v", t.speed, "the record's measured load-point speed", notes);
  add(terms, overrides, "F_drive", t.friction_force, "the mean friction, which the spring's mean force balances",
      notes);
  const double kinetic = kinetic_friction(t, notes);
  add(terms, overrides, "F_kin", kinetic, "F - v dF/dv", notes);
  const double mass = t.slider_mass > 0 ? t.slider_mass : kHeldSliderMass;
  add(terms, overrides, "M", mass,
      t.slider_mass > 0 ? "the slider's mass, as given" : "held ({slider_mass} gives it): it sets only the resonance",
      notes);
  add(terms, overrides, "m", kMiniblockMassShare * mass, "held at 1e-5 M, as in the reference case", notes);
  terms.insert(terms.end(), overrides.begin(), overrides.end());
  Parameters p = build_case("reference", terms);
  // The rest follow from the case as built (N, K, F_kin as the user may have set them).
  start_at(p.k0, overrides, "k0", kContactStiffnessRatio * p.k_drive / double(p.N),
           "held at N k0 = 1000 K: contacts far stiffer than the machine, whose spring the record measures", notes);
  const double viscous = p.F_drive - p.F_kin;  // v dF/dv = N m eta1 v
  notes.push_back("N = " + std::to_string(p.N) + " is held: the band sets alpha and N only as alpha^2/N; " +
                  "eta1 = dF/dv / (N m) follows from v (the corner K / (dF/dv) = " +
                  short_number(landmarks(p).omega_s) + " rad/s)");
  if (p.F_kin > 0)
    start_at(p.alpha, overrides, "alpha", kStartStallShare * 2 * viscous / p.F_kin,
             "where the fit starts, a quarter of the stall boundary alpha F_kin = 2 (F_drive - F_kin)", notes);
  if (t.omega_low > 0 && t.omega_high > t.omega_low)
    start_at(p.a, overrides, "a", p.v / std::sqrt(t.omega_low * t.omega_high),
             "where the fit starts, the renewal corner v/a amid the band", notes);
  return p;
}

}  // namespace slidespec
