#include "core/record/compression.h"

#include <new>
#include <stdexcept>

#include <lz4.h>
// LZ4F_compressFrame_usingCDict: a one-shot frame with a context kept between frames
#define LZ4F_STATIC_LINKING_ONLY
#include <lz4frame.h>
#include <isa-l/crc.h>
#include <zlib.h>
#include <zstd.h>

#include "core/record/mcap.h"

namespace enact::record {

std::uint32_t crc32(std::uint32_t crc, const void* data, std::size_t size) {
  // ISA-L's, the same CRC as zlib's (continued the same way) with the CPU's carry-less
  // multiply where it has one: about 10x zlib's speed on a 4 MiB chunk here, where zlib's took
  // a sixth of an uncompressed recording's writing (docs/performance.md, "Recording")
  return crc32_gzip_refl(crc, static_cast<const unsigned char*>(data), size);
}

std::uint32_t crc32_concat(std::uint32_t first, std::uint32_t second, std::uint64_t second_size) {
  return static_cast<std::uint32_t>(::crc32_combine(first, second, static_cast<z_off_t>(second_size)));
}

std::string_view mcap_name(Compression c) {
  switch (c) {
    case Compression::lz4: return "lz4";
    case Compression::zstd: return "zstd";
    case Compression::none: break;
  }
  return "";
}

const char* to_string(Compression c) { return c == Compression::none ? "none" : mcap_name(c).data(); }

Compression parse_compression(std::string_view name) {
  if (name == "zstd") return Compression::zstd;
  if (name == "lz4") return Compression::lz4;
  if (name == "none") return Compression::none;
  throw std::invalid_argument("unknown compression '" + std::string(name) + "' (choose zstd, lz4 or none)");
}

std::string_view compressor_version(Compression c) {
  switch (c) {
    case Compression::lz4: return LZ4_versionString();
    case Compression::zstd: return ZSTD_versionString();
    case Compression::none: break;
  }
  return "";
}

Compressor::Compressor(Compression c) : compression_(c) {
  if (c == Compression::zstd) zstd_ = ZSTD_createCCtx();
  if (c == Compression::lz4 && LZ4F_isError(LZ4F_createCompressionContext(&lz4_, LZ4F_VERSION))) lz4_ = nullptr;
  if ((c == Compression::zstd && !zstd_) || (c == Compression::lz4 && !lz4_)) throw std::bad_alloc();
}

Compressor::~Compressor() {
  ZSTD_freeCCtx(zstd_);
  LZ4F_freeCompressionContext(lz4_);
}

char* Compressor::room(std::size_t n) {
  if (n > capacity_) {
    out_ = std::make_unique_for_overwrite<char[]>(n);
    capacity_ = n;
  }
  return out_.get();
}

std::string_view Compressor::compress(std::string_view in) {
  switch (compression_) {
    case Compression::none: return in;
    case Compression::zstd: {
      const std::size_t bound = ZSTD_compressBound(in.size());
      // level 1: the fastest standard level; recordings favour throughput
      const std::size_t n = ZSTD_compressCCtx(zstd_, room(bound), bound, in.data(), in.size(), 1);
      if (ZSTD_isError(n)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(n));
      return {out_.get(), n};
    }
    case Compression::lz4: {
      LZ4F_preferences_t prefs{};
      prefs.frameInfo.contentSize = in.size();
      const std::size_t bound = LZ4F_compressFrameBound(in.size(), &prefs);
      const std::size_t n = LZ4F_compressFrame_usingCDict(lz4_, room(bound), bound, in.data(), in.size(), nullptr, &prefs);
      if (LZ4F_isError(n)) throw std::runtime_error(std::string("lz4: ") + LZ4F_getErrorName(n));
      return {out_.get(), n};
    }
  }
  return in;
}

namespace {

bool lz4_decompress(std::string_view in, std::string& out) {
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) return false;
  std::size_t in_at = 0, out_at = 0;
  bool ok = true;
  for (;;) {
    std::size_t in_n = in.size() - in_at, out_n = out.size() - out_at;
    const std::size_t hint = LZ4F_decompress(ctx, out.data() + out_at, &out_n, in.data() + in_at, &in_n, nullptr);
    if (LZ4F_isError(hint)) {
      ok = false;
      break;
    }
    in_at += in_n;
    out_at += out_n;
    if (hint == 0) break;  // frame complete
    if (in_n == 0 && out_n == 0) {
      ok = false;  // no progress: truncated input or output too small
      break;
    }
  }
  LZ4F_freeDecompressionContext(ctx);
  return ok && out_at == out.size() && in_at == in.size();
}

// the most `in` can decompress to: a single zstd frame says its size; otherwise the formats'
// largest ratios bound it (zstd: a 4-byte RLE block gives a 128 KiB block; lz4: 255 bytes
// per input byte)
std::uint64_t most_from(std::string_view name, std::string_view in) {
  if (name == "zstd") {
    const unsigned long long declared = ZSTD_getFrameContentSize(in.data(), in.size());
    const bool single = ZSTD_findFrameCompressedSize(in.data(), in.size()) == in.size();
    if (single && declared != ZSTD_CONTENTSIZE_UNKNOWN && declared != ZSTD_CONTENTSIZE_ERROR) return declared;
    return std::uint64_t{in.size()} * 32 * 1024;
  }
  return std::uint64_t{in.size()} * 255 + 64 * 1024;
}

}  // namespace

bool decompress(std::string_view name, std::string_view in, std::uint64_t size, std::string& out) {
  if (name.empty()) {
    if (in.size() != size) return false;
    out.assign(in);
    return true;
  }
  if (size > most_from(name, in)) return false;  // a damaged size: nothing is allocated for it
  out.resize(static_cast<std::size_t>(size));
  if (name == "zstd") {
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), in.data(), in.size());
    return !ZSTD_isError(n) && n == size;
  }
  if (name == "lz4") return lz4_decompress(in, out);
  return false;
}

}  // namespace enact::record
