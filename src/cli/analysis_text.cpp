#include "cli/analysis_text.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "io/tables.hpp"
#include "slidespec/options.hpp"
#include "util/numbers.hpp"

namespace slidespec::cli {

namespace {

using util::short_number;

std::string number(double x) { return util::format_number(x); }

/// "LO .. HI  # [rad/s], top set by ...", or "none  # ..." when the floor leaves no band.
std::string usable_band_line(const RecordSpectrum& s) {
  if (!(s.usable_high > s.usable_low)) return "none  # " + top_set_by(s);
  return number(s.usable_low) + " .. " + number(s.usable_high) + "  # [rad/s], top set by " + top_set_by(s);
}

/// "# segment = START END KIND SPEED" per segment, and "# strokes = ..." for a reciprocating
/// record's strokes.
std::vector<std::string> segment_lines(const RecordSpectrum& s) {
  std::vector<std::string> lines;
  for (const SteadySegment& g : s.segments)
    lines.push_back("# segment = " + util::format_number(g.start) + " " + util::format_number(g.end) + " " +
                    to_string(g.kind) + " " + util::format_number(g.mean_speed) +
                    "  # start [s], end [s], kind, mean speed [m/s]");
  if (s.strokes)
    lines.push_back("# strokes = " + std::to_string(s.strokes->middles.size()) + " " +
                    util::format_number(s.strokes->speed) + " " + util::format_number(s.strokes->middle_duration) +
                    " " + util::format_number(s.strokes->lowest_omega) +
                    "  # strokes averaged, their mean |speed| [m/s], shortest middle analyzed [s], lowest omega a "
                    "stroke allows [rad/s]");
  return lines;
}

/// Library words, which name options by id, as the command line spells them.
std::string words(const std::string& text) { return worded(text, FrontEnd::command_line); }

std::string verdict_line(const Verdict& verdict) { return verdict.ok ? "true" : "false  # " + words(verdict.reason); }

/// The '#' lines of the record, its spectrum and the sensor floor.
void record_lines(std::ostream& out, const AnalysisSource& source, const AnalysisReport& r) {
  const RecordSpectrum& s = r.spectrum;
  const SlidingFit& v = s.sliding;
  const bool force = s.observable == Observable::force;
  const std::string C = force ? "C_F" : "C_x";
  // The label is the figure's legend: a long channel description (a slip's F/K with its
  // units) stays in the observable line, the legend names the observable.
  constexpr std::size_t kLongestLegendChannel = 40;
  out << "# label = measured: " << source.file << " ("
      << (s.channel.size() <= kLongestLegendChannel ? s.channel : std::string(to_string(s.observable))) << ")\n"
      << "# observable = " << to_string(s.observable) << "  # " << C << " [" << spectrum_unit(s.observable) << "] of "
      << s.channel << "\n";
  if (!r.record.column.empty())
    out << "# units = " << to_string(r.record.unit) << "  # of the displacement column, from "
        << words(r.record.unit_source) << "\n";
  out << "# ok = " << (r.ok() ? "true" : "false") << "  # false: a fit failed, or the spectrum is none (see its line)\n"
      << "# spectrum_ok = " << verdict_line(r.spectrum_verdict) << "\n"
      << "# record = " << source.file << "\n# samples = " << s.samples << "\n# dt = " << number(s.dt) << "  # [s]\n"
      << "# duration = " << number(s.duration) << "  # [s]\n";
  if (force)
    out << "# mean_force = " << number(v.x0 + v.v * s.duration / 2) << "  # [N]\n# force_trend = " << number(v.v)
        << "  # [N/s] +- " << number(v.v_error) << ", removed with the mean\n# F_rms = " << number(v.xi_rms)
        << "  # [N] rms of F about its trend\n";
  else
    out << "# measured_mean_speed = " << number(v.v) << "  # [m/s] +- " << number(v.v_error) << " (from " << v.blocks
        << " blocks)\n"
        << "# xi_rms = " << number(v.xi_rms) << "  # [m] rms of x - x0 - v t\n";
  if (r.mu) out << "# mu = " << number(*r.mu) << "  # M'/M\n";
  out << "# resolution = " << number(r.request.resolution)
      << "  # q [m]\n# sensor_noise = " << number(r.request.sensor_noise)
      << "  # sigma [m]; floor = q^2/12 + sigma^2, white\n"
      << "# top_to_floor = " << number(s.top_to_floor) << "  # C_x / floor at the highest point\n"
      << "# usable_band = " << usable_band_line(s) << "\n"
      << "# estimator = " << to_string(s.estimator) << "  # " << words(s.estimator_reason) << "\n";
  for (const AnalysisMessage& note : r.notes) out << "# note = " << words(note.text) << "\n";
  for (const std::string& line : segment_lines(s)) out << line << "\n";
  if (s.estimator == Estimator::welch)
    out << "# welch = Hann window, 50% overlap, " << s.welch.segments << " segments of " << s.welch.segment_samples
        << " samples, first differences divided by 4 sin^2(omega dt/2); bins " << number(s.welch.bin_spacing)
        << " rad/s apart\n# leaky_points = " << s.leaky_points
        << "  # points the window's leakage may bias high (spectrum steeper than the window allows)\n";
}

void slope_and_alpha_lines(std::ostream& out, const AnalysisReport& r) {
  if (r.slope)
    out << "# slope = " << number(r.slope->slope) << "  # +- " << number(r.slope->slope_error)
        << ", C_x ~ omega^slope over " << number(r.slope->omega_low) << " .. " << number(r.slope->omega_high)
        << " rad/s, " << r.slope->points << " points, chi2/dof " << number(r.slope->chi2_per_dof) << "\n"
        << "# slope_fit_ok = " << verdict_line(r.slope_verdict) << "\n"
        << "# force_slope = " << number(r.slope->force_slope()) << "  # +- " << number(r.slope->slope_error)
        << ", M^2 omega^4 C_x ~ omega^force_slope\n";
  if (r.alpha)
    out << "# fitted_alpha = " << number(r.alpha->alpha) << "  # +- " << number(r.alpha->alpha_error) << " over "
        << number(r.alpha->omega_low) << " .. " << number(r.alpha->omega_high) << " rad/s, " << r.alpha->points
        << " points, chi2/dof " << number(r.alpha->chi2_per_dof) << ", theory order " << r.alpha->theory_order << "\n"
        << "# alpha_fit_ok = " << verdict_line(r.alpha_verdict) << "\n";
}

void power_law_lines(std::ostream& out, const PowerLawFit& p, const Verdict& verdict, const std::string& C,
                     const std::string& unit) {
  out << "# power_law = " << C << " = A (omega / " << number(p.pivot) << ")^slope + floor over " << number(p.omega_low)
      << " .. " << number(p.omega_high) << " rad/s, " << p.points << " points, dof " << p.dof << ", chi2/dof "
      << number(p.chi2_per_dof) << "\n# power_law_A = " << number(p.amplitude) << "  # +- " << number(p.amplitude_error)
      << " " << unit << "\n# power_law_slope = " << number(p.slope) << "  # +- " << number(p.slope_error)
      << "\n# power_law_floor = " << number(p.floor) << "  # +- " << number(p.floor_error) << " " << unit
      << (p.floor_given ? ", given (--resolution, --sensor-noise)" : ", fitted") << "\n"
      << "# power_law_correlation = A-slope " << short_number(p.correlation[0][1]) << ", A-floor "
      << short_number(p.correlation[0][2]) << ", slope-floor " << short_number(p.correlation[1][2]) << "\n"
      << "# power_law_fit_ok = " << verdict_line(verdict) << "\n"
      << "# undetermined = " << words(p.undetermined) << "\n";
}

/// A fitted length in the record's unit as well ("a" in um on a record in um), else "".
std::string lab_units(const std::string& name, double value, double error, LengthUnit length) {
  if (name != "a") return "";
  const double per = metres_per(length);
  return " m (" + number(value / per) + " +- " + number(error / per) + " " + to_string(length) + ")";
}

void model_fit_lines(std::ostream& out, const ModelFit& m, const Verdict& verdict, const std::string& compare_case,
                     const std::string& C, const std::string& unit, LengthUnit length) {
  out << "# model_fit = " << C << " = " << compare_case << "'s theory (" << (m.theory_order == 2 ? "second" : "first")
      << " order) + floor over " << number(m.omega_low) << " .. " << number(m.omega_high) << " rad/s, " << m.points
      << " points, dof " << m.dof << ", chi2/dof " << number(m.chi2_per_dof) << (m.converged ? "" : ", NOT converged")
      << "\n";
  for (std::size_t i = 0; i < m.names.size(); ++i)
    out << "# model_fit_" << m.names[i] << " = " << number(m.values[i]) << "  # +- " << number(m.errors[i])
        << (m.names[i] == "floor" ? " " + unit + ", fitted" : "")
        << lab_units(m.names[i], m.values[i], m.errors[i], length) << "\n";
  if (m.floor_given) out << "# model_fit_floor = " << number(m.floor) << "  # " << unit << ", given\n";
  out << "# model_fit_alpha2_over_N = " << number(m.amplitude) << "  # +- " << number(m.amplitude_error)
      << ", the level the band sets\n# model_fit_correlation =";
  for (std::size_t i = 0; i < m.names.size(); ++i)
    for (std::size_t k = i + 1; k < m.names.size(); ++k)
      out << " " << m.names[i] << "-" << m.names[k] << " "
          << short_number(m.covariance[i][k] / std::sqrt(m.covariance[i][i] * m.covariance[k][k]));
  out << "\n# model_fit_ok = " << verdict_line(verdict) << "\n"
      << "# undetermined = " << words(m.undetermined) << "\n";
}

void column_lines(std::ostream& out, const AnalysisReport& r, const std::string& C, const std::string& unit) {
  const bool force = r.spectrum.observable == Observable::force;
  const std::string rate = force ? "C_Fdot = omega^2 C_F [N^2/s]" : "C_v = omega^2 C_x [m^2/s]";
  out << "# columns: omega [rad/s]; " << C << " " << unit << " estimate, mean over the bin's frequencies; stderr "
      << unit << " from the scatter between segments (streaming) or chi-square statistics (welch); floor " << unit
      << " the sensor's white noise q^2/12 + sigma^2 seen through the estimator; below_floor 1 when " << C
      << " < floor + 2 stderr; n_avg; bandwidth [rad/s]; " << rate
      << "; dof equivalent degrees of freedom (stderr = " << C
      << " sqrt(2/dof)); segment FFT length [samples]; leaky 1 when window leakage may bias the point; C_low, "
      << "C_high " << unit << " the error bar, a 95.4% interval (chi-square for welch)";
  if (r.slope) out << "; fit " << unit << " the fitted power law inside its band";
  if (r.power_law)
    out << "; fit " << unit << " the fitted power law plus floor inside its band; residual (" << C << " - fit) / sigma";
  if (r.model_fit)
    out << "; fit " << unit << " the fitted model plus floor inside its band; residual (" << C << " - fit) / sigma";
  if (r.model)
    out << "; theory " << unit << " the model's " << (r.model_order == 2 ? "second" : "first")
        << "-order theory seen through the estimator (no floor)";
  out << "\n# omega\t" << C << "\tstderr\tfloor\tbelow_floor\tn_avg\tbandwidth\t" << (force ? "C_Fdot" : "C_v")
      << "\tdof\tsegment\tleaky\tC_low\tC_high" << (r.slope ? "\tfit" : "")
      << (r.power_law || r.model_fit ? "\tfit\tresidual" : "") << (r.model ? "\ttheory" : "") << "\n";
}

void point_rows(std::ostream& out, const AnalysisReport& r) {
  for (std::size_t k = 0; k < r.spectrum.points.size(); ++k) {
    const AnalysisPoint& p = r.spectrum.points[k];
    out << number(p.omega) << "\t" << number(p.C_x) << "\t" << number(p.standard_error) << "\t" << number(p.noise_floor)
        << "\t" << (p.below_floor ? 1 : 0) << "\t" << number(p.n_avg) << "\t" << number(p.bandwidth) << "\t"
        << number(velocity_spectrum(p.omega, p.C_x)) << "\t" << number(p.dof) << "\t" << p.segment_samples << "\t"
        << (p.leaky ? 1 : 0) << "\t" << number(p.lower) << "\t" << number(p.upper);
    if (r.slope) {
      const bool inside = p.omega >= r.slope->omega_low && p.omega <= r.slope->omega_high;
      out << "\t" << (inside ? number(r.slope->amplitude * std::pow(p.omega, r.slope->slope)) : "nan");
    }
    if (r.power_law) out << "\t" << number(r.power_law->model[k]) << "\t" << number(r.power_law->residuals[k]);
    if (r.model_fit) out << "\t" << number(r.model_fit->model[k]) << "\t" << number(r.model_fit->residuals[k]);
    if (r.model) out << "\t" << number(r.model_values[k]);
    out << "\n";
  }
}

/// The record's unit or force channel, as the summary and a warning about it say it.
std::string unit_words(const AnalysisReport& r) {
  if (r.spectrum.observable == Observable::force) return "the force " + r.record.force_channel;
  return std::string("read in ") + to_string(r.record.unit) +
         (r.record.unit_source == "default" ? " (no unit in its header)"
                                            : " (from " + words(r.record.unit_source) + ")");
}

void print_fits(const AnalysisSource& source, const AnalysisReport& r) {
  if (r.slope && r.slope_verdict.ok)
    std::cerr << "slidespec: C_x ~ omega^(" << r.slope->slope << " +- " << r.slope->slope_error << ") over "
              << r.slope->omega_low << " .. " << r.slope->omega_high << " rad/s (" << r.slope->points
              << " points, chi2/dof " << r.slope->chi2_per_dof << "); force spectrum ~ omega^("
              << r.slope->force_slope() << ")\n";
  if (r.power_law && r.power_law_verdict.ok) {
    const PowerLawFit& p = *r.power_law;
    std::cerr << "slidespec: C_x = A (omega/" << short_number(p.pivot) << ")^s + floor over "
              << short_number(p.omega_low) << " .. " << short_number(p.omega_high)
              << " rad/s: A = " << short_number(p.amplitude) << " +- " << short_number(p.amplitude_error)
              << " m^2 s, s = " << short_number(p.slope) << " +- " << short_number(p.slope_error)
              << ", floor = " << short_number(p.floor) << " +- " << short_number(p.floor_error) << " m^2 s"
              << (p.floor_given ? " (given)" : "") << "; chi2/dof " << short_number(p.chi2_per_dof) << " (" << p.dof
              << " dof)\n";
  }
  if (r.power_law) std::cerr << "slidespec: not determined: " << words(r.power_law->undetermined) << "\n";
  if (r.model_fit && r.model_fit_verdict.ok) {
    const ModelFit& m = *r.model_fit;
    std::cerr << "slidespec: " << source.compare_case << " fitted over " << short_number(m.omega_low) << " .. "
              << short_number(m.omega_high) << " rad/s:";
    const double per = metres_per(r.record.unit);  // a length in the record's unit, as the lab reads it
    for (std::size_t i = 0; i < m.names.size(); ++i)
      std::cerr << (i ? ", " : " ") << m.names[i] << " = "
                << (m.names[i] == "a" ? short_number(m.values[i] / per) + " +- " + short_number(m.errors[i] / per) +
                                            " " + to_string(r.record.unit)
                                      : short_number(m.values[i]) + " +- " + short_number(m.errors[i]));
    std::cerr << "; alpha^2/N = " << short_number(m.amplitude) << " +- " << short_number(m.amplitude_error)
              << "; chi2/dof " << short_number(m.chi2_per_dof) << " (" << m.dof << " dof)\n";
  }
  if (r.model_fit) std::cerr << "slidespec: not determined: " << words(r.model_fit->undetermined) << "\n";
  if (r.alpha && r.alpha_verdict.ok)
    std::cerr << "slidespec: alpha = " << r.alpha->alpha << " +- " << r.alpha->alpha_error << " ("
              << source.compare_case << ", " << r.alpha->omega_low << " .. " << r.alpha->omega_high
              << " rad/s, chi2/dof " << r.alpha->chi2_per_dof << ", "
              << (r.alpha->theory_order == 2 ? "second" : "first") << "-order theory)\n";
}

}  // namespace

std::string analysis_table(const AnalysisSource& source, const AnalysisReport& r) {
  std::ostringstream out;
  if (r.model)
    out << io::metadata_lines(*r.model, source.compare_case);
  else
    out << "# slidespec " << SLIDESPEC_VERSION << "\n";
  const std::string C = r.spectrum.observable == Observable::force ? "C_F" : "C_x";
  const std::string unit = std::string("[") + spectrum_unit(r.spectrum.observable) + "]";
  record_lines(out, source, r);
  slope_and_alpha_lines(out, r);
  if (r.power_law) power_law_lines(out, *r.power_law, r.power_law_verdict, C, unit);
  if (r.model_fit) model_fit_lines(out, *r.model_fit, r.model_fit_verdict, source.compare_case, C, unit, r.record.unit);
  column_lines(out, r, C, unit);
  point_rows(out, r);
  return out.str();
}

void print_messages(const AnalysisReport& r) {
  for (const AnalysisMessage& note : r.notes) std::cerr << "slidespec: note: " << words(note.text) << "\n";
  for (const AnalysisMessage& message : r.warnings) {
    const std::string text = words(message.text);
    if (message.kind == AnalysisMessage::Kind::warning)
      std::cerr << "slidespec: warning: " << text << "\n";
    else if (message.kind == AnalysisMessage::Kind::failed_fit)
      std::cerr << "slidespec: " << text << "\n";
    else
      std::cerr << "slidespec: not a spectrum (marked spectrum_ok = false, exit status 3): " << text << "\n";
  }
}

void print_summary(const AnalysisSource& source, const AnalysisReport& r) {
  const RecordSpectrum& s = r.spectrum;
  const bool force = s.observable == Observable::force;
  std::cerr << "slidespec: " << source.file << ": " << s.samples << " samples every " << s.dt << " s, "
            << unit_words(r);
  if (force)
    std::cerr << "; mean F = " << s.sliding.x0 + s.sliding.v * s.duration / 2 << " N, trend " << s.sliding.v << " +- "
              << s.sliding.v_error << " N/s";
  else
    std::cerr << "; v = " << s.sliding.v << " +- " << s.sliding.v_error << " m/s";
  std::cerr << "\nslidespec: spectrum " << (force ? "C_F [N^2 s]" : "C_x [m^2 s]") << " of the " << s.channel;
  if (r.mu) std::cerr << ", mu = M'/M = " << *r.mu;
  if (s.usable_high > s.usable_low)
    std::cerr << "\nslidespec: usable band " << s.usable_low << " .. " << s.usable_high << " rad/s (top set by "
              << top_set_by(s) << ")";
  else
    std::cerr << "\nslidespec: usable band: " << top_set_by(s);
  std::cerr << "\nslidespec: estimator " << to_string(s.estimator) << " (" << words(s.estimator_reason) << ")";
  if (s.estimator == Estimator::welch)
    std::cerr << ": " << s.welch.segments << " segments of " << s.welch.segment_samples << " samples, dof "
              << short_number(s.points.front().dof) << " at the lowest point, " << short_number(s.points.back().dof)
              << " at the highest";
  std::cerr << "\n";
  print_fits(source, r);
}

}  // namespace slidespec::cli
