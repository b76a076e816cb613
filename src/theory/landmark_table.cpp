// The landmarks each output shows, computed from slidespec/landmarks.def.
#include <functional>
#include <optional>

#include "model/stall.hpp"
#include "slidespec/theory.hpp"

namespace slidespec {

namespace {

LandmarkShown shown_in(const LandmarkRow& row, LandmarkOutput output) {
  return output == LandmarkOutput::tsv ? row.tsv : output == LandmarkOutput::json ? row.json : row.python;
}

/// What a row's value expression reads, computed once and only when asked for.
class Sources {
 public:
  explicit Sources(const Parameters& parameters) : p(parameters) {}
  const Parameters& p;
  const Landmarks& marks() {
    if (!landmarks_) landmarks_ = landmarks(p);
    return *landmarks_;
  }
  const TheoryChoice& choice() {
    if (!choice_) choice_ = best_theory(p);
    return *choice_;
  }

 private:
  std::optional<Landmarks> landmarks_;
  std::optional<TheoryChoice> choice_;
};

using Value = std::variant<double, bool, std::string>;

/// Each row's value, by the row's place in the table.
const std::vector<std::function<Value(Sources&)>>& values() {
  static const std::vector<std::function<Value(Sources&)>> table = {
#define SLIDESPEC_LANDMARK(key, value, unit, tsv, json, python, doc) \
  [](Sources& s) -> Value {                                          \
    [[maybe_unused]] const Parameters& p = s.p;                      \
    [[maybe_unused]] const Landmarks& l = s.marks();                 \
    [[maybe_unused]] const auto holds = [&s] { return s.choice(); }; \
    return Value(value);                                             \
  },
#include "slidespec/landmarks.def"
  };
  return table;
}

}  // namespace

bool outside_first_order(const Parameters& p) {
  const Landmarks l = landmarks(p);
  // Under a spring best_theory names the first order exactly where it holds (its limits reach
  // far beyond the constant force's); otherwise the first order's own eps limit.
  if (p.drive == Drive::spring) return best_theory(p).kind != TheoryKind::first_order;
  return l.forces_can_stall ||
         l.coupling_eps > (p.renewal == Renewal::poisson ? kFirstOrderPoissonEpsMax : kFirstOrderPeriodicEpsMax);
}

const std::vector<LandmarkRow>& landmark_table() {
  static const std::vector<LandmarkRow> rows = {
#define SLIDESPEC_LANDMARK(key, value, unit, tsv, json, python, doc) \
  {#key, unit, LandmarkShown::tsv, LandmarkShown::json, LandmarkShown::python, doc},
#include "slidespec/landmarks.def"
  };
  return rows;
}

std::vector<Landmark> shown_landmarks(const Parameters& p, LandmarkOutput output) {
  Sources sources(p);
  std::vector<Landmark> shown;
  const std::vector<LandmarkRow>& rows = landmark_table();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const LandmarkShown when = shown_in(rows[i], output);
    if (when != LandmarkShown::always && !(when == LandmarkShown::with_spring && p.drive == Drive::spring)) continue;
    Landmark mark{&rows[i], values()[i](sources), ""};
    const std::string note_key = std::string(rows[i].key) + "_note";
    for (std::size_t k = 0; k < rows.size(); ++k)
      if (note_key == rows[k].key) mark.note = std::get<std::string>(values()[k](sources));
    shown.push_back(std::move(mark));
  }
  return shown;
}

}  // namespace slidespec
