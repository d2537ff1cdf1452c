#pragma once
// An MCAP writer (https://mcap.dev/spec), for recordings of bus messages: schemas, channels
// and messages, messages batched in compressed chunks (zstd, lz4 or none) each followed by
// its message indexes, metadata and attachments, and on close a summary (schemas, channels,
// chunk / attachment / metadata indexes, statistics, summary offsets) and the footer.
//
// Durability: schemas, channels, metadata and attachments reach the file (write(2)) when
// they are added; messages when their chunk closes: at chunk_size_bytes, or once the chunk
// spans chunk_duration_ns of log time (checked on each message and by flush_if_due). A
// process killed with SIGKILL so loses at most the open chunk; `enact recover` rebuilds an
// indexed file from the rest (record::Reader reads files without a summary).
//
// A full disk (or a file size limit): a write that fails throws record::Error and leaves the
// file ending at the last whole record (the failed chunk's messages are lost and not
// counted); close() then still writes the summary if the room left holds it (the failed
// chunk's bytes were given back), else the file stays readable without one.
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/record/compression.h"
#include "core/record/mcap.h"

namespace enact::record {

struct WriterOptions {
  Compression compression = Compression::zstd;
  std::size_t chunk_size_bytes = 4u << 20;          // uncompressed records per chunk, at most about
  std::int64_t chunk_duration_ns = 1'000'000'000;   // a chunk closes once it spans this much log time
  std::string profile;                              // MCAP Header profile ("" = none)
  std::string library = "enact";                    // MCAP Header library
};

using StringMap = std::map<std::string, std::string>;

class Writer {
 public:
  // creates (or truncates) `path` and writes the magic and the header; throws record::Error
  explicit Writer(const std::string& path, WriterOptions options = {});
  // close(); errors are swallowed here (call close() to see them)
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // a schema (e.g. name "enact.msgs.DeviceState", encoding "protobuf", data a serialized
  // FileDescriptorSet); returns its id (from 1)
  std::uint16_t add_schema(std::string_view name, std::string_view encoding, std::string_view data);
  // a channel of messages on `topic` (schema_id 0: no schema); returns its id (from 0)
  std::uint16_t add_channel(std::uint16_t schema_id, std::string_view topic, std::string_view message_encoding,
                            const StringMap& metadata = {});
  // one message; log times need not increase (the chunk and statistics keep min and max)
  void write(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns, std::int64_t publish_time_ns,
             std::string_view data);
  // a Metadata record (name, key-value pairs)
  void add_metadata(std::string_view name, const StringMap& values);
  // an Attachment record (a file kept with the recording)
  void add_attachment(std::string_view name, std::string_view media_type, std::string_view data, std::int64_t log_time_ns,
                      std::int64_t create_time_ns = 0);
  // closes the open chunk if it spans chunk_duration_ns up to now_ns (log-time clock)
  void flush_if_due(std::int64_t now_ns);
  // closes the open chunk now: every message written so far reaches the file
  void flush();
  // flush, data end, summary, footer, magic; then the file is complete. Safe twice.
  void close();

  const std::string& path() const { return path_; }
  std::uint64_t bytes_written() const { return offset_; }
  // messages written so far (those of a chunk that failed to reach the disk excluded)
  std::uint64_t message_count() const { return tally_.messages; }
  std::uint64_t chunk_count() const { return chunk_indexes_.size(); }

 private:
  struct Index {  // summary index entry of a record in the data section
    std::uint64_t offset = 0, length = 0;
    std::int64_t log_time = 0, create_time = 0;
    std::uint64_t data_size = 0;
    std::string name, media_type;
  };
  struct ChunkIndex {
    std::uint64_t start_time = 0, end_time = 0, offset = 0, length = 0;
    std::vector<std::pair<std::uint16_t, std::uint64_t>> index_offsets;
    std::uint64_t index_length = 0, compressed_size = 0, uncompressed_size = 0;
  };
  // appends a record built by `fill` to buffer `s`
  template <class Fill>
  void append_record(std::string& s, Op op, Fill fill);
  // close() up to the file's end
  void finish();
  // the summary's records (MCAP: statistics, chunk, attachment and metadata indexes) appended to `s`
  void append_statistics(std::string& s);
  void append_chunk_indexes(std::string& s);
  void append_attachment_indexes(std::string& s);
  void append_metadata_indexes(std::string& s);
  // sends out_ to the file (adds it to the data-section CRC unless in the summary)
  void drain();

  std::string path_;
  WriterOptions options_;
  int fd_ = -1;
  std::uint64_t offset_ = 0;      // bytes in the file so far
  std::uint32_t data_crc_ = 0;    // of every byte written before the data end
  std::string out_;               // bytes not yet written
  std::vector<std::string> schemas_, channels_;  // their records, repeated in the summary
  // the open chunk
  std::string chunk_, compressed_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> message_index_;
  std::int64_t chunk_start_ = 0, chunk_end_ = 0;
  bool chunk_open_ = false;
  // the summary
  std::vector<ChunkIndex> chunk_indexes_;
  std::vector<Index> attachments_, metadata_;
  struct Tally {  // the statistics' counts
    std::uint64_t messages = 0;
    std::int64_t first_time = 0, last_time = 0;
    std::map<std::uint16_t, std::uint64_t> channel_counts;
  };
  Tally tally_;    // of every message written
  Tally written_;  // of those in chunks that reached the file
};

}  // namespace enact::record
