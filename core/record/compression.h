#pragma once
// Chunk compression: zstd and lz4 (the LZ4 frame format), the two MCAP names
// (https://mcap.dev/spec, "well-known compression formats"), or none.
#include <cstdint>
#include <string>
#include <string_view>

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

// compresses `in` into `out` (replaced)
void compress(Compression c, std::string_view in, std::string& out);
// decompresses a chunk's records of MCAP compression name `name` into `out` (replaced),
// which must come out exactly `size` bytes; false on unknown compression or bad data
bool decompress(std::string_view name, std::string_view in, std::uint64_t size, std::string& out);

}  // namespace enact::record
