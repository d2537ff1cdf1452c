// An independent reader checks our files: the foxglove @mcap/core library (from the npm
// registry, installed by scripts/setup.sh into .deps/npm) reads every record of recordings
// written in each compression, validating every CRC, through the stream and through the
// summary's indexes; protobufjs decodes every payload with the schema stored in the file.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/bus/schema.h"
#include "core/record/writer.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "tests/support/test_util.h"

namespace enact::record {
namespace {

const std::string kModules = std::string(ENACT_SOURCE_DIR) + "/.deps/npm/node_modules";

// the number after "key": in the reader's one-line JSON
long long json_number(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\":");
  return at == std::string::npos ? -1 : std::atoll(json.c_str() + at + key.size() + 3);
}

class Interop : public ::testing::TestWithParam<Compression> {
 protected:
  void SetUp() override {
    // under CI (CI=true) the independent check must run: scripts/setup.sh installs Node.js
    if (test::run("command -v node").exit_code != 0) {
      const char* ci = std::getenv("CI");
      if (ci != nullptr && std::string(ci) == "true") FAIL() << "Node.js is absent under CI: run scripts/setup.sh";
      GTEST_SKIP() << "Node.js is absent: the independent MCAP reader (@mcap/core) cannot run (scripts/setup.sh installs it)";
    }
    ASSERT_TRUE(std::filesystem::exists(kModules + "/@mcap/core")) << "@mcap/core is missing from .deps/npm: run scripts/setup.sh";
  }
  test::RunResult read(const std::string& file) {
    return test::run("ENACT_NODE_MODULES=" + kModules + " node " + test::source_path("tests/interop/read_mcap.mjs") + " " + file);
  }
};

// 3000 device states and their 3000 answers, seq 1..3000 each, in chunks of ~32 kB
long long write_recording(const std::string& path, Compression c) {
  WriterOptions o;
  o.compression = c;
  o.chunk_size_bytes = 32 * 1024;
  Writer w(path, o);
  const auto s1 = w.add_schema("enact.msgs.DeviceState", "protobuf", bus::descriptor_set_of(*msgs::DeviceState::descriptor()));
  const auto s2 = w.add_schema("enact.msgs.ForceCommand", "protobuf", bus::descriptor_set_of(*msgs::ForceCommand::descriptor()));
  const auto c1 = w.add_channel(s1, "ffd/state", "protobuf", {{"publisher", "ffd"}});
  const auto c2 = w.add_channel(s2, "ffd/force", "protobuf", {{"publisher", "sim"}});
  w.add_metadata("enact.params", {{"sim.model", "CM1"}});
  w.add_attachment("sim.scene", "application/yaml", "rate_hz: 5000\n", 1);
  msgs::DeviceState state;
  msgs::ForceCommand force;
  long long seq_sum = 0;
  for (int i = 1; i <= 3000; ++i) {
    const std::int64_t t = 200'000LL * i;
    state.mutable_header()->set_seq(static_cast<std::uint64_t>(i));
    state.mutable_header()->set_stamp_ns(t);
    state.mutable_header()->set_source("ffd");
    state.mutable_position()->set_x(1e-3 * i);
    force.mutable_header()->set_seq(static_cast<std::uint64_t>(i));
    force.set_answered_seq(static_cast<std::uint64_t>(i));
    force.mutable_force()->set_z(0.5);
    w.write(c1, static_cast<std::uint32_t>(i), t, t, state.SerializeAsString());
    w.write(c2, static_cast<std::uint32_t>(i), t + 1000, t + 1000, force.SerializeAsString());
    seq_sum += 2LL * i;
  }
  w.close();
  return seq_sum;
}

TEST_P(Interop, McapCoreReadsEveryRecordWithCrcsAndProtobufjsDecodesEveryPayload) {
  test::TempDir dir;
  const std::string file = dir.file("r.mcap");
  const long long seq_sum = write_recording(file, GetParam());
  const test::RunResult r = read(file);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_EQ(json_number(r.out, "messages"), 6000) << r.out;
  EXPECT_EQ(json_number(r.out, "decoded"), 6000) << r.out;
  EXPECT_EQ(json_number(r.out, "seq_sum"), seq_sum) << r.out;  // every header decoded right
  EXPECT_EQ(json_number(r.out, "indexed_messages"), 6000) << r.out;
  EXPECT_EQ(json_number(r.out, "statistics_messages"), 6000) << r.out;
  EXPECT_GT(json_number(r.out, "chunks"), 3) << r.out;
  EXPECT_NE(r.out.find("\"footer\":true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"metadata\":[\"enact.params\"]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"attachments\":[\"sim.scene\"]"), std::string::npos) << r.out;
}

TEST_P(Interop, TheIndependentReaderCatchesACorruptedChunk) {
  test::TempDir dir;
  const std::string file = dir.file("r.mcap");
  write_recording(file, GetParam());
  std::string bytes = test::read_file(file);
  bytes[bytes.size() / 3] = static_cast<char>(bytes[bytes.size() / 3] ^ 0x40);  // inside some chunk
  test::write_file(file, bytes);
  EXPECT_NE(read(file).exit_code, 0);
}

INSTANTIATE_TEST_SUITE_P(Compressions, Interop, ::testing::Values(Compression::none, Compression::lz4, Compression::zstd),
                         [](const auto& param_info) { return std::string(to_string(param_info.param)); });

}  // namespace
}  // namespace enact::record
