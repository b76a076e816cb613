// Reading a sensor record: the formats a lab's acquisition software writes, and every
// way such a file can be wrong refused with the line that shows it.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <istream>
#include <sstream>

#include "analysis/names.hpp"
#include "analysis/sampling.hpp"
#include "util/numbers.hpp"
#include "util/suggest.hpp"
#include "slidespec/analysis.hpp"

namespace slidespec {

namespace {

// The first word of each unit is its name.
constexpr std::array<detail::Word<LengthUnit>, 16> kLengthWords{{{"m", LengthUnit::m},
                                                                 {"cm", LengthUnit::cm},
                                                                 {"mm", LengthUnit::mm},
                                                                 {"um", LengthUnit::um},
                                                                 {"nm", LengthUnit::nm},
                                                                 {"in", LengthUnit::inch},
                                                                 {"\u00b5m", LengthUnit::um},
                                                                 {"\u03bcm", LengthUnit::um},
                                                                 {"micron", LengthUnit::um},
                                                                 {"microns", LengthUnit::um},
                                                                 {"micrometre", LengthUnit::um},
                                                                 {"micrometres", LengthUnit::um},
                                                                 {"micrometer", LengthUnit::um},
                                                                 {"micrometers", LengthUnit::um},
                                                                 {"inch", LengthUnit::inch},
                                                                 {"inches", LengthUnit::inch}}};

constexpr std::array<detail::Word<ForceUnit>, 20> kForceWords{{{"uN", ForceUnit::uN},
                                                               {"mN", ForceUnit::mN},
                                                               {"N", ForceUnit::N},
                                                               {"kN", ForceUnit::kN},
                                                               {"MN", ForceUnit::MN},
                                                               {"gf", ForceUnit::gf},
                                                               {"kgf", ForceUnit::kgf},
                                                               {"lbf", ForceUnit::lbf},
                                                               {"Pa", ForceUnit::Pa},
                                                               {"kPa", ForceUnit::kPa},
                                                               {"MPa", ForceUnit::MPa},
                                                               {"psi", ForceUnit::psi},
                                                               {"mu", ForceUnit::mu},
                                                               {"\u00b5N", ForceUnit::uN},
                                                               {"\u03bcN", ForceUnit::uN},
                                                               // Instruments (CETR/Bruker UMT) write a
                                                               // force as the mass whose weight it is.
                                                               {"g", ForceUnit::gf},
                                                               {"kg", ForceUnit::kgf},
                                                               {"lb", ForceUnit::lbf},
                                                               {"friction", ForceUnit::mu},
                                                               {"cof", ForceUnit::mu}}};

constexpr const char* kKnownForces = "uN (µN), mN, N, kN, MN, gf (g), kgf (kg), lbf (lb); Pa, kPa, MPa, psi; mu";

/// A time unit's words and the seconds in one of it.
struct TimeWord {
  const char* word;
  double seconds;
};
constexpr std::array<TimeWord, 24> kTimeWords{
    {{"s", 1},          {"sec", 1},        {"secs", 1},           {"second", 1},          {"seconds", 1},
     {"ms", 1e-3},      {"msec", 1e-3},    {"millisecond", 1e-3}, {"milliseconds", 1e-3}, {"us", 1e-6},
     {"\u00b5s", 1e-6}, {"\u03bcs", 1e-6}, {"usec", 1e-6},        {"microsecond", 1e-6},  {"microseconds", 1e-6},
     {"min", 60},       {"mins", 60},      {"minute", 60},        {"minutes", 60},        {"h", 3600},
     {"hr", 3600},      {"hrs", 3600},     {"hour", 3600},        {"hours", 3600}}};

constexpr const char* kKnownTimes = "s (sec), ms (msec), us (µs), min, h (hr)";

constexpr std::array<detail::Word<Observable>, 4> kObservableWords{{{"auto", Observable::automatic},
                                                                    {"displacement", Observable::displacement},
                                                                    {"force", Observable::force},
                                                                    {"slip", Observable::slip}}};

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

/// A length unit as a header writes it, in any case ("mm", "MM", "Microns").
std::optional<LengthUnit> length_unit(const std::string& name) { return detail::find_word(kLengthWords, lower(name)); }

constexpr const char* kKnownLengths = "m, cm, mm, um (µm, microns), nm, in (inch)";

/// Seconds in one time unit of a header (t_ms, Time(sec), time [h]), or 0 when not a time unit.
double seconds_per(const std::string& name) {
  const std::string word = lower(name);
  for (const TimeWord& time : kTimeWords)
    if (word == time.word) return time.seconds;
  return 0;
}

/// A force channel's unit as a header writes it, in any case ("N", "kn", "MPa", "Friction"),
/// except mN and MN: "mn" could be either, a factor 1e9 apart, so it names no unit.
std::optional<ForceUnit> force_unit(const std::string& name) {
  if (const auto exact = detail::find_word(kForceWords, name)) return exact;
  if (lower(name) == "mn") return std::nullopt;
  for (const auto& [word, unit] : kForceWords)
    if (lower(name) == lower(word)) return unit;
  return std::nullopt;
}

/// A number followed by an optional unit ("0.5um", "25 cm2"): the value and the unit's text.
std::pair<double, std::string> number_and_unit(const std::string& text, const std::string& option,
                                               const std::string& example) {
  double value = 0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(begin, end, value);
  std::string unit(stop, end);
  unit.erase(0, unit.find_first_not_of(' '));
  if (error != std::errc() || stop == begin || !std::isfinite(value)) {
    std::string problem;
    if (stop != begin && !util::parse_decimal(std::string(begin, stop), problem))
      throw InputError(option + ": " + problem);
    throw InputError(option + ": '" + text + "' is not a number with an optional unit (e.g. " + example + ")");
  }
  return {value, unit};
}

}  // namespace

LengthUnit parse_length_unit(const std::string& name, const std::string& option) {
  return detail::parse_word(kLengthWords, name, option, "unit",
                            "; a force or stress channel is read with {force_column}");
}

double parse_length(const std::string& text, LengthUnit bare_unit, const std::string& option) {
  const auto [value, unit_name] = number_and_unit(text, option, "0.5, in the record's unit, or 0.5um");
  if (value < 0)
    throw InputError(option + ": '" + text + "' is not a length >= 0 (e.g. 0.5, in the record's unit, or 0.5um)");
  return value * metres_per(unit_name.empty() ? bare_unit : parse_length_unit(unit_name, option));
}

const char* to_string(LengthUnit unit) { return detail::name_of(kLengthWords, unit); }

double metres_per(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::m:
      return 1.0;
    case LengthUnit::cm:
      return 1e-2;
    case LengthUnit::mm:
      return 1e-3;
    case LengthUnit::um:
      return 1e-6;
    case LengthUnit::nm:
      return 1e-9;
    case LengthUnit::inch:
      return 0.0254;
  }
  return 1.0;
}

ForceUnit parse_force_unit(const std::string& name, const std::string& option) {
  if (const auto unit = force_unit(name)) return *unit;
  return detail::parse_word(kForceWords, name, option, "unit", "; a stress needs {contact_area}");
}

const char* to_string(ForceUnit unit) { return detail::name_of(kForceWords, unit); }

namespace {

/// Newtons per unit of a force, pascals per unit of a stress; 0 for mu.
double si_per(ForceUnit unit) {
  constexpr double kStandardGravity = 9.80665;  // [m/s^2]: a gram-force is a gram's weight
  switch (unit) {
    case ForceUnit::uN:
      return 1e-6;
    case ForceUnit::mN:
      return 1e-3;
    case ForceUnit::N:
      return 1;
    case ForceUnit::kN:
      return 1e3;
    case ForceUnit::MN:
      return 1e6;
    case ForceUnit::gf:
      return 1e-3 * kStandardGravity;
    case ForceUnit::kgf:
      return kStandardGravity;
    case ForceUnit::lbf:
      return 0.45359237 * kStandardGravity;
    case ForceUnit::Pa:
      return 1;
    case ForceUnit::kPa:
      return 1e3;
    case ForceUnit::MPa:
      return 1e6;
    case ForceUnit::psi:
      return 0.45359237 * kStandardGravity / (0.0254 * 0.0254);
    case ForceUnit::mu:
      return 0;
  }
  return 0;
}

bool is_stress(ForceUnit unit) {
  return unit == ForceUnit::Pa || unit == ForceUnit::kPa || unit == ForceUnit::MPa || unit == ForceUnit::psi;
}

/// A force unit (not a stress, not mu) as a header or an option writes it.
std::optional<ForceUnit> pure_force_unit(const std::string& name) {
  const auto unit = force_unit(name);
  if (!unit || is_stress(*unit) || *unit == ForceUnit::mu) return std::nullopt;
  return unit;
}

constexpr const char* kKnownPureForces = "uN, mN, N, kN, MN, gf, kgf, lbf";

}  // namespace

double parse_force(const std::string& text, const std::string& option) {
  const auto [value, unit] = number_and_unit(text, option, "1000, in N, or 1.5kN");
  const auto named = unit.empty() ? std::optional(ForceUnit::N) : pure_force_unit(unit);
  if (!named)
    throw InputError(option + ": '" + unit + "' is not a force unit (" + kKnownPureForces + ")" +
                     (lower(unit) == "mn" ? "; mN and MN are a factor 1e9 apart: write which" : ""));
  if (!(value > 0)) throw InputError(option + ": '" + text + "' is not a force > 0");
  return value * si_per(*named);
}

double parse_stress(const std::string& text, const std::string& option) {
  const auto [value, unit] = number_and_unit(text, option, "74e6, in Pa, or 74MPa");
  const auto named = unit.empty() ? std::optional(ForceUnit::Pa) : force_unit(unit);
  if (!named || !is_stress(*named))
    throw InputError(option + ": '" + unit + "' is not a stress unit (Pa, kPa, MPa, psi)");
  if (!(value > 0)) throw InputError(option + ": '" + text + "' is not a stress > 0");
  return value * si_per(*named);
}

double parse_area(const std::string& text, const std::string& option) {
  const auto [value, unit] = number_and_unit(text, option, "0.0025, in m^2, or 25cm2");
  std::string u = lower(unit);
  if (const auto caret = u.find('^'); caret != std::string::npos) u.erase(caret, 1);
  const double scale = u.empty() || u == "m2" ? 1 : u == "cm2" ? 1e-4 : u == "mm2" ? 1e-6 : 0;
  if (scale == 0) throw InputError(option + ": '" + unit + "' is not an area unit (m2, cm2 or mm2)");
  if (!(value > 0)) throw InputError(option + ": '" + text + "' is not an area > 0");
  return value * scale;
}

double parse_stiffness(const std::string& text, double contact_area, const std::string& option) {
  const auto [value, unit] = number_and_unit(text, option, "1e9, in N/m, 0.5kN/um, or 0.002MPa/um with {contact_area}");
  if (!(value > 0)) throw InputError(option + ": '" + text + "' is not a stiffness > 0");
  if (unit.empty()) return value;
  const auto slash = unit.find('/');
  const std::string top = unit.substr(0, slash);
  const std::optional<LengthUnit> per = slash == std::string::npos ? std::nullopt : length_unit(unit.substr(slash + 1));
  const auto named = force_unit(top);
  double force = named && !is_stress(*named) ? si_per(*named) : 0;
  const double stress = named && is_stress(*named) ? si_per(*named) : lower(top) == "gpa" ? 1e9 : 0;
  if (!per || (force == 0 && stress == 0))
    throw InputError(option + ": '" + unit + "' is not a stiffness unit (N/m, kN/mm, N/um...; MPa/um, kPa/um... " +
                     "with {contact_area})");
  if (stress > 0) {
    if (!(contact_area > 0))
      throw InputError(option + ": a stiffness in " + unit +
                       " (stress per length) needs {contact_area} A to become N/m");
    force = stress * contact_area;
  }
  return value * force / metres_per(*per);
}

Observable parse_observable(const std::string& name) {
  return detail::parse_word(kObservableWords, name, "{observable}", "observable");
}

const char* to_string(Observable observable) { return detail::name_of(kObservableWords, observable); }

const char* spectrum_unit(Observable observable) { return observable == Observable::force ? "N^2 s" : "m^2 s"; }
const char* spectrum_name(Observable observable) { return observable == Observable::force ? "C_F" : "C_x"; }

Observable chosen_observable(const RecordFormat& format) {
  if (format.observable != Observable::automatic) return format.observable;
  if (format.machine_stiffness > 0) return Observable::slip;
  return format.force_column.empty() ? Observable::displacement : Observable::force;
}

std::vector<double> observed_values(const Record& record) {
  if (record.observable == Observable::displacement) return record.displacement;
  if (record.observable == Observable::force) return record.force;
  std::vector<double> slip(record.displacement.size());
  for (std::size_t n = 0; n < slip.size(); ++n)
    slip[n] = record.displacement[n] - record.force[n] / record.machine_stiffness;
  return slip;
}

namespace {

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") + 1 - first);
}

/// True while `field` has a bracket or parenthesis it has not closed.
bool open_bracket(const std::string& field) {
  return std::count(field.begin(), field.end(), '(') > std::count(field.begin(), field.end(), ')') ||
         std::count(field.begin(), field.end(), '[') > std::count(field.begin(), field.end(), ']');
}

/// A field as a spreadsheet quotes it ("t (s)", with "" for a quote inside) without its quotes.
std::string unquoted(std::string field) {
  if (field.size() < 2 || field.front() != '"' || field.back() != '"') return field;
  field = field.substr(1, field.size() - 2);
  for (auto at = field.find("\"\""); at != std::string::npos; at = field.find("\"\"", at + 1)) field.erase(at, 1);
  return field;
}

/// Fields of one line: split on commas, else tabs or semicolons, else runs of whitespace
/// (where a unit in brackets stays with its name: "x (mm)", "t [s]"); quotes around a field dropped.
std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  for (const char separator : {',', '\t', ';'}) {
    if (line.find(separator) == std::string::npos) continue;
    std::string field;
    std::istringstream stream(line);
    while (std::getline(stream, field, separator)) fields.push_back(unquoted(trim(field)));
    if (!line.empty() && line.back() == separator) fields.emplace_back();
    return fields;
  }
  std::istringstream stream(line);
  for (std::string field; stream >> field;) {
    if (!fields.empty() && (field[0] == '(' || field[0] == '[' || open_bracket(fields.back())))
      fields.back() += " " + field;
    else
      fields.push_back(field);
  }
  for (std::string& field : fields) field = unquoted(field);
  return fields;
}

/// The whole field as a finite number, or false. from_chars does not accept a leading '+'.
bool parse_number(const std::string& field, double& value) {
  const char* begin = field.data() + (!field.empty() && field[0] == '+' ? 1 : 0);
  const char* end = field.data() + field.size();
  const auto [stop, error] = std::from_chars(begin, end, value);
  return error == std::errc() && stop == end && begin != end && std::isfinite(value);
}

bool is_number(const std::string& field) {
  double ignored;
  if (parse_number(field, ignored)) return true;
  const std::string word = lower(field);
  return word == "nan" || word == "-nan" || word == "inf" || word == "-inf" || word == "infinity";
}

/// A header without its trailing unit in brackets: "F" of "F (N)", "x" of "x [mm]".
std::string without_bracket(const std::string& name) {
  const std::string n = trim(name);
  for (const auto& [open, close] : {std::pair{'(', ')'}, std::pair{'[', ']'}}) {
    const auto start = n.rfind(open);
    if (start != std::string::npos && start > 0 && n.back() == close) return trim(n.substr(0, start));
  }
  return n;
}

std::string hex_byte(int byte) {
  constexpr char kDigits[] = "0123456789abcdef";
  return {kDigits[(byte >> 4) & 0xf], kDigits[byte & 0xf]};
}

std::string column_list(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& name : names) list += (list.empty() ? "" : ", ") + name;
  return list;
}

/// A header name and the unit it carries: "time (s)", "t [ms]", "x_mm", "position [um]";
/// a name that is a unit alone ("nm") has an empty base. The base is in lower case, the
/// unit as written (mN and MN differ).
struct ColumnName {
  std::string base, unit;
};

bool is_known_unit(const std::string& unit) {
  const auto force = force_unit(unit);
  return length_unit(unit).has_value() || seconds_per(unit) > 0 || (force && *force != ForceUnit::mu);
}

/// The text in a header's trailing brackets, as written ("days" of "t (days)"), or empty.
std::string bracket_text(const std::string& name) {
  const std::string n = trim(name);
  for (const auto& [open, close] : {std::pair{'(', ')'}, std::pair{'[', ']'}}) {
    const auto start = n.rfind(open);
    if (start != std::string::npos && n.back() == close) return trim(n.substr(start + 1, n.size() - start - 2));
  }
  return "";
}

ColumnName split_unit(const std::string& name) {
  const std::string n = trim(name);
  if (is_known_unit(n)) return {"", n};
  for (const auto& [open, close] : {std::pair{'(', ')'}, std::pair{'[', ']'}}) {
    const auto start = n.rfind(open);
    if (start != std::string::npos && !n.empty() && n.back() == close) {
      const std::string unit = trim(n.substr(start + 1, n.size() - start - 2));
      if (is_known_unit(unit)) return {lower(trim(n.substr(0, start))), unit};
    }
  }
  for (const char separator : {'_', '/'}) {
    const auto at = n.rfind(separator);
    if (at != std::string::npos && at > 0 && is_known_unit(n.substr(at + 1)))
      return {lower(n.substr(0, at)), n.substr(at + 1)};
  }
  return {lower(n), ""};
}

/// The unit a header writes that analyze does not know, in brackets ("Displ(km)", "t (days)")
/// or after '_' or '/' when the rest is one of `bases` ("x_ft", "time_days"); else empty.
std::string unknown_unit(const std::string& name, std::initializer_list<const char*> bases) {
  if (!split_unit(name).unit.empty()) return "";
  if (const std::string unit = bracket_text(name); !unit.empty()) return lower(unit);
  const std::string n = lower(trim(name));
  for (const char separator : {'_', '/'}) {
    const auto at = n.rfind(separator);
    const std::string unit = at == std::string::npos ? "" : n.substr(at + 1);
    if (!unit.empty() && std::all_of(unit.begin(), unit.end(), [](unsigned char c) { return std::isalpha(c); }) &&
        std::find(bases.begin(), bases.end(), n.substr(0, at)) != bases.end())
      return unit;
  }
  return "";
}

/// The unit a displacement column's header writes that is not a length analyze knows
/// ("Displ(km)", "x [furlong]", "x_ft"), or empty: such a column is never read as metres.
std::string unknown_length_unit(const std::string& name) {
  return unknown_unit(name, {"x", "position", "displacement", "displ", "disp", "pos", "lp_disp", "lp_displ"});
}

/// The same for a time column ("t (days)", "time_fortnights"): never read as seconds.
std::string unknown_time_unit(const std::string& name) {
  const std::string unit = unknown_unit(name, {"t", "time"});
  if (!unit.empty()) return unit;
  // A unit analyze knows that is not a time ("x (mm)" named as the time column).
  const ColumnName c = split_unit(name);
  return !c.unit.empty() && seconds_per(c.unit) == 0 ? c.unit : "";
}

bool is_time_base(const std::string& base) { return base == "t" || base == "time"; }

bool is_time_name(const ColumnName& c) { return is_time_base(c.base) && (c.unit.empty() || seconds_per(c.unit) > 0); }

bool is_displacement_name(const ColumnName& c) {
  // lp_disp: the load point's displacement, as a biaxial rig's acquisition names it.
  static const std::vector<std::string> bases = {"x",        "pos",     "position",        "displacement", "distance",
                                                 "displ",    "disp",    "lp_disp",         "lp_displ",     "slip",
                                                 "lp displ", "lp disp", "sliding distance"};
  const bool unit_ok = c.unit.empty() || length_unit(c.unit).has_value();
  return unit_ok &&
         (std::find(bases.begin(), bases.end(), c.base) != bases.end() || (c.base.empty() && !c.unit.empty()));
}

/// A header naming a friction coefficient, which carries no unit: mu, COF, Friction
/// coefficient, and Friction without a unit (a biaxial rig's mu; a tribometer that writes
/// its friction force as Friction writes the unit too, Friction [uN]).
bool names_coefficient(const std::string& name) {
  const ColumnName c = split_unit(name);
  return (c.base == "friction" && c.unit.empty() && bracket_text(name).empty()) || c.base == "mu" || c.base == "cof" ||
         c.base == "friction coefficient" || c.base == "coefficient of friction" || c.base == "friction_coefficient";
}

/// A header naming a force, a stress or a friction coefficient (Friction, mu, shear_MPa,
/// Normal_stress(MPa), F (N), Fx (g)): never read as a displacement. What it holds, or empty.
std::string force_like(const std::string& name) {
  const std::string n = lower(name);
  for (const char* word :
       {"friction", "stress", "shear", "force", "tau", "sigma", "mpa", "kpa", "(n)", "[n]", "(kn)", "[kn]"})
    if (n.find(word) != std::string::npos) return "a force, stress or friction channel";
  for (const char* unit : {"_n", "_kn", " n", " kn"})
    if (n.size() > std::string(unit).size() && n.ends_with(unit)) return "a force channel";
  if (const auto unit = force_unit(split_unit(name).unit); unit && *unit != ForceUnit::mu)
    return is_stress(*unit) ? "a stress channel" : "a force channel";
  const std::string base = lower(without_bracket(name));
  if (base == "f" || base == "fx" || base == "ff") return "a force channel";
  if (names_coefficient(name) || n.rfind("mu ", 0) == 0 || n.rfind("mu_", 0) == 0 || n.rfind("mu(", 0) == 0)
    return "a friction coefficient";
  return "";
}

/// A column naming a normal load (Normal_stress(MPa), Nor_stress(MPa), effNS_MPa, Fz):
/// what presses the surfaces together, never the friction along them.
bool names_normal_load(const std::string& name) {
  const std::string n = lower(name), base = split_unit(name).base;
  // Biaxial rigs abbreviate: Nor_stress, effNS (the effective normal stress); a
  // tribometer's normal force is its Fz (or Fn).
  const bool abbreviated = base.rfind("nor_", 0) == 0 || base.rfind("nor ", 0) == 0 || base.rfind("norm_", 0) == 0;
  const bool load = n.find("stress") != std::string::npos || n.find("load") != std::string::npos ||
                    n.find("force") != std::string::npos;
  return n.find("normal") != std::string::npos || (abbreviated && load) || base == "effns" || base == "eff_ns" ||
         base == "sigma_n" || base == "sigman" || base == "fz" || base == "fn";
}

/// A unit written in a units row, its brackets dropped: "mm" of "(mm)" or "[mm]".
std::string unbracketed(const std::string& field) {
  const std::string unit = trim(field);
  if (unit.size() >= 2 && ((unit.front() == '(' && unit.back() == ')') || (unit.front() == '[' && unit.back() == ']')))
    return trim(unit.substr(1, unit.size() - 2));
  return unit;
}

/// A row of units below a header (s, mm, g, mm/sec, and an empty field for mu): at least
/// one unit analyze knows, and nothing but units, of other quantities too.
bool is_units_row(const std::vector<std::string>& fields) {
  bool known = false;
  for (const std::string& field : fields) {
    const std::string unit = unbracketed(field);
    if (unit.empty()) continue;
    if (is_known_unit(unit)) {
      known = true;
      continue;
    }
    static const std::vector<std::string> others = {"-", "%",  "deg", "\u00b0", "\u00b0c", "c",   "k",
                                                    "v", "mv", "hz",  "rpm",    "rad",     "a.u."};
    const std::string u = lower(unit);
    const bool other = (u.find('/') != std::string::npos || u.find('^') != std::string::npos ||
                        std::find(others.begin(), others.end(), u) != others.end()) &&
                       u.find(' ') == std::string::npos;
    if (!other) return false;
  }
  return known;
}

/// "0,001;2,5" or "0,001<TAB>2,5": numbers written with a decimal comma.
bool looks_like_decimal_commas(const std::string& line) {
  if (line.find(';') == std::string::npos && line.find('\t') == std::string::npos) return false;
  for (std::size_t k = 1; k + 1 < line.size(); ++k)
    if (line[k] == ',' && std::isdigit(static_cast<unsigned char>(line[k - 1])) &&
        std::isdigit(static_cast<unsigned char>(line[k + 1])))
      return true;
  return false;
}

// A record's line holds a few numbers: a longer one is not a record (/dev/zero, a stream
// without newlines) and ends the read at once.
constexpr std::streamsize kLongestRecordLine = std::streamsize{1} << 16;
// An instrument's preamble runs to some tens of lines; this many without a line of numbers
// is no record, and the lines are kept until the header is known.
constexpr std::size_t kLongestHead = 1000;
// Some 5e7 samples (20 bytes a line): far beyond any lab record, within a machine's memory.
constexpr std::uint64_t kMostRecordBytes = std::uint64_t{1} << 30;

// A spectrum sums squares of a record's values over up to 1e8 samples: values up to this
// keep every sum inside a double (no displacement or force is anywhere near it).
constexpr double kLargestRecordValue = 1e30;

/// A line above a record's first line of numbers, kept until the header is known.
struct HeadLine {
  std::vector<std::string> fields;
  int line_number;
  std::string raw;
};

class RecordReader {
 public:
  RecordReader(const std::string& source, const RecordFormat& format) : source_(source), format_(format) {}

  Record read(std::istream& in) {
    std::string line;
    for (int line_number = 1; read_line(in, line, line_number); ++line_number) {
      if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
      raw_line_ = line;
      const auto comment = line.find('#');
      if (comment != std::string::npos) line.erase(comment);
      line = trim(line);
      if (line.empty()) continue;
      take_line(split_fields(line), line_number);
    }
    // Not one line of numbers: the lines below the header, if any, are data lines gone wrong
    // (decimal commas, most often), refused with their fault.
    if (names_.empty() && !head_.empty()) read_head(0, head_.back().line_number);
    if (names_.empty() || record_.samples() == 0) throw InputError(source_ + ": no data lines");
    if (record_.samples() < 2)
      throw InputError(source_ + ": line " + std::to_string(last_line_) +
                       ": the only sample; a spectrum needs a record of many samples");
    finish();
    return record_;
  }

  /// Named columns of numbers, read as a file with that header is: the same column choices,
  /// units and checks, each sample named by its index.
  Record from_columns(const std::vector<std::string>& names, const std::vector<std::vector<double>>& columns) {
    place_ = "sample";
    if (names.size() != columns.size() || names.empty())
      throw InputError(source_ + ": " + std::to_string(names.size()) + " names for " + std::to_string(columns.size()) +
                       " columns");
    names_ = names;
    for (std::size_t c = 1; c < columns.size(); ++c)
      if (columns[c].size() != columns[0].size())
        throw InputError(source_ + ": column " + names[c] + " has " + std::to_string(columns[c].size()) +
                         " samples, column " + names[0] + " " + std::to_string(columns[0].size()));
    choose_columns(0);
    for (std::size_t k = 0; k < columns[0].size(); ++k)
      take_row(
          [&](int index) {
            const double v = columns[std::size_t(index)][k];
            if (!std::isfinite(v)) fail(int(k), "column " + names_[std::size_t(index)] + " is not a finite number");
            return v;
          },
          int(k));
    if (record_.samples() < 2)
      throw InputError(source_ + ": a spectrum needs a record of many samples, not " +
                       std::to_string(record_.samples()));
    finish();
    return record_;
  }

  /// Samples given as numbers (t empty: format.dt), checked as lines of a file are.
  Record from_samples(const std::vector<double>& time, const std::vector<double>& x) {
    place_ = "sample";
    names_ = {"t", "x"};
    record_.column = names_[1];
    if (!time.empty() && time.size() != x.size())
      throw InputError(source_ + ": " + std::to_string(time.size()) + " times for " + std::to_string(x.size()) +
                       " samples");
    for (std::size_t k = 0; k < x.size(); ++k) {
      const int sample = static_cast<int>(k);
      if (!std::isfinite(x[k])) fail(sample, "x is not a finite number");
      if (!time.empty()) {
        if (!std::isfinite(time[k])) fail(sample, "t is not a finite number");
        take_time(time[k], sample);
      }
      record_.displacement.push_back(bounded(x[k] * metres_per(format_.unit.value_or(LengthUnit::m)), "m", sample));
    }
    if (x.size() < 2)
      throw InputError(source_ + ": a spectrum needs a record of many samples, not " + std::to_string(x.size()));
    finish();
    return record_;
  }

 private:
  /// The next line of `in` (false at its end), refusing a line or a record beyond the caps.
  /// A line ends at LF, CR LF or a CR alone (as old Mac software writes).
  bool read_line(std::istream& in, std::string& line, int line_number) {
    std::streambuf& from = *in.rdbuf();
    line.clear();
    int c = from.sbumpc();
    if (c == std::char_traits<char>::eof()) return false;
    for (; c != std::char_traits<char>::eof() && c != '\n'; c = from.sbumpc()) {
      if (c == '\r') {
        if (from.sgetc() == '\n') from.sbumpc();
        break;
      }
      if (static_cast<std::streamsize>(line.size()) == kLongestRecordLine)
        throw InputError(source_ + ": line " + std::to_string(line_number) + ": longer than " +
                         std::to_string(kLongestRecordLine) + " characters: not a record of numbers");
      // Text records hold no control bytes but tab; a NUL is a binary file, whose bytes
      // would otherwise be echoed back as a header of columns.
      if (c == '\0' || (c < 0x20 && c != '\t' && c != '\f' && c != '\v'))
        throw InputError(source_ + ": line " + std::to_string(line_number) + ": a control byte (0x" + hex_byte(c) +
                         ") at character " + std::to_string(line.size() + 1) + ": not a text record (binary data?)");
      line.push_back(static_cast<char>(c));
    }
    bytes_ += line.size() + 1;
    if (bytes_ > kMostRecordBytes)
      throw InputError(source_ + ": more than " + std::to_string(kMostRecordBytes >> 30) +
                       " GiB: beyond the largest record analyze reads (cut a window of it first)");
    return true;
  }

  [[noreturn]] void fail(int where, const std::string& what) const {
    const std::string hint =
        looks_like_decimal_commas(raw_line_) ? " (decimal commas? write numbers with a point, e.g. sed 's/,/./g')" : "";
    throw InputError(source_ + ": " + place_ + " " + std::to_string(where) + ": " + what + hint);
  }

  void take_line(const std::vector<std::string>& fields, int line_number) {
    if (names_.empty()) {
      if (!std::all_of(fields.begin(), fields.end(), is_number)) {
        if (head_.size() == kLongestHead)
          fail(line_number, std::to_string(kLongestHead) + " lines and not one of numbers: not a record");
        head_.push_back({fields, line_number, raw_line_});
        return;
      }
      read_head(fields.size(), line_number);
    }
    take_data(fields, line_number);
  }

  void take_data(const std::vector<std::string>& fields, int line_number) {
    if (fields.size() != names_.size()) {
      // An export of several steps or runs starts the next one's preamble below the data.
      const bool text = !std::all_of(fields.begin(), fields.end(), is_number);
      fail(line_number, (text ? "a line of text inside the data, " : "") + std::to_string(fields.size()) +
                            " fields, expected " + std::to_string(names_.size()) + " (" + column_list(names_) + ")" +
                            (text ? "; an export of several steps or runs? keep one's lines" : ""));
    }
    take_row([&](int index) { return number(fields, index, line_number); }, line_number);
    last_line_ = line_number;
  }

  /// The lines above the first line of numbers: the header is the last without a number in
  /// it, a units row may follow it, and what precedes it is the preamble an instrument
  /// writes (its settings, the date). A line below the header that holds numbers is a data
  /// line gone wrong, read as one to be refused with its fault.
  void read_head(std::size_t data_fields, int first_data_line) {
    const auto text = [](const HeadLine& line) {
      return std::none_of(line.fields.begin(), line.fields.end(), is_number);
    };
    int header = static_cast<int>(head_.size()) - 1;
    while (header >= 0 && !text(head_[std::size_t(header)])) --header;
    const HeadLine* units = nullptr;
    if (header >= 1 && is_units_row(head_[std::size_t(header)].fields) && text(head_[std::size_t(header) - 1]) &&
        head_[std::size_t(header) - 1].fields.size() == head_[std::size_t(header)].fields.size())
      units = &head_[std::size_t(header--)];
    if (header < 0) {
      const std::size_t count = head_.empty() ? data_fields : head_.front().fields.size();
      for (std::size_t k = 0; k < count; ++k) names_.push_back(std::to_string(k + 1));
      choose_columns(first_data_line);
    } else {
      const HeadLine& names = head_[std::size_t(header)];
      names_ = names.fields;
      if (header > 0)
        record_.notes.push_back("lines " + std::to_string(head_.front().line_number) + "-" +
                                std::to_string(head_[std::size_t(header) - 1].line_number) +
                                " above the header (line " + std::to_string(names.line_number) +
                                ") are the file's preamble, not read");
      if (units) take_units(*units);
      choose_columns(names.line_number);
    }
    const std::string current_line = raw_line_;
    for (std::size_t k = std::size_t(header + (units ? 2 : 1)); k < head_.size(); ++k) {
      raw_line_ = head_[k].raw;
      take_data(head_[k].fields, head_[k].line_number);
    }
    raw_line_ = current_line;
    head_.clear();
  }

  /// Each column's unit from the units row below the header, as if its header named it.
  void take_units(const HeadLine& units) {
    for (std::size_t k = 0; k < names_.size(); ++k) {
      const std::string unit = unbracketed(units.fields[k]);
      if (unit.empty()) continue;
      const std::string in_header = bracket_text(names_[k]);
      if (in_header.empty())
        names_[k] += " (" + unit + ")";
      else if (lower(in_header) != lower(unit))
        fail(units.line_number, "column " + names_[k] + ": its header says " + in_header + ", the units row " + unit);
    }
    record_.notes.push_back("the columns' units are the units row's (line " + std::to_string(units.line_number) + ")");
  }

  /// One sample from the chosen columns, `value(index)` giving a column's number.
  template <class Value>
  void take_row(const Value& value, int where) {
    if (x_index_ >= 0) record_.displacement.push_back(bounded(value(x_index_) * metres_per(record_.unit), "m", where));
    if (force_index_ >= 0) {
      const double normal = normal_index_ >= 0 ? value(normal_index_) : 1;
      record_.force.push_back(bounded(value(force_index_) * normal * newtons_per_, "N", where));
      if (normal_load_per_ > 0) normal_load_sum_ += normal * normal_load_per_;
    }
    if (time_index_ >= 0) take_time(value(time_index_) * seconds_per_time_, where);
  }

  /// `value` in SI `unit`, refused beyond kLargestRecordValue.
  double bounded(double value, const char* unit, int where) const {
    if (std::fabs(value) <= kLargestRecordValue) return value;
    // The value as given, all its digits: 1.0004e+30 rounded to three would read as the limit.
    fail(where, util::format_number(value) + " " + unit + " is beyond " + util::format_number(kLargestRecordValue) +
                    " " + unit + ": its spectrum would leave a double");
  }

  double number(const std::vector<std::string>& fields, int index, int line_number) const {
    double value;
    const std::string& field = fields[static_cast<std::size_t>(index)];
    if (parse_number(field, value)) return value;
    const std::string& name = names_[static_cast<std::size_t>(index)];
    if (field.empty()) fail(line_number, "column " + name + " is empty");
    if (is_number(field)) fail(line_number, "column " + name + ": '" + field + "' is not a finite number");
    fail(line_number, "column " + name + ": '" + field + "' is not a number");
  }

  /// The column headed `name`, or else the one whose header is `name` and a unit in brackets
  /// ("F" for "F (N)", "Displ" for "Displ(microns)"; any case) when only one is.
  int find_column(const std::string& name, const char* option, int line_number) const {
    const std::string wanted = unquoted(trim(name));  // as the header's fields are read
    const auto found = std::find(names_.begin(), names_.end(), wanted);
    if (found != names_.end()) return named_once(static_cast<int>(found - names_.begin()), line_number);
    std::vector<int> matches;
    for (int k = 0; k < static_cast<int>(names_.size()); ++k)
      if (lower(without_bracket(names_[std::size_t(k)])) == lower(wanted) ||
          split_unit(names_[std::size_t(k)]).base == lower(wanted))
        matches.push_back(k);
    if (matches.size() > 1)
      fail(line_number, std::string(option) + ": '" + name + "' names " + std::to_string(matches.size()) +
                            " columns (columns: " + column_list(names_) + "); give the whole header");
    if (matches.empty())
      fail(line_number, std::string(option) + ": no column '" + name + "' (columns: " + column_list(names_) + ")");
    return matches.front();
  }

  /// `index`, refused when another column bears its header: which of two columns named
  /// alike holds the numbers would be a guess.
  int named_once(int index, int line_number) const {
    const std::string& name = names_[static_cast<std::size_t>(index)];
    const auto alike = std::count(names_.begin(), names_.end(), name);
    if (alike > 1)
      fail(line_number, "the header names " + std::to_string(alike) + " columns '" + name + "' (columns: " +
                            column_list(names_) + "); which one is meant would be a guess: rename one");
    return index;
  }

  void choose_columns(int line_number) {
    const int count = static_cast<int>(names_.size());
    if (format_.dt <= 0) {
      if (!format_.time_column.empty()) {
        time_index_ = find_column(format_.time_column, "{time_column}", line_number);
      } else {
        for (int k = 0; k < count && time_index_ < 0; ++k)
          if (is_time_name(split_unit(names_[k]))) time_index_ = k;
        for (int k = 0; k < count && time_index_ < 0; ++k)
          if (const std::string unknown = unknown_unit(names_[k], {"t", "time"});
              !unknown.empty() && (is_time_base(lower(without_bracket(names_[k]))) || bracket_text(names_[k]).empty()))
            fail(line_number,
                 "column " + names_[k] + ": '" + unknown + "' is not a time unit analyze knows (" + kKnownTimes + ")");
        if (time_index_ < 0 && count == 2 && names_[0] == "1") time_index_ = 0;
        if (time_index_ < 0)
          fail(line_number,
               "no time column (columns: " + column_list(names_) + "); name it with {time_column} or give {dt}");
      }
    }
    if (format_.dt > 0)
      for (int k = 0; k < count; ++k)
        if (is_time_name(split_unit(names_[k])))
          fail(line_number, "{dt}: the record has a time column '" + names_[k] +
                                "'; {dt} is for records without one (the time column is read by default)");
    record_.observable = chosen_observable(format_);
    record_.machine_stiffness = format_.machine_stiffness;
    if (record_.observable != Observable::displacement) choose_force_column(line_number);
    // A force record keeps its displacement, when it has one, for the steady segments.
    choose_displacement_column(line_number, record_.observable != Observable::force);
    for (const int chosen : {time_index_, x_index_, force_index_, normal_index_})
      if (chosen >= 0) named_once(chosen, line_number);
    if (time_index_ >= 0) {
      const std::string& name = names_[static_cast<std::size_t>(time_index_)];
      // As with a length, a unit the header names and analyze cannot read is never taken
      // for seconds (a time in ms read as s gives a speed 1000x too low).
      if (const std::string unknown = unknown_time_unit(name); !unknown.empty())
        fail(line_number,
             "time column " + name + ": '" + unknown + "' is not a time unit analyze knows (" + kKnownTimes + ")");
      if (const double seconds = seconds_per(split_unit(name).unit); seconds > 0) seconds_per_time_ = seconds;
    }
  }

  void choose_displacement_column(int line_number, bool needed) {
    const int count = static_cast<int>(names_.size());
    const auto taken = [&](int k) { return k == time_index_ || k == force_index_ || k == normal_index_; };
    if (!format_.column.empty()) {
      x_index_ = find_column(format_.column, "{column}", line_number);
      const std::string& named = names_[static_cast<std::size_t>(x_index_)];
      const std::string holds = force_like(named);
      if (names_normal_load(named))
        fail(line_number, "{column} " + format_.column +
                              ": the header names a normal load, not a displacement; it enters only as mu's normal "
                              "load ({normal_stress_column}), and {column} is the displacement");
      if (!holds.empty())
        fail(line_number, "{column} " + format_.column + ": the header names " + holds +
                              ", not a displacement; give it as {force_column} ({column} is the displacement)");
    } else {
      std::vector<std::string> candidates;
      for (int k = 0; k < count; ++k)
        if (!taken(k) && is_displacement_name(split_unit(names_[k])) && force_like(names_[k]).empty()) {
          if (x_index_ < 0) x_index_ = named_once(k, line_number);
          candidates.push_back(names_[static_cast<std::size_t>(k)]);
        }
      // Two columns that could each be the displacement (x (um), x (mm)): taking the first
      // would be a guess.
      if (candidates.size() > 1)
        fail(line_number, "which column is the displacement: " + column_list(candidates) + "? give {column}");
      if (x_index_ < 0 && needed && count - (time_index_ >= 0 ? 1 : 0) == 1) {
        x_index_ = time_index_ == 0 ? 1 : 0;
        const std::string holds = force_like(names_[static_cast<std::size_t>(x_index_)]);
        if (!holds.empty())
          fail(line_number, "the only column besides time, '" + names_[static_cast<std::size_t>(x_index_)] +
                                "', names " + holds +
                                ", not a displacement; give {force_column} to analyze it as a force (C_F)");
      }
      if (x_index_ < 0 && !needed) return;
      if (x_index_ < 0)
        fail(line_number, "which column is the displacement? give {column} (columns: " + column_list(names_) + ")");
    }
    if (x_index_ == time_index_) fail(line_number, "the displacement column is the time column");
    if (x_index_ == force_index_) fail(line_number, "the displacement column is the force column");
    record_.column = names_[static_cast<std::size_t>(x_index_)];
    const std::string header_unit = split_unit(record_.column).unit;
    if (seconds_per(header_unit) > 0)
      fail(line_number, "column " + record_.column + " is in " + header_unit +
                            ", a time unit: it holds times, not a displacement; give {column}");
    if (format_.unit) {
      if (const auto named = length_unit(header_unit); named && *named != *format_.unit)
        fail(line_number, std::string("{units} ") + to_string(*format_.unit) + " contradicts the header of column " +
                              record_.column + ", which gives " + to_string(*named) + "; leave {units} out");
      record_.unit = *format_.unit;
      record_.unit_source = "{units}";
    } else if (const auto unit = length_unit(header_unit)) {
      record_.unit = *unit;
      record_.unit_source = "header";
    } else if (const std::string unknown = unknown_length_unit(record_.column); !unknown.empty()) {
      fail(line_number, "column " + record_.column + ": '" + unknown + "' is not a length unit analyze knows (" +
                            kKnownLengths + "); give {units}");
    } else {
      record_.unit = LengthUnit::m;
      record_.unit_source = "default";
    }
  }

  /// The unit of force column `name`: its header's, or the one {force_units} gives, which
  /// may not contradict the header.
  ForceUnit choose_force_unit(const std::string& name, int line_number) {
    ForceUnit unit{};
    const std::string header_unit = split_unit(name).unit;
    const auto named = force_unit(header_unit);
    // A length or time in the header is what the column holds, whatever unit is given.
    if (!named && (length_unit(header_unit) || seconds_per(header_unit) > 0))
      fail(line_number, "force column " + name + " is in " + header_unit + ", a " +
                            (length_unit(header_unit) ? "length" : "time") + " unit: it holds " +
                            (length_unit(header_unit) ? "a displacement" : "times") +
                            ", not a force; give {force_column} the column of the force");
    if (format_.force_unit) {
      unit = *format_.force_unit;
      // The header's word decides what the numbers are: an option that says otherwise is a
      // slip of the user's (a uN column read as N is a million times too strong).
      if (named && *named != unit)
        fail(line_number, std::string("{force_units} ") + to_string(unit) + " contradicts the header of column " +
                              name + ", which gives " + to_string(*named) + "; leave {force_units} out");
      if (!named && names_coefficient(name) && unit != ForceUnit::mu)
        fail(line_number, std::string("{force_units} ") + to_string(unit) + " contradicts the header of column " +
                              name +
                              ", which names a friction coefficient mu (no unit); leave {force_units} out (a "
                              "friction force's header names its unit, e.g. Friction [N])");
    } else if (named) {
      unit = *named;
    } else if (names_coefficient(name)) {
      unit = ForceUnit::mu;
    } else if (const std::string unknown = bracket_text(name); !unknown.empty()) {
      fail(line_number, "force column " + name + ": '" + unknown + "' is not a unit analyze knows (" + kKnownForces +
                            "); give {force_units}");
    } else {
      fail(line_number,
           "force column " + name + ": its header names no unit; give {force_units} (" + kKnownForces + ")");
    }
    return unit;
  }

  /// The force channel and what turns it into newtons: its unit, a contact area for a
  /// stress, a normal force or a normal-stress column (and the area) for mu.
  void choose_force_column(int line_number) {
    const int count = static_cast<int>(names_.size());
    if (!format_.force_column.empty()) {
      force_index_ = find_column(format_.force_column, "{force_column}", line_number);
      if (names_normal_load(names_[static_cast<std::size_t>(force_index_)]))
        fail(line_number, "{force_column} " + format_.force_column +
                              ": the header names a normal load, which presses the surfaces together, not the "
                              "friction force along them; give the friction or shear column (columns: " +
                              column_list(names_) + "), this one as {normal_stress_column} for mu");
    } else {
      for (int k = 0; k < count && force_index_ < 0; ++k)
        if (k != time_index_ && !force_like(names_[k]).empty() && !names_normal_load(names_[k])) force_index_ = k;
      if (force_index_ < 0)
        fail(line_number, std::string("the ") + to_string(record_.observable) +
                              " needs a force channel and no column names a force, stress or friction (columns: " +
                              column_list(names_) + "); give {force_column}");
    }
    if (force_index_ == time_index_) fail(line_number, "the force column is the time column");
    const std::string& name = names_[static_cast<std::size_t>(force_index_)];
    const ForceUnit unit = choose_force_unit(name, line_number);
    const double area = format_.contact_area;
    // The unit in words unless the header already writes it.
    std::string made_of = name;
    if (format_.force_unit || split_unit(name).unit.empty()) made_of += std::string(" (") + to_string(unit) + ")";
    const double stress = format_.normal_stress;
    if (stress > 0 && !(area > 0))
      fail(line_number, "{normal_stress}: a normal load needs {contact_area} A (m^2, or 25cm2)");
    if (unit == ForceUnit::mu) {
      if ((format_.normal_force > 0) + (stress > 0) + !format_.normal_stress_column.empty() > 1)
        fail(line_number,
             "{normal_force}, {normal_stress} and {normal_stress_column} each give mu's normal load; "
             "give one");
      if (format_.normal_force > 0) {
        if (area > 0) fail(line_number, "{contact_area}: mu x {normal_force} is a force already; the area is not used");
        newtons_per_ = format_.normal_force;
        made_of += " x normal force " + util::format_number(format_.normal_force) + " N";
      } else if (stress > 0) {
        newtons_per_ = stress * area;
        made_of += " x normal stress " + util::format_number(stress) + " Pa x contact area " +
                   util::format_number(area) + " m^2";
      } else {
        choose_normal_stress_column(line_number);
        const std::string& normal_name = names_[static_cast<std::size_t>(normal_index_)];
        const auto normal_unit = force_unit(split_unit(normal_name).unit);
        if (!normal_unit || !is_stress(*normal_unit))
          fail(line_number,
               "normal-stress column " + normal_name + ": its header names no stress unit (Pa, kPa, MPa or psi)");
        if (!(area > 0))
          fail(line_number, "column " + name + " is a friction coefficient mu: mu x " + normal_name +
                                " is a shear stress; give {contact_area} A (m^2, or 25cm2) to make it a force, or "
                                "{normal_force} FN instead");
        newtons_per_ = si_per(*normal_unit) * area;
        made_of += " x " + normal_name + " x contact area " + util::format_number(area) + " m^2";
      }
      normal_load_per_ = newtons_per_;
    } else {
      if (format_.normal_force > 0 || !format_.normal_stress_column.empty())
        fail(line_number, std::string(format_.normal_force > 0 ? "{normal_force}" : "{normal_stress_column}") +
                              ": the force channel " + name + " is in " + to_string(unit) +
                              ", not a friction coefficient; the normal load is not used");
      if (is_stress(unit)) {
        if (!(area > 0))
          fail(line_number, "column " + name + " is a stress in " + to_string(unit) +
                                "; give {contact_area} A (m^2, or 25cm2) to make it a force in N");
        newtons_per_ = si_per(unit) * area;
        made_of += " x contact area " + util::format_number(area) + " m^2";
      } else {
        if (area > 0 && !(stress > 0))
          fail(line_number, "{contact_area}: the force channel " + name + " is in " + to_string(unit) +
                                ", a force already; the area is not used");
        newtons_per_ = si_per(unit);
      }
      record_.normal_force = stress * area;
    }
    record_.force_channel = made_of;
  }

  void choose_normal_stress_column(int line_number) {
    if (!format_.normal_stress_column.empty()) {
      normal_index_ = find_column(format_.normal_stress_column, "{normal_stress_column}", line_number);
      return;
    }
    std::vector<std::string> candidates;
    for (int k = 0; k < static_cast<int>(names_.size()); ++k) {
      const std::string written = split_unit(names_[k]).unit;
      const auto unit = force_unit(written);
      // A normal force (Fz) is no stress; a header naming no unit is refused below for that.
      if (k != force_index_ && names_normal_load(names_[k]) && (written.empty() || (unit && is_stress(*unit)))) {
        if (normal_index_ < 0) normal_index_ = k;
        candidates.push_back(names_[std::size_t(k)]);
      }
    }
    // A rig may write the applied normal stress and the effective one (less the pore
    // pressure): which one mu was made with is the lab's to say.
    if (candidates.size() > 1)
      fail(line_number,
           "which column is mu's normal stress: " + column_list(candidates) + "? give {normal_stress_column}");
    if (normal_index_ < 0)
      fail(line_number, "column " + names_[static_cast<std::size_t>(force_index_)] +
                            " is a friction coefficient mu; give {normal_force} FN [N], or "
                            "{normal_stress_column} NAME with {contact_area} A");
  }

  // Uniform sampling is what a spectrum of samples assumes: a missing sample (a gap) or
  // a clock jump would fold into the spectrum silently, so both are refused here.
  void finish() {
    if (normal_load_per_ > 0 && !record_.force.empty())
      record_.normal_force = normal_load_sum_ / double(record_.force.size());
    record_.window_hold_share = format_.window ? window_hold_share() : 0.0;
    if (times_.empty()) {
      record_.dt = format_.dt;
      detail::apply_window(record_, format_, source_);
      if (format_.resample == Resampling::median || format_.resample == Resampling::interval)
        throw InputError("{resample}: the record has no time column ({dt}); its samples are uniform");
    } else {
      detail::make_uniform(record_, times_, where_, source_, place_, format_);
    }
    check_slip();
  }

  /// The share of the window's time that lies in holds of the whole record: a hold is slow
  /// only beside the record's sliding, so the segments are the whole record's. A record that
  /// is not uniform without its window (a gap outside it) is not judged.
  double window_hold_share() const {
    if (record_.displacement.empty()) return 0;
    RecordFormat whole = format_;
    whole.window.reset();
    Record full = record_;
    try {
      if (times_.empty())
        full.dt = format_.dt;
      else
        detail::make_uniform(full, times_, where_, source_, place_, whole);
    } catch (const InputError&) {
      return 0;
    }
    const auto [t0, t1] = *format_.window;
    double inside = 0, held = 0;  // [s]
    for (const SteadySegment& s : steady_segments(full)) {
      const double overlap = std::min(s.end, t1) - std::max(s.start, t0);
      if (!(overlap > 0)) continue;
      inside += overlap;
      if (s.kind == SegmentKind::hold) held += overlap;
    }
    return inside > 0 ? held / inside : 0;
  }

  /// The slip x - F/K within the values a record may hold: a stiffness far too small (in
  /// the wrong unit, most often) would make F/K inf or too large to square and sum.
  void check_slip() const {
    if (record_.observable != Observable::slip || record_.force.empty()) return;
    double largest = 0;
    for (const double force : record_.force) largest = std::max(largest, std::fabs(force));
    const double reach = largest / record_.machine_stiffness;
    if (reach <= kLargestRecordValue) return;
    throw InputError(source_ + ": {machine_stiffness} " + util::format_number(record_.machine_stiffness) +
                     " N/m: the slip's F/K reaches " + util::format_number(reach) + " m, beyond the " +
                     util::format_number(kLargestRecordValue) +
                     " m a record may hold (the stiffness in the wrong unit?)");
  }

  void take_time(double t, int line_number) {
    // A record's times are bounded as its values are: times of 1e300 s give intervals and
    // speeds a double cannot hold.
    bounded(t, "s", line_number);
    if (!times_.empty() && !(t > times_.back()))
      fail(line_number, "time " + util::format_number(t) + " s does not increase (previous " +
                            util::format_number(times_.back()) + " s)");
    times_.push_back(t);
    where_.push_back(line_number);
  }

  std::vector<HeadLine> head_;
  std::string source_;
  std::uint64_t bytes_ = 0;  // read so far
  std::string place_ = "line";
  RecordFormat format_;
  std::vector<std::string> names_;
  int time_index_ = -1, x_index_ = -1, force_index_ = -1, normal_index_ = -1;
  double newtons_per_ = 1;  // of the force column's unit (x the normal stress column's value for mu)
  // mu's normal load [N] per unit of its normal-stress column (1 for a constant one); 0: not mu.
  double normal_load_per_ = 0;
  double normal_load_sum_ = 0;
  int last_line_ = 0;
  std::vector<double> times_;  // [s], as read
  std::vector<int> where_;     // the line (or sample) of each time
  double seconds_per_time_ = 1;
  std::string raw_line_;
  Record record_;
};

void check_format(const RecordFormat& format) {
  if (format.dt < 0 || !std::isfinite(format.dt)) throw InputError("{dt}: must be a positive number of seconds");
  if (format.dt > kLargestRecordValue)
    throw InputError("{dt}: " + util::format_number(format.dt) + " s is beyond the " +
                     util::format_number(kLargestRecordValue) + " s a record's times may reach");
  if (!(format.time_tolerance > 0 && format.time_tolerance < kLoosestTimeTolerance))
    throw InputError("{time_tolerance}: must lie between 0 and " + util::format_number(kLoosestTimeTolerance) +
                     " (exclusive), a share of the median interval; a record off by more is not uniform: {resample} "
                     "median interpolates it, {window} T0:T1 picks a stretch");
  if (format.contact_area < 0 || !std::isfinite(format.contact_area))
    throw InputError("{contact_area}: must be an area > 0");
  if (format.normal_force < 0 || !std::isfinite(format.normal_force))
    throw InputError("{normal_force}: must be a force > 0");
  if (format.normal_stress < 0 || !std::isfinite(format.normal_stress))
    throw InputError("{normal_stress}: must be a stress > 0");
  if (format.machine_stiffness < 0 || !std::isfinite(format.machine_stiffness))
    throw InputError("{machine_stiffness}: must be a stiffness > 0");
  const Observable observable = chosen_observable(format);
  if (observable == Observable::slip && !(format.machine_stiffness > 0))
    throw InputError("{observable} slip: the slip x - F/K needs {machine_stiffness} K");
  if (observable != Observable::slip && format.machine_stiffness > 0)
    throw InputError(std::string("{machine_stiffness}: gives the slip x - F/K, but {observable} is ") +
                     to_string(observable) + "; give {observable} slip (or leave it out)");
  if (observable == Observable::displacement) {
    const char* unused = !format.force_column.empty()           ? "{force_column}"
                         : format.force_unit                    ? "{force_units}"
                         : format.contact_area > 0              ? "{contact_area}"
                         : format.normal_force > 0              ? "{normal_force}"
                         : format.normal_stress > 0             ? "{normal_stress}"
                         : !format.normal_stress_column.empty() ? "{normal_stress_column}"
                                                                : nullptr;
    if (unused)
      throw InputError(std::string(unused) +
                       ": applies to a force channel, and the observable is the displacement; give {observable} "
                       "force (its spectrum C_F) or {machine_stiffness} K (the slip x - F/K)");
  }
}

}  // namespace

Record read_record(std::istream& in, const std::string& source, const RecordFormat& format) {
  check_format(format);
  return RecordReader(source, format).read(in);
}

Record record_from_samples(const std::vector<double>& time, const std::vector<double>& x, const RecordFormat& format,
                           const std::string& source) {
  check_format(format);
  if (time.empty() && !(format.dt > 0)) throw InputError(source + ": give the sample times or a positive dt");
  return RecordReader(source, format).from_samples(time, x);
}

Record record_from_columns(const std::vector<std::string>& names, const std::vector<std::vector<double>>& columns,
                           const RecordFormat& format, const std::string& source) {
  check_format(format);
  return RecordReader(source, format).from_columns(names, columns);
}

Record read_record_file(const std::string& path, const RecordFormat& format) {
  if (path == "-") return read_record(std::cin, "stdin", format);
  std::ifstream in(path);
  if (!in) throw FileError(path + ": cannot open");
  return read_record(in, path, format);
}

}  // namespace slidespec
