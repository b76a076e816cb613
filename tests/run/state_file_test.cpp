// Saved run states: every damaged byte is refused (or, where it changes nothing, gives
// bitwise the original result), truncation is told apart from corruption, and the
// numbers' version is checked on load.
#include <gtest/gtest.h>

#include <cstring>

#include "slidespec/run.hpp"

using namespace slidespec;

namespace {

RunSession small_finished_session() {
  RunRequest request;
  request.omega_min = 100;
  request.omega_max = 1000;
  request.realizations = 16;
  request.seed = 5;
  request.threads = 1;
  RunSession session(ParameterBuilder("reference").build(), request, "reference");
  session.advance({});
  return session;
}

bool same_result(const RunResult& a, const RunResult& b) {
  if (a.points.size() != b.points.size()) return false;
  for (std::size_t k = 0; k < a.points.size(); ++k)
    if (std::memcmp(&a.points[k].C_x, &b.points[k].C_x, sizeof(double)) != 0 ||
        std::memcmp(&a.points[k].standard_error, &b.points[k].standard_error, sizeof(double)) != 0)
      return false;
  return a.complete == b.complete;
}

std::string message_of(const std::string& bytes) {
  try {
    RunSession::load(bytes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(StateFile, EveryFlippedByteIsRefusedOrChangesNothing) {
  const RunSession session = small_finished_session();
  const std::string bytes = session.save();
  const RunResult original = session.result();
  ASSERT_TRUE(same_result(RunSession::load(bytes).result(), original));
  ASSERT_LT(bytes.size(), 20000u) << "keep the state small: the test loads it once per byte and pattern";
  int tried = 0, refused = 0, unchanged = 0;
  for (std::size_t k = 0; k < bytes.size(); ++k)
    for (unsigned char flip : {0x01, 0x80, 0xff}) {
      std::string damaged = bytes;
      damaged[k] = static_cast<char>(static_cast<unsigned char>(damaged[k]) ^ flip);
      ++tried;
      try {
        const RunSession loaded = RunSession::load(damaged);
        if (same_result(loaded.result(), original))
          ++unchanged;
        else
          ADD_FAILURE() << "byte " << k << " ^ " << int(flip) << " accepted with another result";
      } catch (const InputError& e) {
        ++refused;
        const std::string what = e.what();
        EXPECT_TRUE(what.find("corrupt") != std::string::npos || what.find("not a slidespec") != std::string::npos)
            << "byte " << k << ": " << what;
      }
    }
  RecordProperty("tried", tried);
  RecordProperty("refused", refused);
  EXPECT_EQ(refused + unchanged, tried);
  std::printf("state file of %zu bytes: %d single-byte corruptions tried, %d refused, %d accepted unchanged\n",
              bytes.size(), tried, refused, unchanged);
}

TEST(StateFile, TruncationIsToldApartFromCorruption) {
  const std::string bytes = small_finished_session().save();
  for (std::size_t length = 8; length < bytes.size(); ++length) {
    const std::string what = message_of(bytes.substr(0, length));
    EXPECT_NE(what.find("truncated"), std::string::npos) << length << " bytes: " << what;
  }
  EXPECT_NE(message_of(bytes + "x").find("corrupt"), std::string::npos);
  EXPECT_NE(message_of(bytes.substr(0, 5)).find("not a slidespec"), std::string::npos);
}

TEST(StateFile, RefusesAnotherFormatVersion) {
  std::string bytes = small_finished_session().save();
  bytes[8] = 1;  // a format version of the files made before the checksum
  EXPECT_NE(message_of(bytes).find("format version 1"), std::string::npos) << message_of(bytes);
  EXPECT_NE(message_of(bytes).find("corrupt"), std::string::npos) << message_of(bytes);
  bytes[8] = 7;  // any other: the header's checksum fails first
  EXPECT_NE(message_of(bytes).find("corrupt"), std::string::npos) << message_of(bytes);
}

TEST(StateFile, RecordsTheNumericsVersion) {
  // The fingerprint names it, so merge and resume compare it like any parameter.
  const RunSession session = small_finished_session();
  RunRequest request = session.request();
  EXPECT_EQ(session.difference(session.parameters(), request), "");
  const std::string bytes = session.save();
  EXPECT_NE(bytes.find("numerics"), std::string::npos);
}

// The least state a run saves (what a full disk is checked against before any work): for a
// fixed count R, each realization's own mean at every point of its sub-band, its control
// and its speed, R (points + 2 per sub-band) doubles; the saved state holds at least that.
TEST(StateFile, LeastStateBytesAreEachRealizationsOwnMeansControlAndSpeed) {
  const RunSession session = small_finished_session();
  const RunResult result = session.result();
  ASSERT_TRUE(result.complete);
  const double realizations = static_cast<double>(session.request().realizations);
  const double doubles = realizations * static_cast<double>(result.points.size() + 2 * result.sub_bands.size());
  const double least = least_state_bytes(session.parameters(), session.request());
  EXPECT_EQ(least, doubles * sizeof(double));
  EXPECT_GE(static_cast<double>(session.save().size()), least);
}

TEST(Checkpoints, ComeWithinOneBatchOfBeingDue) {
  // Due at every moment: a checkpoint after every batch (one thread: a chunk is a batch),
  // where chunks of 32 batches gave one per 32. The numbers do not change.
  RunRequest request;
  request.omega_min = 100;
  request.omega_max = 1000;
  request.realizations = 64;
  request.threads = 1;
  const Parameters p = ParameterBuilder("reference").build();
  RunSession plain(p, request);
  plain.advance({});
  RunSession checkpointed(p, request);
  RunSession::Control control;
  control.checkpoint_every = 1e-9;
  int saves = 0;
  control.checkpoint = [&](const RunSession& s) {
    ++saves;
    RunSession::load(s.save());  // a loadable state at every checkpoint
  };
  checkpointed.advance(control);
  const std::size_t bands = plan_sub_bands(p, request).size();
  EXPECT_EQ(saves, static_cast<int>(bands * 64 / 8));
  EXPECT_TRUE(same_result(plain.result(), checkpointed.result()));
}

// A resume or merge across drives names the key that differs, by name: a spring's run
// describes keys that a constant force's does not, so the lists do not line up.
TEST(StateFile, ADifferentDriveIsNamedByItsKey) {
  const RunSession force = small_finished_session();
  const Parameters spring = ParameterBuilder("reference").set("drive=spring").set("k_drive=1e4").build();
  const std::string message = force.difference(spring, force.request());
  EXPECT_EQ(message.rfind("drive: ", 0), 0u) << message;
  EXPECT_NE(message.find("spring here"), std::string::npos) << message;
  EXPECT_EQ(force.difference(force.parameters(), force.request()), "");
}
