// The MCAP writer's own properties: the bytes it writes for a fixed input are the ones the
// writer wrote before chunks went to a worker thread (tests/record/data, made by the writer of
// commit 6c3fc58), writing a message allocates nothing once the writer is warm, and a worker's
// failed write leaves a file with no hole.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "core/record/reader.h"
#include "core/record/writer.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::record {
namespace {

using test::read_file;
using test::source_path;
using test::TempDir;

// the compressors the reference files were made with (Debian 12's): compressed bytes are
// only comparable from the same versions
constexpr std::string_view kReferenceZstd = "1.5.4", kReferenceLz4 = "1.9.4";

// a fixed input through every path of the writer: a schema-less channel beside two with
// schemas, payloads of 0 to 149 bytes, log times out of order and some negative, chunks
// closed by duration (1 ms apart, by a write past the span and by flush_if_due), by size
// (10 us apart), and by flush(); a schema, a channel, metadata and an attachment added while
// a chunk is open
void write_fixed_input(const std::string& path, Compression compression) {
  WriterOptions o;
  o.compression = compression;
  o.chunk_size_bytes = 6000;
  o.chunk_duration_ns = 40'000'000;
  o.profile = "enact-test";
  Writer w(path, o);
  const std::uint16_t state = w.add_schema("enact.msgs.DeviceState", "protobuf", std::string("\x0a\x03x.y\x00", 6));
  std::vector<std::uint16_t> channels = {w.add_channel(state, "ffd/state", "protobuf", {{"publisher", "ffd"}}),
                                         w.add_channel(0, "raw", "", {})};
  w.add_metadata("enact.graph", {{"graph", "fixed"}, {"clock", "real"}});
  std::int64_t time_ns = -3'000'000;
  for (int i = 0; i < 1200; ++i) {
    if (i == 400) {
      const std::uint16_t force = w.add_schema("enact.msgs.ForceCommand", "protobuf", "descriptor");
      channels.push_back(w.add_channel(force, "ffd/force", "protobuf", {{"publisher", "sim"}}));
      w.add_attachment("sim.scene", "application/yaml", "contact: {}\n", 5, 6);
    }
    if (i == 700) w.flush();
    if (i == 900) w.add_metadata("enact.params", {{"rate_hz", "5000"}});
    if (i % 250 == 249) w.flush_if_due(time_ns + 50'000'000);
    time_ns += i < 600 ? 1'000'000 : 10'000;
    const std::int64_t jitter_ns = (i * 7919 % 13 - 6) * 20'000;
    std::string payload(static_cast<std::size_t>(i * 37 % 150), '\0');
    for (std::size_t k = 0; k < payload.size(); ++k) payload[k] = static_cast<char>(k < 40 ? i * 31 + k * 7 : k % 11);
    const std::uint16_t channel = channels[static_cast<std::size_t>(i * 5 % 7) % channels.size()];
    w.write(channel, static_cast<std::uint32_t>(i + 1), time_ns + jitter_ns, time_ns - 1'000, payload);
  }
  w.close();
}

std::string reference_path(Compression c) { return source_path("tests/record/data/fixed_" + std::string(to_string(c)) + ".mcap"); }

// every message as the reader gives it back: topic, sequence, times and data
std::vector<std::string> messages_of(const std::string& path) {
  Reader r(path);
  std::vector<std::string> out;
  r.for_each([&](const Message& m) {
    out.push_back(std::string(m.topic) + " " + std::to_string(m.sequence) + " " + std::to_string(m.log_time_ns) + " " +
                  std::to_string(m.publish_time_ns) + " " + std::string(m.data));
    return true;
  });
  EXPECT_TRUE(r.complete()) << path;
  EXPECT_TRUE(r.damage().empty()) << path;
  return out;
}

bool same_compressor_as_the_reference(Compression c) {
  if (c == Compression::zstd) return compressor_version(c) == kReferenceZstd;
  if (c == Compression::lz4) return compressor_version(c) == kReferenceLz4;
  return true;
}

class WriterFixedInput : public ::testing::TestWithParam<Compression> {};

// ENACT_WRITE_REFERENCE=1 writes the reference files instead (only ever with the writer they
// stand for)
TEST_P(WriterFixedInput, GivesTheBytesOfTheReferenceFile) {
  const Compression c = GetParam();
  if (std::getenv("ENACT_WRITE_REFERENCE")) {
    write_fixed_input(reference_path(c), c);
    GTEST_SKIP() << "wrote " << reference_path(c);
  }
  TempDir dir;
  write_fixed_input(dir.file("fixed.mcap"), c);
  const std::string written = read_file(dir.file("fixed.mcap")), reference = read_file(reference_path(c));
  ASSERT_GT(reference.size(), 1000u) << reference_path(c);
  // what a reader gets back is the same in any case
  EXPECT_EQ(messages_of(dir.file("fixed.mcap")), messages_of(reference_path(c)));
  if (!same_compressor_as_the_reference(c)) {
    GTEST_SKIP() << to_string(c) << " is not the version that compressed the reference file: messages compared, bytes not";
  }
  ASSERT_EQ(written.size(), reference.size());
  for (std::size_t i = 0; i < written.size(); ++i) ASSERT_EQ(written[i], reference[i]) << "first difference at byte " << i;
}

INSTANTIATE_TEST_SUITE_P(Compressions, WriterFixedInput, ::testing::Values(Compression::none, Compression::lz4, Compression::zstd),
                         [](const auto& param_info) { return std::string(to_string(param_info.param)); });

class WriterSteadyState : public ::testing::TestWithParam<Compression> {};

// once the writer is warm (a chunk through each of its buffers: the open chunk's and each
// worker's), writing a message allocates nothing on the writing thread, in an open chunk and
// when a full chunk is handed on (to be compressed, indexed and written)
TEST_P(WriterSteadyState, WritingAMessageAllocatesNothing) {
  TempDir dir;
  WriterOptions o;
  o.compression = GetParam();
  o.chunk_size_bytes = 256 * 1024;
  Writer w(dir.file("steady.mcap"), o);
  const std::uint16_t channels[3] = {w.add_channel(0, "a", "", {}), w.add_channel(0, "b", "", {}), w.add_channel(0, "c", "", {})};
  const std::string payload(100, 'p');
  constexpr int kPerChunk = 256 * 1024 / (100 + 31);
  std::int64_t t = 0;
  const auto write = [&](int n) {
    for (int i = 0; i < n; ++i, t += 20'000) w.write(channels[i % 3], static_cast<std::uint32_t>(i), t, t, payload);
  };
  const int warm_up = static_cast<int>(kMaxWorkers + 1) * kPerChunk;
  write(warm_up);
  const std::uint64_t chunks_before = w.chunk_count();
  std::size_t in_chunk = 0, across_chunks = 0;
  {
    const test::AllocGuard guard;
    write(kPerChunk / 2);
    in_chunk = guard.allocations();
  }
  {
    const test::AllocGuard guard;
    write(5 * kPerChunk);
    across_chunks = guard.allocations();
  }
  EXPECT_GE(w.chunk_count(), chunks_before + 5);  // the second count did hand chunks on
  EXPECT_EQ(in_chunk, 0u) << "allocations in " << kPerChunk / 2 << " messages in an open chunk";
  EXPECT_EQ(across_chunks, 0u) << "allocations in " << 5 * kPerChunk << " messages across 5 chunks";
  w.close();
  EXPECT_EQ(w.message_count(), static_cast<std::uint64_t>(warm_up + kPerChunk / 2 + 5 * kPerChunk));
}

INSTANTIATE_TEST_SUITE_P(Compressions, WriterSteadyState, ::testing::Values(Compression::none, Compression::lz4, Compression::zstd),
                         [](const auto& param_info) { return std::string(to_string(param_info.param)); });


// a full chunk written by a worker that finds the disk full (here a file size limit): the
// error comes out of a later call, and the file keeps the messages up to the last chunk that
// reached it, with no hole (the chunks behind the failed one are given up too), as many as the
// writer counts
TEST(WriterFullDisk, AWorkersFailedWriteIsThrownAndTheFileEndsAtItsLastWholeChunk) {
  TempDir dir;
  const std::string path = dir.file("full.mcap"), report = dir.file("report");
  const pid_t child = fork();
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);  // a write past the limit fails (EFBIG) instead of killing
    const rlimit limit{174'000, 174'000};
    setrlimit(RLIMIT_FSIZE, &limit);
    WriterOptions o;
    o.compression = Compression::none;
    o.chunk_size_bytes = 8 * 1024;              // full chunks: the workers write them
    o.chunk_duration_ns = 1'000'000'000'000;  // never on time
    bool thrown = false;
    std::uint64_t counted = 0;
    {
      Writer w(path, o);
      const std::uint16_t c = w.add_channel(0, "t", "", {});
      // chunks of 63 small messages (8.3 kB) between chunks of 60 small and one of 30 kB
      // (38 kB): the limit stops a large one with room left for the small one behind it
      const std::string small(100, 'x'), large(30'000, 'y');
      try {
        for (int i = 0; i < 100'000; ++i) w.write(c, static_cast<std::uint32_t>(i + 1), 1'000LL * i, 0, i % 124 == 123 ? large : small);
      } catch (const Error&) {
        thrown = true;
      }
      try {
        w.close();
      } catch (const Error&) {
      }
      counted = w.message_count();
    }
    FILE* f = std::fopen(report.c_str(), "w");
    std::fprintf(f, "%d %llu", thrown ? 1 : 0, static_cast<unsigned long long>(counted));
    std::fclose(f);
    _exit(0);
  }
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  int thrown = 0;
  unsigned long long counted = 0;
  ASSERT_EQ(std::sscanf(read_file(report).c_str(), "%d %llu", &thrown, &counted), 2) << read_file(report);
  EXPECT_EQ(thrown, 1) << "the failed write was never thrown";
  Reader r(path);
  std::vector<std::uint32_t> sequences;
  r.for_each([&](const Message& m) {
    sequences.push_back(m.sequence);
    return true;
  });
  ASSERT_GT(sequences.size(), 300u);  // 3 pairs of chunks, at least, fit
  EXPECT_EQ(sequences.size(), counted);
  for (std::size_t i = 0; i < sequences.size(); ++i) ASSERT_EQ(sequences[i], i + 1) << "a hole in the file";
}

}  // namespace
}  // namespace enact::record
