#pragma once
// Facts of the MCAP container format, major version 0 (https://mcap.dev/spec): the magic,
// the record opcodes, and the little-endian serialization of record fields. Written from the
// specification; shared by the writer and the reader.
#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

namespace enact::record {

// a file that cannot be opened or read as MCAP (the message names the file and the problem)
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// 0x89 'M' 'C' 'A' 'P' '0' '\r' '\n', at the start and at the end of every file
inline constexpr std::string_view kMagic{"\x89MCAP0\r\n", 8};

enum class Op : std::uint8_t {
  header = 0x01,
  footer = 0x02,
  schema = 0x03,
  channel = 0x04,
  message = 0x05,
  chunk = 0x06,
  message_index = 0x07,
  chunk_index = 0x08,
  attachment = 0x09,
  attachment_index = 0x0A,
  statistics = 0x0B,
  metadata = 0x0C,
  metadata_index = 0x0D,
  summary_offset = 0x0E,
  data_end = 0x0F,
};

// a record: opcode (1 byte) and content length (uint64) before the content
inline constexpr std::size_t kRecordPrefix = 9;

// a Message record's fields before its data: channel id, sequence, log time, publish time
inline constexpr std::size_t kMessageFields = 2 + 4 + 8 + 8;

// `v` little-endian at `p`; returns the byte after (one store on a little-endian CPU: GCC 12
// left the byte loop a loop, most of the time the writer's message indexes took)
template <class T>
char* put(char* p, T v) {
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(p, &v, sizeof(T));
  } else {
    for (std::size_t i = 0; i < sizeof(T); ++i) p[i] = static_cast<char>((static_cast<std::uint64_t>(v) >> (8 * i)) & 0xFF);
  }
  return p + sizeof(T);
}

// the little-endian `T` at `p`
template <class T>
T get(const char* p) {
  T v;
  if constexpr (std::endian::native == std::endian::little) {
    std::memcpy(&v, p, sizeof(T));
  } else {
    std::uint64_t u = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) u |= static_cast<std::uint64_t>(static_cast<unsigned char>(p[i])) << (8 * i);
    v = static_cast<T>(u);
  }
  return v;
}

// the bytes of a Message record with `data_size` bytes of data
constexpr std::size_t message_record_size(std::size_t data_size) { return kRecordPrefix + kMessageFields + data_size; }

// a Message record at `p` (message_record_size(data.size()) bytes); returns the byte after
inline char* put_message(char* p, std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time, std::uint64_t publish_time,
                         std::string_view data) {
  p = put(p, static_cast<std::uint8_t>(Op::message));
  p = put(p, std::uint64_t{kMessageFields + data.size()});
  p = put(p, channel_id);
  p = put(p, sequence);
  p = put(p, log_time);
  p = put(p, publish_time);
  if (!data.empty()) std::memcpy(p, data.data(), data.size());
  return p + data.size();
}

// CRC-32 (ISO-HDLC, zlib's), the checksum MCAP uses, continued from `crc`
std::uint32_t crc32(std::uint32_t crc, const void* data, std::size_t size);

// appends little-endian fields to a byte string
struct Out {
  std::string& s;
  template <class T>
  void num(T v) {
    char b[sizeof(T)];
    put(b, v);
    s.append(b, sizeof(T));
  }
  void u8(std::uint8_t v) { num(v); }
  void u16(std::uint16_t v) { num(v); }
  void u32(std::uint32_t v) { num(v); }
  void u64(std::uint64_t v) { num(v); }
  // String and uint32 length-prefixed Bytes
  void str(std::string_view v) {
    u32(static_cast<std::uint32_t>(v.size()));
    s.append(v);
  }
  // uint64 length-prefixed Bytes
  void bytes64(std::string_view v) {
    u64(v.size());
    s.append(v);
  }
  // opens a record; returns where its length goes, for end_record
  std::size_t begin_record(Op op) {
    u8(static_cast<std::uint8_t>(op));
    const std::size_t at = s.size();
    u64(0);
    return at;
  }
  void end_record(std::size_t length_at) {
    put(s.data() + length_at, std::uint64_t{s.size() - length_at - 8});
  }
  // a Map or Array: a uint32 byte length, then the elements; returns where the length goes
  std::size_t begin_block() {
    const std::size_t at = s.size();
    u32(0);
    return at;
  }
  void end_block(std::size_t at) {
    put(s.data() + at, static_cast<std::uint32_t>(s.size() - at - 4));
  }
};

// reads little-endian fields from a record's content; any read past the end sets `bad`
// (and yields zeros), so a parser checks `bad` once at the end
struct In {
  std::string_view s;
  std::size_t at = 0;
  bool bad = false;
  bool has(std::size_t n) {
    if (at > s.size() || s.size() - at < n) bad = true;
    return !bad;
  }
  template <class T>
  T num() {
    if (!has(sizeof(T))) return 0;
    const T v = get<T>(s.data() + at);
    at += sizeof(T);
    return v;
  }
  std::uint8_t u8() { return num<std::uint8_t>(); }
  std::uint16_t u16() { return num<std::uint16_t>(); }
  std::uint32_t u32() { return num<std::uint32_t>(); }
  std::uint64_t u64() { return num<std::uint64_t>(); }
  std::string_view take(std::size_t n) {
    if (!has(n)) return {};
    const std::string_view v = s.substr(at, n);
    at += n;
    return v;
  }
  std::string_view str() { return take(u32()); }
  std::string_view bytes64() {
    const std::uint64_t n = u64();
    return n > s.size() ? (bad = true, std::string_view{}) : take(static_cast<std::size_t>(n));
  }
  std::string_view rest() { return take(s.size() - at); }
};

}  // namespace enact::record
