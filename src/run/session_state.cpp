// The saved form of a run session (checkpoints, parts of a run) and the merge of parts.
#include <algorithm>
#include <charconv>
#include <cstring>

#include <zlib.h>

#include "run/session.hpp"

namespace slidespec {

using namespace run_detail;

namespace {

constexpr char kStateMagic[8] = {'S', 'L', 'S', 'P', 'R', 'U', 'N', 'S'};
// 2: renewals take effect at their own time inside a step (docs/numerics.md); a state of
// version 1 holds realizations of the time-stepped process and cannot be continued.
// 3: a checksummed envelope (below) and the numerics version in the fingerprint.
// 4: whether the run is a part of a larger one (kept for merge when finished).
constexpr std::uint32_t kStateVersion = 5;
// A batch record's fixed fields: the accumulator's length, the realization and point counts.
constexpr std::uint64_t kSmallestBatchBytes = 24;
// The envelope: magic, version, body length, a checksum of those 20 bytes (so the length
// can be trusted to tell a truncated file from a corrupt one), the body, and a checksum
// of everything before it.
constexpr std::size_t kHeaderBytes = sizeof kStateMagic + 4 + 8 + 4;

std::uint32_t checksum(const char* data, std::size_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  while (size > 0) {
    const auto piece = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(data), piece);
    data += piece;
    size -= piece;
  }
  return static_cast<std::uint32_t>(crc);
}

/// The body of a state file after its envelope is checked; throws InputError saying
/// "truncated" or "corrupt".
std::string open_envelope(const std::string& bytes) {
  if (bytes.size() < sizeof kStateMagic || std::memcmp(bytes.data(), kStateMagic, sizeof kStateMagic) != 0)
    throw InputError("run state: not a slidespec run state file");
  if (bytes.size() < kHeaderBytes)
    throw InputError("run state: truncated (" + std::to_string(bytes.size()) + " bytes, less than its header)");
  util::Reader header(bytes, "run state");
  for (std::size_t i = 0; i < sizeof kStateMagic; ++i) header.get<char>();
  const auto version = header.get<std::uint32_t>();
  const auto length = header.get<std::uint64_t>();
  if (header.get<std::uint32_t>() != checksum(bytes.data(), kHeaderBytes - 4))
    throw InputError(version == 1 || version == 2
                         ? "run state: format version " + std::to_string(version) +
                               " (before checksums) or a corrupt file; this build reads version " +
                               std::to_string(kStateVersion)
                         : "run state: corrupt (its header fails its checksum)");
  if (version != kStateVersion)
    throw InputError("run state: format version " + std::to_string(version) + ", this build reads version " +
                     std::to_string(kStateVersion));
  const std::uint64_t expected = kHeaderBytes + length + 4;
  if (length > bytes.size() || bytes.size() < expected)
    throw InputError("run state: truncated (" + std::to_string(bytes.size()) + " of " + std::to_string(expected) +
                     " bytes)");
  if (bytes.size() > expected)
    throw InputError("run state: corrupt (" + std::to_string(bytes.size() - expected) + " bytes after its end)");
  std::uint32_t stored;
  std::memcpy(&stored, bytes.data() + expected - 4, 4);
  if (stored != checksum(bytes.data(), expected - 4))
    throw InputError("run state: corrupt (its content fails its checksum)");
  return bytes.substr(kHeaderBytes, length);
}

/// The shortest text that reads back as x, as describe() writes parameters: one text per
/// double, so texts compare as the numbers do, and a message quotes what the user typed.
std::string number_text(double x) {
  char text[40];
  return std::string(text, std::to_chars(text, text + sizeof text, x).ptr);
}

/// What makes two runs the same run, as ordered (key, value) text: every parameter and
/// every request field that changes a number, and the program version.
std::vector<std::pair<std::string, std::string>> fingerprint(const Parameters& p, const RunRequest& r) {
  auto fields = describe(p);
  fields.emplace_back("omega_min", number_text(r.omega_min));
  fields.emplace_back("omega_max", number_text(r.omega_max));
  fields.emplace_back("points_per_decade", std::to_string(r.points_per_decade));
  fields.emplace_back("precision", number_text(r.precision));
  fields.emplace_back("duration", number_text(r.duration));
  fields.emplace_back("realizations", std::to_string(r.realizations));
  fields.emplace_back("first_realization", std::to_string(r.first_realization));
  fields.emplace_back("part", r.part ? "1" : "0");
  fields.emplace_back("seed", std::to_string(r.seed));
  fields.emplace_back("control_variate", r.control_variate ? "shadow" : "off");
  fields.emplace_back("numerics", std::to_string(kNumericsVersion));
  fields.emplace_back("version", SLIDESPEC_VERSION);
  return fields;
}

std::string first_difference(const std::vector<std::pair<std::string, std::string>>& here,
                             const std::vector<std::pair<std::string, std::string>>& given,
                             const std::vector<std::string>& ignored = {}) {
  // By key: a spring's run describes keys (drive, k_drive) a constant force's does not.
  const auto value_of = [](const std::vector<std::pair<std::string, std::string>>& fields, const std::string& key) {
    for (const auto& [name, value] : fields)
      if (name == key) return value;
    return std::string("(none)");
  };
  std::vector<std::string> keys;
  for (const auto* fields : {&here, &given})
    for (const auto& field : *fields)
      if (std::find(keys.begin(), keys.end(), field.first) == keys.end()) keys.push_back(field.first);
  for (const std::string& key : keys) {
    if (std::find(ignored.begin(), ignored.end(), key) != ignored.end()) continue;
    const std::string a = value_of(here, key), b = value_of(given, key);
    if (a != b) return key + ": " + a + " there, " + b + " here";
  }
  return "";
}

/// Parameters back from describe(): one of v and eta1 was derived from the other, and
/// only rebuilding from the one that was given reproduces both bit for bit.
Parameters rebuild_parameters(const std::vector<std::pair<std::string, std::string>>& described) {
  for (const char* derived : {"eta1", "v"}) {
    ParameterBuilder builder("reference");
    try {
      for (const auto& [key, value] : described)
        if (key != derived) builder.set(key, value);
      const Parameters p = builder.build();
      if (describe(p) == described) return p;
    } catch (const InputError&) {
    }
  }
  throw InputError("run state: its parameters do not rebuild exactly (made by another version?)");
}

}  // namespace

namespace run_detail {

void put_batch(std::string& bytes, const BatchRecord& batch) {
  util::put_bytes(bytes, batch.spectrum.save());
  util::put<std::uint64_t>(bytes, batch.control.size());
  util::put<std::uint64_t>(bytes, batch.own_mean.empty() ? 0 : batch.own_mean.front().size());
  for (const auto& mean : batch.own_mean)
    for (double x : mean) util::put<double>(bytes, x);
  for (double x : batch.control) util::put<double>(bytes, x);
  for (double x : batch.speed) util::put<double>(bytes, x);
  util::put<std::uint8_t>(bytes, batch.shadow_mean.empty() ? 0 : 1);
  for (const auto& mean : batch.shadow_mean)
    for (double x : mean) util::put<double>(bytes, x);
}

BatchRecord get_batch(util::Reader& in) {
  BatchRecord batch;
  batch.spectrum = SpectrumAccumulator::load(in.get_bytes());
  const auto count = in.get<std::uint64_t>();
  const auto points = in.get<std::uint64_t>();
  if (count > kBatchRealizations || points > 100000 || count * points * sizeof(double) > in.remaining())
    throw InputError("run state: corrupt batch record");
  batch.own_mean.assign(count, std::vector<double>(points));
  for (auto& mean : batch.own_mean)
    for (double& x : mean) x = in.get<double>();
  batch.control.resize(count);
  for (double& x : batch.control) x = in.get<double>();
  batch.speed.resize(count);
  for (double& x : batch.speed) x = in.get<double>();
  if (in.get<std::uint8_t>() != 0) {
    if (count * points * sizeof(double) > in.remaining()) throw InputError("run state: corrupt batch record");
    batch.shadow_mean.assign(count, std::vector<double>(points));
    for (auto& mean : batch.shadow_mean)
      for (double& x : mean) x = in.get<double>();
  }
  return batch;
}

std::uint64_t realizations_in(const std::vector<BatchRecord>& batches) {
  std::uint64_t count = 0;
  for (const BatchRecord& batch : batches) count += batch.control.size();
  return count;
}

}  // namespace run_detail

std::string RunSession::save() const {
  const Impl& s = *impl_;
  std::string bytes;
  const auto fields = fingerprint(s.params, s.request);
  util::put<std::uint64_t>(bytes, fields.size());
  for (const auto& [key, value] : fields) util::put_bytes(bytes, key), util::put_bytes(bytes, value);
  util::put<std::int32_t>(bytes, s.request.threads);
  util::put<std::int32_t>(bytes, static_cast<std::int32_t>(s.request.simd));
  util::put_bytes(bytes, s.case_name);
  util::put<double>(bytes, s.wall_seconds);
  util::put<std::uint64_t>(bytes, s.bands.size());
  for (const BandTotals& totals : s.bands) {
    util::put<std::uint64_t>(bytes, totals.planned);
    util::put<std::int32_t>(bytes, totals.rounds);
    util::put<std::uint8_t>(bytes, totals.finished ? 1 : 0);
    util::put<std::uint64_t>(bytes, totals.batches.size());
    for (const BatchRecord& batch : totals.batches) put_batch(bytes, batch);
  }
  std::string file(kStateMagic, sizeof kStateMagic);
  util::put<std::uint32_t>(file, kStateVersion);
  util::put<std::uint64_t>(file, bytes.size());
  util::put<std::uint32_t>(file, checksum(file.data(), file.size()));
  file += bytes;
  util::put<std::uint32_t>(file, checksum(file.data(), file.size()));
  return file;
}

RunSession RunSession::load(const std::string& bytes) {
  // A damaged file can hold any count or text: whatever it breaks is a bad input.
  try {
    return load_checked(bytes);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(std::string("run state: corrupt file (") + e.what() + ")");
  }
}

RunSession RunSession::load_checked(const std::string& file) {
  const std::string bytes = open_envelope(file);
  util::Reader in(bytes, "run state");
  // Every count is bounded by the bytes that remain before anything is allocated for it.
  std::vector<std::pair<std::string, std::string>> fields(in.get_count(16));
  for (auto& [key, value] : fields) key = in.get_bytes(), value = in.get_bytes();
  auto field = [&](const std::string& key) {
    for (const auto& [k, value] : fields)
      if (k == key) return value;
    throw InputError("run state: no " + key + " recorded");
  };
  if (field("numerics") != std::to_string(kNumericsVersion))
    throw InputError("run state: computed with numerics version " + field("numerics") + ", this build computes with " +
                     std::to_string(kNumericsVersion) + " (a resumed or merged run would not be bitwise); rerun it");
  if (field("version") != SLIDESPEC_VERSION)
    throw InputError("run state: made by slidespec " + field("version") + ", this is " SLIDESPEC_VERSION);
  RunRequest request;
  request.omega_min = std::stod(field("omega_min"));
  request.omega_max = std::stod(field("omega_max"));
  request.points_per_decade = std::stoi(field("points_per_decade"));
  request.precision = std::stod(field("precision"));
  request.duration = std::stod(field("duration"));
  request.realizations = std::stoull(field("realizations"));
  request.first_realization = std::stoull(field("first_realization"));
  request.part = field("part") == "1";
  request.seed = std::stoull(field("seed"));
  request.control_variate = field("control_variate") == "shadow";
  request.threads = in.get<std::int32_t>();
  request.simd = static_cast<SimdPath>(in.get<std::int32_t>());
  const std::vector<std::pair<std::string, std::string>> described(fields.begin(), fields.end() - 12);
  const Parameters params = rebuild_parameters(described);
  auto impl = std::make_unique<Impl>(params, request, in.get_bytes());
  if (fingerprint(params, request) != fields) throw InputError("run state: its request does not rebuild exactly");
  impl->wall_seconds = in.get<double>();
  if (in.get<std::uint64_t>() != impl->bands.size())
    throw InputError("run state: sub-band count does not match its request");
  for (BandTotals& totals : impl->bands) {
    totals.planned = in.get<std::uint64_t>();
    totals.rounds = in.get<std::int32_t>();
    totals.finished = in.get<std::uint8_t>() != 0;
    totals.batches.resize(in.get_count(kSmallestBatchBytes));
    for (BatchRecord& batch : totals.batches) batch = get_batch(in);
    totals.realizations = realizations_in(totals.batches);
  }
  if (!in.at_end()) throw InputError("run state: trailing bytes after the data");
  return RunSession(std::move(impl));
}

std::string RunSession::difference(const Parameters& params, const RunRequest& request) const {
  return first_difference(fingerprint(impl_->params, impl_->request), fingerprint(params, request));
}

RunSession RunSession::merge(std::vector<RunSession> parts) {
  if (parts.empty()) throw InputError("merge: no parts given");
  std::sort(parts.begin(), parts.end(), [](const RunSession& x, const RunSession& y) {
    return x.request().first_realization < y.request().first_realization;
  });
  const auto reference = fingerprint(parts[0].parameters(), parts[0].request());
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const Impl& part = *parts[k].impl_;
    const std::string differs = first_difference(reference, fingerprint(part.params, part.request),
                                                 {"realizations", "first_realization", "part"});
    if (!differs.empty()) throw InputError("merge: parts of different runs (" + differs + ")");
    if (part.request.realizations == 0)
      throw InputError(
          "merge: a part must be a fixed realization range ({realizations_range}), not a "
          "precision-driven run");
    if (!parts[k].finished())
      throw InputError("merge: part " + std::to_string(part.request.first_realization) + ":" +
                       std::to_string(part.request.realizations) + " is incomplete (interrupted?)");
    if (k == 0 && part.request.first_realization != 0)
      throw InputError("merge: realizations 0 to " + std::to_string(part.request.first_realization) +
                       " are missing (the first part starts at " + std::to_string(part.request.first_realization) +
                       ")");
    if (k > 0) {
      const RunRequest& before = parts[k - 1].request();
      const std::uint64_t end = before.first_realization + before.realizations;
      if (part.request.first_realization < end)
        throw InputError("merge: realization ranges overlap (" + std::to_string(before.first_realization) + ":" +
                         std::to_string(before.realizations) + " and " +
                         std::to_string(part.request.first_realization) + ":" +
                         std::to_string(part.request.realizations) + ")");
      if (end % kBatchRealizations != 0 || part.request.first_realization != end)
        throw InputError(
            "merge: realizations " + std::to_string(end) + " to " + std::to_string(part.request.first_realization) +
            " are missing, or a part other than the last ends inside a batch of " + std::to_string(kBatchRealizations));
    }
  }
  RunRequest whole = parts[0].request();
  whole.realizations = 0;
  whole.part = false;
  for (const RunSession& part : parts) whole.realizations += part.request().realizations;
  auto impl = std::make_unique<Impl>(parts[0].parameters(), whole, parts[0].case_name());
  for (RunSession& part : parts) {
    impl->wall_seconds += part.impl_->wall_seconds;
    for (std::size_t b = 0; b < impl->bands.size(); ++b) {
      BandTotals& into = impl->bands[b];
      BandTotals& from = part.impl_->bands[b];
      for (BatchRecord& batch : from.batches) into.batches.push_back(std::move(batch));
      into.realizations += from.realizations;
      into.planned = into.realizations;
      into.rounds = 1;
      into.finished = true;
    }
  }
  return RunSession(std::move(impl));
}

}  // namespace slidespec
