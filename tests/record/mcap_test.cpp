// MCAP writer and reader: round trips, the byte layout of the spec, and damaged files.
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/record/reader.h"
#include "core/record/writer.h"
#include "tests/support/test_util.h"

namespace enact::record {
namespace {

using test::read_file;
using test::TempDir;
using test::write_file;

struct Sent {
  std::string topic;
  std::uint32_t seq;
  std::int64_t time;
  std::string data;
};

// three channels of messages of varied sizes, 1 ms apart
std::vector<Sent> write_sample(const std::string& path, WriterOptions options, int count) {
  Writer w(path, options);
  const std::uint16_t s1 = w.add_schema("enact.msgs.DeviceState", "protobuf", std::string("\x0a\x01x", 3));
  const std::uint16_t s2 = w.add_schema("enact.msgs.ForceCommand", "protobuf", "descriptor");
  const std::uint16_t c[3] = {w.add_channel(s1, "ffd/state", "protobuf", {{"publisher", "ffd"}}),
                              w.add_channel(s2, "ffd/force", "protobuf", {{"publisher", "sim"}}),
                              w.add_channel(0, "raw", "", {})};
  const char* topics[3] = {"ffd/state", "ffd/force", "raw"};
  w.add_metadata("enact.launch", {{"file", "bridge.yaml"}, {"text", "launch: []"}});
  w.add_attachment("sim.scene", "application/yaml", "contact: {}\n", 5);
  std::vector<Sent> sent;
  for (int i = 0; i < count; ++i) {
    const int k = i % 3;
    std::string data(static_cast<std::size_t>(i % 97), static_cast<char>('a' + i % 26));
    sent.push_back({topics[k], static_cast<std::uint32_t>(i / 3 + 1), 1'000'000LL * i, data});
    w.write(c[k], sent.back().seq, sent.back().time, sent.back().time - 7, data);
  }
  w.close();
  return sent;
}

std::vector<Sent> read_all(Reader& r) {
  std::vector<Sent> got;
  r.for_each([&](const Message& m) {
    got.push_back({std::string(m.topic), m.sequence, m.log_time_ns, std::string(m.data)});
    return true;
  });
  return got;
}

void expect_same(const std::vector<Sent>& a, const std::vector<Sent>& b, std::size_t n) {
  ASSERT_GE(a.size(), n);
  ASSERT_GE(b.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(a[i].topic, b[i].topic) << i;
    ASSERT_EQ(a[i].seq, b[i].seq) << i;
    ASSERT_EQ(a[i].time, b[i].time) << i;
    ASSERT_EQ(a[i].data, b[i].data) << i;
  }
}

std::uint64_t le(const std::string& s, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(s[at + i])) << (8 * i);
  return v;
}

class RoundTrip : public ::testing::TestWithParam<Compression> {};

TEST_P(RoundTrip, EveryMessageMetadataAndAttachmentComeBack) {
  TempDir dir;
  WriterOptions o;
  o.compression = GetParam();
  o.chunk_size_bytes = 16 * 1024;  // many chunks
  const auto sent = write_sample(dir.file("a.mcap"), o, 9000);
  Reader r(dir.file("a.mcap"));
  const auto got = read_all(r);
  EXPECT_TRUE(r.complete());
  EXPECT_TRUE(r.damage().empty()) << r.damage().front();
  ASSERT_EQ(got.size(), sent.size());
  expect_same(sent, got, sent.size());
  EXPECT_EQ(r.metadata("enact.launch").at("file"), "bridge.yaml");
  EXPECT_EQ(r.attachment("sim.scene").value(), "contact: {}\n");
  EXPECT_EQ(r.channels().at(0).metadata.at("publisher"), "ffd");
  EXPECT_EQ(r.schemas().at(1).name, "enact.msgs.DeviceState");
}

INSTANTIATE_TEST_SUITE_P(Compressions, RoundTrip, ::testing::Values(Compression::none, Compression::lz4, Compression::zstd),
                         [](const auto& param_info) { return std::string(to_string(param_info.param)); });

// the CRC-32 every chunk and the data section carry (ISA-L's) is zlib's, from any start, of
// any length and alignment, and continues as zlib's does: a reader checks it with zlib
TEST(McapCrc, IsZlibsForEveryLengthAlignmentAndContinuation) {
  std::vector<unsigned char> data(3 << 20);
  std::uint64_t x = 0x9E3779B97F4A7C15ull;
  for (unsigned char& b : data) {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    b = static_cast<unsigned char>(x);
  }
  const auto zlib = [&](std::uint32_t crc, std::size_t at, std::size_t n) {
    return static_cast<std::uint32_t>(::crc32(crc, data.data() + at, static_cast<uInt>(n)));
  };
  for (std::size_t n = 0; n < 600; ++n) {
    for (const std::size_t at : std::vector<std::size_t>{0, 1, 3, 7, 13}) ASSERT_EQ(crc32(0, data.data() + at, n), zlib(0, at, n)) << n << " bytes from " << at;
  }
  for (const std::size_t n : std::vector<std::size_t>{4095, 4096, 65537, 1u << 20, (3u << 20) - 5}) {
    EXPECT_EQ(crc32(0, data.data() + 5, n - 5), zlib(0, 5, n - 5)) << n;
    // continued: the CRC of a first part, then the rest from it
    const std::size_t half = n / 3;
    EXPECT_EQ(crc32(crc32(0, data.data(), half), data.data() + half, n - half), zlib(0, 0, n)) << n;
    EXPECT_EQ(crc32(0x12345678u, data.data(), n), zlib(0x12345678u, 0, n)) << n;
  }
}

TEST(Mcap, FileStartsWithMagicAndHeaderAsTheSpecLaysThemOut) {
  TempDir dir;
  WriterOptions o;
  o.profile = "p";
  o.library = "lib";
  { Writer w(dir.file("h.mcap"), o); }
  const std::string f = read_file(dir.file("h.mcap"));
  // magic, op 0x01, uint64 length 12, string "p" (uint32 1), string "lib" (uint32 3)
  const std::string expected("\x89MCAP0\r\n" "\x01" "\x0c\0\0\0\0\0\0\0" "\x01\0\0\0" "p" "\x03\0\0\0" "lib", 8 + 9 + 12);
  EXPECT_EQ(f.substr(0, expected.size()), expected);
  EXPECT_EQ(f.substr(f.size() - 8), f.substr(0, 8));  // closing magic
}

TEST(Mcap, FooterLocatesTheSummaryAndItsCrcAndIndexesPointAtTheirRecords) {
  TempDir dir;
  WriterOptions o;
  o.compression = Compression::none;
  o.chunk_size_bytes = 2000;
  write_sample(dir.file("s.mcap"), o, 600);
  const std::string f = read_file(dir.file("s.mcap"));
  // footer: op 0x02, length 20, summary_start, summary_offset_start, summary_crc; then magic
  const std::size_t footer = f.size() - 8 - 29;
  ASSERT_EQ(f[footer], '\x02');
  ASSERT_EQ(le(f, footer + 1, 8), 20u);
  const std::uint64_t summary_start = le(f, footer + 9, 8);
  const std::uint64_t offsets_start = le(f, footer + 17, 8);
  const auto crc = static_cast<std::uint32_t>(le(f, footer + 25, 4));
  // the CRC covers the summary up to and including summary_offset_start
  const uLong expected = ::crc32(0, reinterpret_cast<const Bytef*>(f.data() + summary_start), static_cast<uInt>(footer + 25 - summary_start));
  EXPECT_EQ(crc, expected);
  // the data end record sits just before the summary; the summary opens with the schemas
  EXPECT_EQ(f[summary_start - 13], '\x0f');
  EXPECT_EQ(f[summary_start], '\x03');
  // every summary offset record points at a group of records of its opcode; chunk indexes
  // point at chunks and their message indexes
  int chunk_indexes = 0;
  for (std::size_t at = offsets_start; at < footer; at += 9 + 17) {
    ASSERT_EQ(f[at], '\x0e');
    const char op = f[at + 9];
    const std::uint64_t start = le(f, at + 10, 8), length = le(f, at + 18, 8);
    for (std::size_t r = start; r < start + length; r += 9 + le(f, r + 1, 8)) {
      ASSERT_EQ(f[r], op);
      if (op != '\x08') continue;
      ++chunk_indexes;
      const std::uint64_t chunk_offset = le(f, r + 9 + 16, 8);
      EXPECT_EQ(f[chunk_offset], '\x06');
      const std::uint64_t first_index = le(f, r + 9 + 32 + 4 + 2, 8);  // the map's first value
      EXPECT_EQ(f[first_index], '\x07');
    }
  }
  EXPECT_GT(chunk_indexes, 3);
}

TEST(Mcap, ChunkClosesOnceItSpansTheChunkDuration) {
  TempDir dir;
  WriterOptions o;
  o.chunk_duration_ns = 1'000'000'000;
  Writer w(dir.file("d.mcap"), o);
  const auto c = w.add_channel(0, "t", "", {});
  for (int i = 0; i < 40; ++i) w.write(c, i, 100'000'000LL * i, 0, "x");  // 0 .. 3.9 s
  EXPECT_EQ(w.chunk_count(), 3u);  // closed at 1.0, 2.0 and 3.0 s
  w.flush_if_due(4'000'000'000LL);
  EXPECT_EQ(w.chunk_count(), 4u);
}

TEST(Mcap, UnclosedFileKeepsEveryCompletedChunk) {
  TempDir dir;
  const std::string path = dir.file("killed.mcap");
  // a child writes 2.5 s of messages and dies without closing (as under kill -9)
  const pid_t child = fork();
  if (child == 0) {
    WriterOptions o;
    auto* w = new Writer(path, o);
    const auto c = w->add_channel(0, "t", "", {});
    for (int i = 0; i < 250; ++i) w->write(c, i + 1, 10'000'000LL * i, 0, "m");
    _exit(0);
  }
  int status = 0;
  waitpid(child, &status, 0);
  Reader r(path);
  const auto got = read_all(r);
  EXPECT_FALSE(r.complete());
  ASSERT_FALSE(r.damage().empty());
  EXPECT_NE(r.damage().front().find("not closed"), std::string::npos);
  ASSERT_EQ(got.size(), 200u);  // chunks of 0-1 s and 1-2 s; the open one (2-2.5 s) is lost
  EXPECT_EQ(got.back().seq, 200u);
}

TEST(Mcap, TruncatedFileReadsEverythingBeforeTheCut) {
  TempDir dir;
  WriterOptions o;
  o.compression = Compression::zstd;
  o.chunk_size_bytes = 4000;
  const auto sent = write_sample(dir.file("t.mcap"), o, 3000);
  std::string f = read_file(dir.file("t.mcap"));
  write_file(dir.file("cut.mcap"), f.substr(0, f.size() / 2));
  Reader r(dir.file("cut.mcap"));
  const auto got = read_all(r);
  EXPECT_FALSE(r.complete());
  ASSERT_FALSE(r.damage().empty());
  EXPECT_NE(r.damage().front().find("truncated"), std::string::npos) << r.damage().front();
  EXPECT_GT(got.size(), sent.size() / 3);
  EXPECT_LT(got.size(), sent.size());
  expect_same(sent, got, got.size());
}

// a file cut inside a record names the record as the specification does, with its article
TEST(Mcap, ACutRecordIsNamedOnceWithItsArticle) {
  TempDir dir;
  write_sample(dir.file("whole.mcap"), WriterOptions{}, 10);
  const std::string f = read_file(dir.file("whole.mcap"));
  const std::size_t after_header = 8 + 9 + le(f, 8 + 1, 8);  // magic, then the header record
  auto cut_in = [&](char opcode) {
    std::string length(8, '\0');
    length[0] = static_cast<char>(0xe8), length[1] = 0x03;  // 1000 bytes, little-endian
    write_file(dir.file("cut.mcap"), f.substr(0, after_header) + opcode + length + "partial");
    Reader r(dir.file("cut.mcap"));
    return r.damage().empty() ? std::string() : r.damage().front();
  };
  const std::string index = cut_in(0x07), attachment = cut_in(0x09), unknown = cut_in(0x7f);
  EXPECT_NE(index.find("truncated: a message index record of 1000 bytes"), std::string::npos) << index;
  EXPECT_NE(attachment.find("truncated: an attachment record of 1000 bytes"), std::string::npos) << attachment;
  EXPECT_NE(unknown.find("truncated: a record of opcode 0x7f of 1000 bytes"), std::string::npos) << unknown;
  for (const std::string& said : {index, attachment, unknown}) EXPECT_EQ(said.find("record record"), std::string::npos) << said;
}

TEST(Mcap, CorruptedChunkIsSkippedAndTheOthersAreRead) {
  TempDir dir;
  WriterOptions o;
  o.compression = Compression::none;
  o.chunk_size_bytes = 4000;
  const auto sent = write_sample(dir.file("c.mcap"), o, 3000);
  std::string f = read_file(dir.file("c.mcap"));
  // flip one byte of message data in the middle of the file: inside some chunk
  const std::size_t at = f.find(std::string(40, 'm'), f.size() / 2);
  ASSERT_NE(at, std::string::npos);
  f[at + 10] = 'M';
  write_file(dir.file("bad.mcap"), f);
  Reader r(dir.file("bad.mcap"));
  const auto got = read_all(r);
  ASSERT_EQ(r.damage().size(), 1u);
  EXPECT_NE(r.damage()[0].find("CRC mismatch"), std::string::npos) << r.damage()[0];
  EXPECT_LT(got.size(), sent.size());
  EXPECT_GT(got.size(), sent.size() * 9 / 10);
  EXPECT_EQ(got.back().data, sent.back().data);  // chunks after the damage are still read
}

TEST(Mcap, NotMcapFilesAreRefusedByName) {
  TempDir dir;
  write_file(dir.file("x.csv"), "t_s,x_m\n0,0\n");
  write_file(dir.file("empty.mcap"), "");
  write_file(dir.file("magic_only.mcap"), std::string("\x89MCAP0\r\n", 8) + "garbage!!garbage!!");
  for (const char* name : {"x.csv", "empty.mcap", "magic_only.mcap"}) {
    try {
      Reader r(dir.file(name));
      ADD_FAILURE() << name << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("MCAP"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(Reader(dir.file("missing.mcap")), Error);
}

TEST(Mcap, MessagesOfAChannelWithAnUnknownSchemaAreReportedNotLost) {
  TempDir dir;
  {
    Writer w(dir.file("u.mcap"));
    const auto c = w.add_channel(7, "ghost", "protobuf", {});  // schema 7 never written
    w.write(c, 1, 10, 10, "payload");
  }
  Reader r(dir.file("u.mcap"));
  const auto got = read_all(r);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].data, "payload");
  ASSERT_EQ(r.damage().size(), 1u);
  EXPECT_NE(r.damage()[0].find("unknown schema 7"), std::string::npos) << r.damage()[0];
}

}  // namespace
}  // namespace enact::record
