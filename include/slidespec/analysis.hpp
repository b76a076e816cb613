// Measured sliding-distance records (the paper's experimental half): reading a sensor
// record, removing the mean sliding v t, the spectrum of xi with the sensor's
// quantization floor, the slope of C_x ~ omega^-n and a fit of the model's alpha.
// Method and error bars: docs/analysis.md.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "slidespec/estimator.hpp"
#include "slidespec/parameters.hpp"

namespace slidespec {

/// Unit of a record's displacement column.
enum class LengthUnit { m, cm, mm, um, nm, inch };

/// Parses m|cm|mm|um|nm|in (µm, μm, micron(s), micrometre(s) for um; inch(es) for in);
/// throws InputError naming `option` (an option id in braces, slidespec/options.hpp) and the known units.
LengthUnit parse_length_unit(const std::string& name, const std::string& option = "{units}");
/// A length such as "0.5", "0.5um" or "5e-7 m" in metres; a bare number is in
/// `bare_unit`. Throws InputError naming `option` when it is not a finite length >= 0.
double parse_length(const std::string& text, LengthUnit bare_unit, const std::string& option);
const char* to_string(LengthUnit unit);
/// Metres in one `unit`.
double metres_per(LengthUnit unit);

/// Unit of a record's force channel: a force, a shear stress (a force once multiplied by the
/// contact area) or a friction coefficient (a force once multiplied by the normal force).
/// gf and kgf are the weight of a gram and a kilogram (g_n = 9.80665 m/s^2).
enum class ForceUnit { uN, mN, N, kN, MN, gf, kgf, lbf, Pa, kPa, MPa, psi, mu };
/// Parses uN|mN|N|kN|MN|gf|kgf|lbf|Pa|kPa|MPa|psi|mu (µN for uN, g and kg for gf and kgf,
/// lb for lbf, friction for mu); any case but mN and MN, which differ by 1e9. Throws
/// InputError naming `option` and the known units.
ForceUnit parse_force_unit(const std::string& name, const std::string& option = "{force_units}");
const char* to_string(ForceUnit unit);

/// A force such as "1000", "1000N", "1.5kN" or "200gf" in newtons (a bare number in N); throws
/// InputError naming `option` unless it is finite and > 0.
double parse_force(const std::string& text, const std::string& option);
/// A stress such as "74e6", "74MPa" or "500psi" in Pa (a bare number in Pa); throws
/// InputError naming `option` unless it is finite and > 0.
double parse_stress(const std::string& text, const std::string& option);
/// An area such as "0.0025", "0.0025m2", "25cm2" or "2500mm2" in m^2 (a bare number in m^2);
/// throws InputError naming `option` unless it is finite and > 0.
double parse_area(const std::string& text, const std::string& option);
/// A machine stiffness such as "1e9", "1e9N/m", "0.5kN/um" or "0.002MPa/um" in N/m (a bare
/// number in N/m); a stress per length needs `contact_area` [m^2] > 0. Throws InputError
/// naming `option`.
double parse_stiffness(const std::string& text, double contact_area, const std::string& option);

/// The channel whose spectrum a record is analyzed for (docs/analysis.md, "Channels").
enum class Observable {
  automatic,     ///< slip with a machine stiffness, force with a force column, else displacement
  displacement,  ///< the displacement column x [m]: C_x [m^2 s]
  force,         ///< the force channel F [N] (a stress or mu converted): C_F [N^2 s]
  slip,          ///< the slider's slip x - F/K with K the machine stiffness [m]: C_x [m^2 s]
};
/// Parses auto|displacement|force|slip; throws InputError naming --observable.
Observable parse_observable(const std::string& name);
const char* to_string(Observable observable);
/// "m^2 s" for a displacement or slip, "N^2 s" for a force: the unit of its spectrum.
const char* spectrum_unit(Observable observable);
/// "C_F" for a force, "C_x" for a displacement or slip: the name of its spectrum.
const char* spectrum_name(Observable observable);

/// What to do with sampling that is not uniform (docs/analysis.md).
enum class Resampling {
  automatic,  ///< jitter without a missing sample: interpolate onto the median interval, with a
              ///< note; a gap (an interval over 1.5 medians) is refused
  off,        ///< refuse any interval beyond time_tolerance
  median,     ///< interpolate onto the median interval, gaps included
  interval,   ///< interpolate onto RecordFormat::resample_interval
};

/// How to read a record. Without a header line, columns are named by number ("1", "2", ...).
/// A header name may carry its unit: `t_s`, `Time(sec)`, `t [ms]`, `x_m`, `x (mm)`,
/// `position [um]`, `Friction [uN]`, or the unit alone (`nm`); or a units row below the
/// header gives them. Lines before the header (an instrument's preamble) are skipped.
/// A unit the header names and an option contradicts is refused, as is a time or length
/// unit analyze does not know.
struct RecordFormat {
  std::string column;              ///< displacement column; empty: x, position, displacement or
                                   ///< distance (with or without a unit), else the only non-time column
  std::string time_column;         ///< empty: a column named t or time (any case, any time unit), or column 1 of 2;
                                   ///< its unit from the header, else seconds
  double dt = 0;                   ///< > 0: fixed sampling interval [s], no time column is read
  std::optional<LengthUnit> unit;  ///< the column's unit where its header names none (or one analyze does not
                                   ///< know); neither: metres
  double time_tolerance = 0.01;    ///< largest |interval - median| / median accepted as uniform [-]
  /// Keep the samples with T0 <= t <= T1, in record time [s] (--window T0:T1).
  std::optional<std::pair<double, double>> window;
  /// Sampling irregular beyond time_tolerance (and a rate that changes, with resample_interval).
  Resampling resample = Resampling::automatic;
  double resample_interval = 0;  ///< Resampling::interval: the grid's interval [s]
  Observable observable = Observable::automatic;
  std::string force_column;             ///< empty: the first column naming a force, stress or friction (not a
                                        ///< normal one), when the observable needs a force
  std::optional<ForceUnit> force_unit;  ///< the force column's unit where its header names none
  double contact_area = 0;              ///< [m^2]: turns a stress into a force; 0: none given
  double normal_force = 0;              ///< [N]: turns mu into a force; 0: none given
  double normal_stress = 0;             ///< sigma_n [Pa], constant: with contact_area the normal load (mu's,
                                        ///< and the rig case's); 0: none given
  std::string normal_stress_column;     ///< turns mu into a stress (with contact_area, a force);
                                        ///< empty: a column naming a normal stress, when mu needs one
  double machine_stiffness = 0;         ///< K [N/m]: slip = x - F/K; 0: none given
};

/// RecordFormat::time_tolerance lies in (0, kLoosestTimeTolerance): beyond half an interval
/// a sample is lost, not late.
inline constexpr double kLoosestTimeTolerance = 0.5;

/// A stretch of a record sampled at one rate.
struct SamplingPart {
  double start = 0, end = 0;  ///< first and last sample time [s]
  double interval = 0;        ///< median sampling interval [s]
  std::size_t samples = 0;
};

/// The observable `format` asks for, never automatic: slip with a machine stiffness, force
/// with a force column, else displacement.
Observable chosen_observable(const RecordFormat& format);

/// A uniformly sampled record of displacement x_n = x(t_0 + n dt), of force F_n, or both.
struct Record {
  std::vector<double> displacement;                  ///< x_n [m]; empty when the file has no displacement column
  std::vector<double> force;                         ///< F_n [N]; empty unless the observable needs a force
  Observable observable = Observable::displacement;  ///< the channel analyzed (never automatic)
  std::string force_channel;                         ///< what the force is made of, in words ("Friction (mu) x 1000 N")
  double machine_stiffness = 0;                      ///< K [N/m] of the slip x - F/K
  double normal_force = 0;          ///< mean normal load [N] where the reader knew one (mu's, or sigma_n x A); 0: none
  double dt = 0;                    ///< sampling interval [s]
  double start_time = 0;            ///< t_0 [s]
  std::string column;               ///< the displacement column read
  LengthUnit unit = LengthUnit::m;  ///< the unit the displacement column was read in
  std::string unit_source;          ///< "--units", "header" or "default"
  std::vector<SamplingPart> parts;  ///< the read window's parts of constant rate (one: steady rate)
  double jitter = 0;                ///< largest |interval - median| / median of the samples kept
  bool resampled = false;           ///< interpolated onto the uniform grid
  double interpolation_cut = 0;     ///< resampled: omega above which interpolation filters [rad/s]
  /// Resampled: the input interval that sets interpolation_cut [s], the coarsest median
  /// interval of the parts the record's time span overlaps.
  double interpolation_interval = 0;
  std::vector<std::string> notes;  ///< every choice made about the sampling, in words
  /// Read with a window: the share of its samples that lie in holds of the whole record
  /// (steady_segments of the record read without the window); 0 when not known.
  double window_hold_share = 0;

  std::size_t samples() const { return displacement.empty() ? force.size() : displacement.size(); }
};

/// The analyzed channel of `record`: x_n [m], F_n [N] or the slip x_n - F_n/K [m].
std::vector<double> observed_values(const Record& record);

/// What a stretch of a lab record is (docs/analysis.md, "Segments").
enum class SegmentKind {
  sliding,   ///< steady sliding at one speed: what a spectrum is taken of
  hold,      ///< the load point stopped (speed below 2% of the fastest stretch, or its noise)
  loading,   ///< the speed steady, the force still rising or settling after a start or a hold
  step,      ///< the transition of a velocity step (to, from or between speeds), and the force's
             ///< evolution after it
  reversal,  ///< the sliding direction turning (a reciprocating tribometer's stroke end)
};
const char* to_string(SegmentKind kind);

/// A stretch of a record and what it is.
struct SteadySegment {
  double start = 0, end = 0;  ///< [s], record time
  double mean_speed = 0;      ///< [m/s]
  std::size_t samples = 0;
  bool hold = false;  ///< kind == SegmentKind::hold
  SegmentKind kind = SegmentKind::sliding;
};

/// Splits a record into labelled stretches that cover it end to end, sorted by start: the
/// speeds of blocks of about 1/2048 of the record (at least 32 samples; median of three),
/// grouped while within a factor 1.6 or four scatters (of successive blocks' speeds) of their
/// group's median, holds together; groups of three blocks or more are sliding or holds, the
/// blocks between them a step or a reversal. With a force channel, the start of a sliding
/// stretch where the force's block means lie beyond four scatters of its settled level is
/// loading (after a start or a hold) or step (after another speed).
std::vector<SteadySegment> steady_segments(const Record& record);
/// The samples of `record` with start <= t <= end, as a record of their own.
Record record_window(const Record& record, double start, double end);
/// The longest sliding one of `segments` when other stretches split the record, with a
/// note saying so appended to `notes`; else the record itself.
Record longest_steady(const Record& record, const std::vector<SteadySegment>& segments,
                      std::vector<std::string>& notes);

/// A reciprocating record's strokes: sliding stretches whose direction alternates.
struct Strokes {
  /// The steady middle of each stroke (its sliding stretch without kStrokeEndShare at either
  /// end), as analyzed.
  std::vector<SteadySegment> middles;
  double speed = 0;            ///< mean |speed| of the strokes [m/s]
  double middle_duration = 0;  ///< the shortest middle [s]: every stroke's periodogram has its length
  /// The lowest point a stroke allows: bin 2 of its periodogram, 2 x 2 pi / middle_duration [rad/s].
  double lowest_omega = 0;
};
/// Share of a stroke's sliding stretch left out at each end, where the slider still
/// accelerates or the friction force has not yet settled after the reversal.
inline constexpr double kStrokeEndShare = 0.1;
/// Fewest strokes that make a record reciprocating.
inline constexpr std::size_t kFewestStrokes = 4;

/// The strokes of `segments` when at least kFewestStrokes sliding stretches alternate in
/// direction (reversals between them), and those stretches are most of the sliding; else none.
std::optional<Strokes> find_strokes(const std::vector<SteadySegment>& segments, double dt);
/// Reads CSV, TSV or whitespace-separated text: '#' comments, blank lines, an optional
/// header. Throws InputError naming `source` and the line for a missing column, a field
/// that is not a finite number, a wrong field count, non-increasing time, a gap or jitter
/// beyond `time_tolerance`, or fewer than two samples.
Record read_record(std::istream& in, const std::string& source, const RecordFormat& format);
/// The same from a file ("-": standard input); a file that cannot be opened is an InputError.
Record read_record_file(const std::string& path, const RecordFormat& format);

/// A record given as numbers: x in `format.unit` at times `time` [s] (empty: every
/// format.dt). Checked as read_record checks a file (finite values, uniform increasing
/// time), naming `source` and the sample (from 0) in the InputError.
Record record_from_samples(const std::vector<double>& time, const std::vector<double>& x, const RecordFormat& format,
                           const std::string& source = "record");

/// Named columns of numbers (a time column among them unless format.dt > 0), read as a file
/// with `names` as its header is: the same choice of columns, units from the names or
/// `format`, force channels and checks, each sample named by its index in the InputError.
Record record_from_columns(const std::vector<std::string>& names, const std::vector<std::vector<double>>& columns,
                           const RecordFormat& format, const std::string& source = "record");

/// The mean sliding motion x = x_0 + v (t - t_0) of the observed channel, fitted by least
/// squares (of a force channel: its mean trend, x_0 in N and v in N/s).
struct SlidingFit {
  double v = 0;        ///< mean sliding speed [m/s]
  double v_error = 0;  ///< its standard error, from the scatter of the speeds of blocks [m/s]
  double x0 = 0;       ///< x at t_0 [m]
  double xi_rms = 0;   ///< rms of xi about the line [m]
  int blocks = 0;      ///< blocks behind v_error
};

SlidingFit fit_sliding(const Record& record);
/// xi_n = x_n - x_0 - v n dt of the observed channel [m, or N].
std::vector<double> sliding_fluctuation(const Record& record, const SlidingFit& fit);

/// Friction coefficient of the paper's slider, mu = M'/M: M the mass loading the block
/// (normal force M g), M' the hanging mass pulling it (driving force M' g). Throws
/// InputError unless both are positive.
double friction_coefficient(double normal_load_mass, double driving_mass);

/// Which estimator turns a record into a spectrum.
enum class Estimator {
  automatic,  ///< welch up to kWelchLargestRecord samples, streaming beyond
  welch,      ///< Welch, Hann window, 50% overlap, of the first differences (short records)
  streaming,  ///< the run's estimator: a cascade of segment lengths, 12 segments per point
};
/// Longest record the automatic choice gives to Welch [samples].
inline constexpr std::size_t kWelchLargestRecord = 10'000'000;
/// Parses auto|welch|streaming; throws InputError naming --estimator.
Estimator parse_estimator(const std::string& name);
const char* to_string(Estimator estimator);

struct WelchRequest {
  double omega_min = 0;  ///< [rad/s]; 0: bin 2 of 8 half-overlapping segments (9 x 2 pi / T)
  double omega_max = 0;  ///< [rad/s]; 0: up to the bin below Nyquist
  int points_per_decade = 8;
  std::size_t segment_samples = 0;          ///< 0: chosen from the record length and omega_min
  const std::atomic<bool>* stop = nullptr;  ///< heard between segments (AnalysisRequest::stop)
};

/// One point of a Welch spectrum: the mean over `bins` FFT bins from `first_bin`.
struct WelchPoint {
  double omega = 0;           ///< mean frequency of the bins [rad/s]
  double C = 0;               ///< mean of the bins' estimates [unit^2 s]
  double standard_error = 0;  ///< C sqrt(2 / dof): the chi-square scatter of the estimate
  double dof = 0;             ///< equivalent degrees of freedom (segments, overlap, bins)
  /// The error bar: C's chi-square interval at the two-sigma level (95.4%), asymmetric at
  /// few degrees of freedom, where C +- 2 standard_error would be too short below.
  double lower = 0, upper = 0;
  std::size_t first_bin = 0, bins = 0;
  double leakage = 0;  ///< side-lobe power from the rest of the spectrum / the point's own
  bool leaky = false;  ///< leakage above 0.3 standard errors: the spectrum is steeper than
                       ///< a prewhitened Hann window allows, the point is biased high
};

struct WelchSpectrum {
  std::vector<WelchPoint> points;
  std::size_t segment_samples = 0;  ///< FFT length, a product of 2, 3, 5, 7
  std::size_t segments = 0;         ///< half-overlapping segments averaged
  double dt = 0;                    ///< [s]
  double bin_spacing = 0;           ///< 2 pi / (segment_samples dt) [rad/s]
};

/// The Welch estimate's fixed choices, as a report states them.
inline constexpr const char* kWelchWindow = "hann";
inline constexpr double kWelchOverlap = 0.5;
inline constexpr const char* kWelchPrewhitening = "first differences, divided by 4 sin^2(omega dt / 2)";

/// The segment length welch_spectrum chooses: the longest fast FFT length giving 8
/// half-overlapping segments, longer (down to 4 segments) when omega_min asks for it.
/// Throws InputError naming --omega-min and the lowest omega the record reaches.
std::size_t welch_segment_samples(std::size_t samples, double dt, double omega_min);

/// Welch's estimate (docs/model.md §3 normalisation) of x's spectrum: Hann window, segments
/// overlapping by half, each segment's mean difference removed, the periodogram of the first
/// differences divided by 4 sin^2(omega dt / 2); points on a log grid from bin 2 to the bin
/// below Nyquist, each bin its own point where bins are sparser than the grid.
WelchSpectrum welch_spectrum(const std::vector<double>& x, double dt, const WelchRequest& request);
/// The same of independent pieces of a record (a reciprocating record's strokes): segments of
/// request.segment_samples (0: the longest fast length of the shortest piece) half-overlapping
/// within each piece, all averaged, the pieces' segments counted as independent.
WelchSpectrum welch_spectrum(const std::vector<std::vector<double>>& pieces, double dt, const WelchRequest& request);
/// The mean of `true_spectrum` over each point's bins: what each point estimates.
std::vector<double> welch_expected(const WelchSpectrum& spectrum, const std::function<double(double)>& true_spectrum);

struct AnalysisRequest {
  Estimator estimator = Estimator::automatic;
  double omega_min = 0;  ///< [rad/s]; 0 = the lowest the record length allows
  double omega_max = 0;  ///< [rad/s]; 0 = Nyquist (welch), half of Nyquist (streaming)
  int points_per_decade = 8;
  double resolution = 0;    ///< sensor resolution q [m]; 0 = no quantization floor
  double sensor_noise = 0;  ///< rms white noise of the sensor before quantization [m]
  /// Heard between the analysis's stages and between pieces of its samples, each well within
  /// a second however long the record: once set, the analysis throws AnalysisStopped.
  const std::atomic<bool>* stop = nullptr;
};

/// What an analysis throws when its request's stop is set.
struct AnalysisStopped {};

/// Throws AnalysisStopped once `stop` (none: never) is set.
inline void hear_stop(const std::atomic<bool>* stop) {
  if (stop != nullptr && stop->load(std::memory_order_relaxed)) throw AnalysisStopped{};
}

/// Refuses a band no spectrum can have (a negative or non-finite omega_min or omega_max,
/// omega_min >= omega_max) or points per decade outside 1..100, naming the option; before any
/// record is read. analyze_record checks the same.
void check_band(const AnalysisRequest& request);

/// What `analyze` (and Python's ss.analyze) warns about, from a result's own fields: below
/// this share of the white q^2/12 floor at the top of the band the floor line misleads
/// (RecordSpectrum::top_to_floor), and a mean speed above this [m/s] is faster than any
/// friction experiment the model describes, so the length unit is the likely cause.
inline constexpr double kWhiteFloorShortfall = 0.5;
inline constexpr double kImplausibleSpeed = 1.0;

/// One point of a measured spectrum.
struct AnalysisPoint {
  double omega;                     ///< [rad/s]
  double C_x;                       ///< estimate of the sampled xi's spectrum, mean over the point's bins [m^2 s]
  double standard_error;            ///< from the scatter between the record's segments [m^2 s]
  double noise_floor;               ///< sensor noise q^2/12 + sigma^2, white, seen through the estimator [m^2 s]
  double n_avg;                     ///< periodogram values averaged
  double bandwidth;                 ///< resolution bandwidth [rad/s]
  bool below_floor;                 ///< C_x < noise_floor + 2 standard_error: indistinguishable from sensor noise
  double dof = 0;                   ///< equivalent degrees of freedom of C_x
  double lower = 0, upper = 0;      ///< the error bar, a 95.4% interval [m^2 s] (streaming: +- 2 stderr)
  std::size_t segment_samples = 0;  ///< FFT length behind the point
  bool leaky = false;               ///< window leakage may bias the point (welch only)
};

struct RecordSpectrum {
  std::vector<AnalysisPoint> points;
  Estimator estimator = Estimator::streaming;  ///< the one used (never automatic)
  std::string estimator_reason;                ///< why it was chosen
  SpectrumAccumulator accumulator;             ///< streaming: for expected(), any true spectrum through these bins
  WelchSpectrum welch;                         ///< welch: segments, bins of each point
  int leaky_points = 0;                        ///< points flagged for leakage
  Observable observable = Observable::displacement;  ///< C_x of x or the slip, or C_F of the force
  std::string channel;  ///< the observable in words: "column Displ(microns)", "force Friction (mu) x ..."
  SlidingFit sliding;
  std::size_t samples = 0;
  double dt = 0;                     ///< [s]
  double duration = 0;               ///< samples x dt [s]
  double quantization_variance = 0;  ///< q^2/12 [m^2]
  double sensor_noise_variance = 0;  ///< sigma^2 [m^2]
  /// C_x / floor at the highest point: well below 1 means the quantization error is not
  /// white (a steady ramp read without dither; docs/analysis.md), 0 without a floor.
  double top_to_floor = 0;
  /// The usable band: from the lowest point (set by the record length) to the highest point
  /// below the first one where the floor exceeds a tenth of C_x (or the highest point); 0 .. 0
  /// when the floor exceeds it at the lowest point already (no usable band).
  double usable_low = 0, usable_high = 0;
  /// The record's stretches as steady_segments finds them (empty until the caller sets them),
  /// and its strokes when the spectrum is of a reciprocating record's strokes.
  std::vector<SteadySegment> segments;
  std::optional<Strokes> strokes;
  bool top_set_by_interpolation = false;  ///< a resampled record's band cut where interpolation filters
  double interpolation_interval = 0;      ///< the input interval [s] behind that cut
  bool top_set_by_omega_max = false;      ///< the omega_max asked for, below the estimator's own top
  bool usable_high_set_by_floor = false;  ///< else by the estimator's top (the bin below Nyquist for
                                          ///< welch, half of Nyquist for streaming)
  /// The floor at or above C_x at every point (a resolution in the wrong unit, most often); a
  /// band can also be missing with the floor below C_x, when it exceeds a tenth of it.
  bool floor_above_spectrum = false;
  /// A resolution q was given, yet the displacement's steps are not whole multiples of it: the
  /// sensor reads finer than q, and the q^2/12 floor lies too high.
  bool readings_off_grid = false;

  /// Whether any band is usable (else usable_low = usable_high = 0: the floor covers all).
  bool has_usable_band() const { return usable_high > usable_low; }
  /// A force record's mean [N]: its fitted trend at the middle of the record, where the
  /// trend's error least moves it.
  double mean_force() const { return sliding.x0 + sliding.v * duration / 2; }
};

/// Fits and removes v t, then estimates C_x(omega) with the SpectrumEstimator (one lane,
/// the conventions of docs/model.md §3). Throws InputError when the record is too short
/// for a single point or the band does not fit the sampling.
RecordSpectrum analyze_record(const Record& record, const AnalysisRequest& request);
/// The strokes' middles analyzed as independent pieces of one spectrum: each stroke's own
/// sliding line removed, Welch segments of one common length (the shortest middle) within
/// each stroke, their periodograms averaged over all strokes with degrees of freedom summed
/// (docs/analysis.md, "Reciprocating records"); a note on what was done appended to `notes`.
RecordSpectrum analyze_strokes(const Record& record, const Strokes& strokes, const AnalysisRequest& request,
                               std::vector<std::string>& notes);

/// What each point of `spectrum` reports on average for a process of spectrum `true_spectrum`.
std::vector<double> expected_points(const RecordSpectrum& spectrum, const std::function<double(double)>& true_spectrum);

/// C_x ~ omega^slope over a band: weighted least squares of ln(C_x - floor) on ln omega,
/// over the points of the band that stand out of the floor.
struct SlopeFit {
  double omega_low = 0, omega_high = 0;  ///< the band asked for [rad/s]
  int points = 0;                        ///< points inside it
  double slope = 0;                      ///< exponent of C_x, -n [-]
  double slope_error = 0;                ///< standard error, scaled up by sqrt(chi2/dof) when > 1
  double chi2_per_dof = 0;
  double amplitude = 0;  ///< C_x at omega = 1 rad/s on the fitted line [m^2 s]
  /// Exponent of the force spectrum M^2 omega^4 C_x (docs/model.md §5): slope + 4.
  double force_slope() const { return slope + 4; }
  bool reaches_floor = false;  ///< a point of the band is beyond the usable band
};

/// Throws InputError when the band holds fewer than 3 points.
SlopeFit fit_slope(const RecordSpectrum& spectrum, double omega_low, double omega_high);

/// C_x = amplitude (omega / pivot)^slope + floor over a band, jointly: what a short record's
/// band can determine without a model of the machine. The floor (white, the sensor's) is
/// fitted unless the request gave it (--resolution, --sensor-noise): never taken for motion.
struct PowerLawFit {
  double omega_low = 0, omega_high = 0;       ///< the band [rad/s]
  double pivot = 0;                           ///< geometric centre of the band's points [rad/s]
  int points = 0, dof = 0;                    ///< points fitted (leaky ones left out); points - parameters
  double amplitude = 0, amplitude_error = 0;  ///< C_x at the pivot, without the floor [m^2 s]
  double slope = 0, slope_error = 0;          ///< [-]
  double floor = 0, floor_error = 0;          ///< white level [m^2 s]; error 0 when given
  bool floor_given = false;
  /// Correlations of (amplitude, slope, floor); errors are scaled by sqrt(chi2/dof) when > 1.
  double correlation[3][3] = {};
  double chi2_per_dof = 0;
  /// The slope ended at an end of its search range (kSteepestPowerLawSlope ..
  /// kFlattestPowerLawSlope): the band does not bound it (the fit is no result).
  bool slope_at_search_edge = false;
  std::vector<double> model;      ///< per point of the spectrum (NaN outside the band) [m^2 s]
  std::vector<double> residuals;  ///< (C_x - model) / sigma per point (NaN outside the band)
  std::string undetermined;       ///< what the data cannot determine, in words
};

/// The range fit_power_law searches for the slope: steeper than any friction spectrum
/// (omega^-4 and its force omega^0) by far on both sides.
inline constexpr double kSteepestPowerLawSlope = -10, kFlattestPowerLawSlope = 2;

/// Weighted least squares (weights from the model's level and each point's relative error,
/// iterated), the slope scanned and (amplitude, floor) solved at each, then refined; throws
/// InputError when the band holds fewer points than parameters + 1.
PowerLawFit fit_power_law(const RecordSpectrum& spectrum, double omega_low, double omega_high);

/// Which theory a model comparison or an alpha fit uses.
enum class ModelOrder {
  first,  ///< the exact first-order theory
  best,   ///< the second order (docs/model.md §7) where it can be computed (one touching
          ///< level, a constant force); the first order elsewhere
};

/// The order `order` gives at `params`: 2 where the second-order theory applies, else 1.
int model_order(const Parameters& params, ModelOrder order);

/// alpha of a model case fitted to the measured spectrum: C_x = alpha^2 T(omega) + floor,
/// with T the exact theory at alpha = 1 seen through the estimator's bins and window. With
/// the second order, T depends on alpha through eps (about 1/(1 + eps^2/2) in the omega^-4
/// band, where the first order would bias alpha low by eps^2/4): fitted by iteration.
struct AlphaFit {
  double omega_low = 0, omega_high = 0;  ///< [rad/s]
  int points = 0;
  double alpha = 0;
  double alpha_error = 0;  ///< standard error, scaled up by sqrt(chi2/dof) when > 1
  double chi2_per_dof = 0;
  int theory_order = 1;  ///< the order of the theory fitted
  /// Why the fit is not at the order asked, in words ("" when it is): the refit beyond first
  /// order stopped where no theory beyond first order holds at the alpha found (the random
  /// forces can stall the block) or gave no positive alpha^2; the fit is the last one made.
  std::string order_not_reached;
};

/// The model's spectrum at `params` (its own alpha) seen through the estimator, one value
/// per point of `spectrum`, without the floor: C_x [m^2 s], or for a force the spring's
/// k_drive^2 C_x [N^2 s] (InputError unless drive = spring).
std::vector<double> model_spectrum(const RecordSpectrum& spectrum, const Parameters& params,
                                   ModelOrder order = ModelOrder::best);

/// The band of an alpha fit when none is given: where the data are usable and the model's
/// Eq. (1) omega^-4 holds (5 v/a to omega_c/3), the band the paper's Fig. 6 compares.
/// Throws InputError when the two do not overlap.
std::pair<double, double> default_alpha_band(const RecordSpectrum& spectrum, const Parameters& params);

/// Weighted least squares for alpha^2 over the points in [omega_low, omega_high]; the
/// alpha of `params` is ignored. Throws InputError when the band holds no point.
AlphaFit fit_alpha(const RecordSpectrum& spectrum, const Parameters& params, double omega_low, double omega_high,
                   ModelOrder order = ModelOrder::best);

/// The compared case on the record's terms (docs/analysis.md, "Comparing and fitting a model"):
/// `case_name` with `overrides` ("KEY=VALUE"), its v the record's `measured_speed` [m/s] (when
/// > 0) and, for a machine-driven record (`machine_stiffness` K > 0 [N/m]), drive = spring with
/// k_drive = K; a key the overrides set is kept as set. Each choice made is appended to `notes`.
Parameters record_model(const std::string& case_name, const std::vector<std::string>& overrides, double measured_speed,
                        double machine_stiffness, std::vector<std::string>& notes);
/// The overrides record_model applies: `overrides` and the record's terms after them.
std::vector<std::string> record_terms(const std::vector<std::string>& overrides, double measured_speed,
                                      double machine_stiffness, std::vector<std::string>& notes);
/// The record's mean sliding speed [m/s]: the observed channel's, or for a force the
/// displacement column's (0 when there is none).
double measured_speed(const Record& record, const RecordSpectrum& spectrum);

/// The compared case built from the record and the rig (docs/analysis.md, "The model on a
/// rig's scale"): `--compare-case rig`.
inline constexpr const char* kRigCase = "rig";

/// What a user knows of a rig beyond its record.
struct RigKnowledge {
  double friction_force = 0;  ///< mean friction [N]; 0: the force channel's mean over the stretch analysed
  double slider_mass = 0;     ///< [kg]; 0: not known (the model's M is held)
};

/// A velocity step: the mean friction of the steady sliding on each side of it.
struct FrictionStep {
  double speed_before = 0, speed_after = 0;  ///< [m/s]
  double force_before = 0, force_after = 0;  ///< [N]
  double end_before = 0, start_after = 0;    ///< [s], record time: the step lies between
  double slope() const { return (force_after - force_before) / (speed_after - speed_before); }  ///< dF/dv [N s/m]
};

/// The velocity steps of `record` (with a force channel): consecutive sliding `segments` at
/// different speeds with only a step or loading between them (no hold, no reversal).
std::vector<FrictionStep> friction_steps(const Record& record, const std::vector<SteadySegment>& segments);

/// The friction of a reciprocating record's `strokes` (with a force channel): the mean over
/// their middles of the force signed by the stroke's direction, as friction opposes the
/// sliding and the force reverses with it [N].
double stroke_friction(const Record& record, const Strokes& strokes);

/// What the rig case is built from: the record's measures and the user's knowledge.
struct RigTerms {
  double speed = 0;                      ///< the measured load-point speed v [m/s]
  double friction_force = 0;             ///< mean friction F [N]
  double normal_force = 0;               ///< [N]; 0: not known (only said)
  double machine_stiffness = 0;          ///< K [N/m]
  double slider_mass = 0;                ///< [kg]; 0: not known
  std::vector<FrictionStep> steps;       ///< the record's velocity steps; those next to the stretch analysed set dF/dv
  double start = 0, end = 0;             ///< the stretch analysed [s], record time
  double omega_low = 0, omega_high = 0;  ///< the band the case is compared over [rad/s]
};

/// The model on the rig's scale: drive = spring with k_drive = K, v the measured speed,
/// F_drive the mean friction, F_kin = F - v dF/dv (dF/dv across a velocity step next to the
/// stretch, else held at v dF/dv = 1% of F), and the rest held at stated values (N, M, m,
/// k0 = 1000 K / N, alpha and a as the fit's start); a key `overrides` sets is kept. Each
/// choice is appended to `notes`. Throws InputError without a stiffness or a friction.
Parameters rig_model(const RigTerms& terms, const std::vector<std::string>& overrides, std::vector<std::string>& notes);

/// Model parameters a joint fit can vary (positive reals, fitted in their logarithm).
inline const std::vector<std::string>& fittable_parameters() {
  static const std::vector<std::string> names{"alpha", "a", "k_drive", "k0"};
  return names;
}
/// "alpha,a" into its names; throws InputError naming --fit for an unknown or repeated one.
std::vector<std::string> parse_fit_parameters(const std::string& list);

/// Model parameters fitted jointly to a measured spectrum: C = T(theta) + floor, T the model's
/// theory seen through the estimator (C_x, or k_drive^2 C_x for a force), by Levenberg-Marquardt
/// in log theta with the white floor solved with them (held when the request gave it), weights
/// from the model's level and each point's relative error, iterated.
struct ModelFit {
  std::vector<std::string> names;               ///< fitted model parameters, then "floor" when it was fitted
  std::vector<double> values, errors;           ///< same order; errors scaled by sqrt(chi2/dof) when > 1
  std::vector<std::vector<double>> covariance;  ///< same order and scaling
  double omega_low = 0, omega_high = 0;         ///< [rad/s]
  int points = 0, dof = 0;                      ///< points fitted (leaky ones left out); points - fitted values
  double chi2_per_dof = 0;
  bool converged = false;  ///< the iteration settled (relative chi2 change below 1e-9)
  /// Parameters that ended at the search's edge, a factor 1e4 from their start: the band
  /// does not bound them (the fit is no result).
  std::vector<std::string> at_search_edge;
  double floor = 0, floor_error = 0;  ///< white level [unit^2 s]; error 0 when given
  bool floor_given = false;
  /// alpha^2 / N: the level the band sets when N is not known (alpha is alpha at the given N).
  double amplitude = 0, amplitude_error = 0;
  int theory_order = 1;
  Parameters fitted;              ///< the start with the fitted values
  std::vector<double> theory;     ///< T at the fit per point of the spectrum (no floor)
  std::vector<double> model;      ///< T + floor per point (NaN outside the band)
  std::vector<double> residuals;  ///< (C - model) / sigma per point (NaN outside the band)
  std::string undetermined;       ///< what the data cannot determine, in words
};

/// Fits `names` (a subset of fittable_parameters()) of `start` over [omega_low, omega_high];
/// throws InputError when the band holds fewer points than fitted values + 1, or the model
/// cannot be computed at the start.
ModelFit fit_model(const RecordSpectrum& spectrum, const Parameters& start, const std::vector<std::string>& names,
                   double omega_low, double omega_high, ModelOrder order = ModelOrder::best);

/// One stretch of a synthetic record's drive: the load point at `speed_factor` x the case's v
/// (0: a hold, the slider standing where it is; negative: backwards) for `duration` seconds.
struct DriveStretch {
  double speed_factor = 1;
  double duration = 0;  ///< [s]
};

/// What a displacement sensor records of a simulated slider.
struct SensorRequest {
  double sample_interval = 1e-3;  ///< [s]
  double duration = 1000;         ///< [s]
  double resolution = 0.5e-6;     ///< q [m]; readings are whole multiples of q; 0 = exact
  /// rms white noise added before quantization [m]. At q/2 or more it makes the
  /// quantization error white (q^2/12); without it the error of a steady ramp is not.
  double sensor_noise = 0.25e-6;
  std::uint64_t seed = 1;
  /// drive = spring: record what a rig does, the load point's position v t (read by this
  /// sensor) and the spring's force F_drive - k_drive xi [N], for the slip x - F/K. With a
  /// program, each speed f v is the case with its contacts kept (eta1), so the force's mean is
  /// the steady friction F_kin + f (F_drive - F_kin); in a hold the force stands (the model
  /// does not relax a standing slider through the spring).
  bool load_point = false;
  /// The drive, stretch after stretch (holds, velocity steps, strokes); empty: the case's v
  /// for `duration`. Given, it sets the record's length and `duration` is not read.
  std::vector<DriveStretch> program;
};

/// A reciprocating tribometer's drive: `strokes` strokes of `stroke_length` [m] at the case's
/// speed `v` [m/s], alternating in direction (the first forwards), with a hold of `dwell` [s]
/// at each reversal. Throws InputError naming {strokes}, {stroke_length} or {dwell}.
std::vector<DriveStretch> stroke_program(double strokes, double stroke_length, double v, double dwell);

/// Simulates one realization of the model with the library's stepper (time step = the
/// sample interval, exact for any step) and returns x = v t + xi as the sensor reads it.
/// With a program, each stretch at speed f v is the case at that speed (eta1 scaled by 1/f,
/// the forces kept; one realization per speed, continued where the speed returns), and
/// backwards the slider's fluctuation is mirrored: x = the load point's path + sign(f) xi.
/// A program's speeds are warmed up over 10 renewals first, so that every stretch is stationary.
/// Throws InputError naming {program} where a rig's speed would let the random forces stall it.
Record synthesize_record(const Parameters& params, const SensorRequest& sensor);

/// The record as CSV: '#' lines from `comments`, a header "t,x", time in s, x in `unit`, and
/// the force F in N when the record has one.
std::string record_csv(const Record& record, LengthUnit unit, const std::string& comments);

// ---------------------------------------------------------------------------------------
// An analysis as one call: what `slidespec analyze` and Python's ss.analyze both do.

/// What is asked of a record beyond reading it: its spectrum, and the fits made to it.
struct AnalysisPlan {
  AnalysisRequest request;
  /// The record was read through a window (RecordFormat::window): analyzed whole, with a note
  /// when it holds several steady stretches; else its longest steady stretch is analyzed.
  bool windowed = false;
  std::optional<std::pair<double, double>> slope_band;  ///< fit C_x ~ omega^slope over LO HI [rad/s]
  std::string compare_case;                             ///< a model case compared with the data; "" none
  std::vector<std::string> overrides;                   ///< KEY=VALUE over compare_case
  /// "" none, "alpha" (the compared case's), "power-law", or model parameters fitted jointly
  /// ("alpha,a", any of fittable_parameters()).
  std::string fit;
  /// The fit's band [rad/s]; none: every point for a power law, the usable band for a model
  /// fit, default_alpha_band() for alpha.
  std::optional<std::pair<double, double>> fit_band;
  ModelOrder order = ModelOrder::best;
  double normal_mass = 0, driving_mass = 0;  ///< M and M' [kg] for mu = M'/M; 0: not given
  RigKnowledge rig;                          ///< for compare_case kRigCase
  /// How the front end read request.resolution and sensor_noise: a bare number in the
  /// record's unit (the command line), else in metres always (Python); a warning says which.
  bool bare_lengths_in_record_unit = true;
};

/// Refuses a plan no record can satisfy, naming the option, before any record is read: a
/// band that is none, masses that give no mu, a fit of what none varies, a fit that needs a
/// compared case without one, two power-law fits, a compared case that cannot be built (with
/// a machine stiffness `machine_stiffness` [N/m] > 0, driven through it).
void check_plan(const AnalysisPlan& plan, double machine_stiffness);

/// Whether a fit (or the spectrum) describes the data (docs/analysis.md, "Judging a fit").
struct Verdict {
  bool ok = true;
  std::string reason;  ///< why not, in words ("" when ok)
};

/// What an analysis tells its reader besides its numbers. The text names options as "{id}"
/// (slidespec/options.hpp), which each front end words with worded().
struct AnalysisMessage {
  enum class Kind {
    note,        ///< a choice made for the user (a window, a resampling, a model's terms)
    warning,     ///< the numbers hold less than they seem (a floor, a unit, leakage)
    failed_fit,  ///< a fit does not describe the data: the result is marked not ok
    no_spectrum  ///< the spectrum is none (inf, nan or 0 everywhere): marked not ok
  };
  Kind kind = Kind::note;
  /// What it is about, one word: "sampling", "window", "model_terms", "implausible_speed",
  /// "no_usable_band", "floor_not_white", "leaky_points", "slope_reaches_floor", "slope",
  /// "alpha", "power-law", "model", "spectrum".
  std::string topic;
  std::string text;
  std::vector<std::pair<std::string, double>> fields;  ///< the numbers it is about, by name
};

/// A record analyzed: its spectrum, each fit asked for with its verdict, and the messages.
struct AnalysisReport {
  AnalysisRequest request;              ///< the plan's request
  Record record;                        ///< the samples analyzed (a window or a steady stretch of the input)
  std::vector<SteadySegment> segments;  ///< the input record's steady stretches
  RecordSpectrum spectrum;
  Verdict spectrum_verdict;  ///< whether the spectrum is one
  std::optional<double> mu;  ///< M'/M when the masses were given
  std::optional<SlopeFit> slope;
  std::optional<PowerLawFit> power_law;
  std::optional<ModelFit> model_fit;  ///< model parameters fitted jointly
  std::optional<AlphaFit> alpha;
  Verdict slope_verdict, power_law_verdict, model_fit_verdict, alpha_verdict;
  std::optional<Parameters> model;        ///< the compared case on the record's terms, at the fitted values
  std::vector<double> model_values;       ///< its theory seen through the estimator, per point
  int model_order = 1;                    ///< the theory order of model_values
  std::vector<AnalysisMessage> notes;     ///< the choices made, in order
  std::vector<AnalysisMessage> warnings;  ///< warnings, then failed fits, then a spectrum that is none

  /// The spectrum is one and every fit describes the data.
  bool ok() const;
  /// Why not ok, the first reason of: the spectrum, the model fit, the power law, alpha, the slope.
  std::string failure() const;
  /// The time of the last sample analysed [s, record time] (the first is record.start_time).
  double end_time() const;
};

/// The analysis of `record` as `plan` asks: its steady stretch (unless windowed), the
/// spectrum, the fits with their verdicts, the compared model, notes and warnings. Throws
/// InputError for a plan check_plan refuses or a record too short for the band.
AnalysisReport analyze(Record record, const AnalysisPlan& plan);

/// What sets the top of the usable band, in words: the sensor floor, the interpolation
/// filter of a resampled record, the estimator's top or the omega_max asked for.
std::string top_set_by(const RecordSpectrum& spectrum);

}  // namespace slidespec
