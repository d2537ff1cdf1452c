#pragma once
// Chunk compression: zstd and lz4 (the LZ4 frame format), the two MCAP names
// (https://mcap.dev/spec, "well-known compression formats"), or none.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

struct ZSTD_CCtx_s;
struct LZ4F_cctx_s;

namespace enact::record {

enum class Compression : std::uint8_t { none, lz4, zstd };

// the name in an MCAP Chunk record: "", "lz4", "zstd"
std::string_view mcap_name(Compression c);
// "none", "lz4", "zstd" for people
const char* to_string(Compression c);
// from "none", "lz4" or "zstd"; throws std::invalid_argument naming the choices
Compression parse_compression(std::string_view name);
// the version of the library that compresses (e.g. "1.5.4"; "" for none): the same input
// gives the same bytes from the same version
std::string_view compressor_version(Compression c);

// the CRC-32 of two pieces one after the other, from each one's CRC (crc32 in mcap.h) and the
// second's length
std::uint32_t crc32_concat(std::uint32_t first, std::uint32_t second, std::uint64_t second_size);

// compresses chunk after chunk with one context kept between them: the bytes of a one-shot
// ZSTD_compress (level 1) or LZ4F_compressFrame (default preferences, content size given),
// without their allocations once its buffer has the size of the largest chunk
class Compressor {
 public:
  explicit Compressor(Compression c);
  ~Compressor();
  Compressor(const Compressor&) = delete;
  Compressor& operator=(const Compressor&) = delete;

  // `in` compressed (none: `in` itself), valid until the next call; throws std::runtime_error
  // naming the compressor's error
  std::string_view compress(std::string_view in);

 private:
  // room for at least `n` bytes in out_
  char* room(std::size_t n);

  Compression compression_;
  ZSTD_CCtx_s* zstd_ = nullptr;
  LZ4F_cctx_s* lz4_ = nullptr;
  std::unique_ptr<char[]> out_;
  std::size_t capacity_ = 0;
};

// decompresses a chunk's records of MCAP compression name `name` into `out` (replaced),
// which must come out exactly `size` bytes; false on unknown compression or bad data
bool decompress(std::string_view name, std::string_view in, std::uint64_t size, std::string& out);

}  // namespace enact::record
