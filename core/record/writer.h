#pragma once
// An MCAP writer (https://mcap.dev/spec), for recordings of bus messages: schemas, channels
// and messages, messages batched in compressed chunks (zstd, lz4 or none) each followed by
// its message indexes, metadata and attachments, and on close a summary (schemas, channels,
// chunk / attachment / metadata indexes, statistics, summary offsets) and the footer.
//
// Writing a message copies it into the open chunk and allocates nothing once the chunk's
// buffers have their size. A chunk that closes at chunk_size_bytes goes to one of the writer's
// worker threads (one per CPU, at most kMaxWorkers), which compresses and indexes it beside the
// others and writes it in its turn, while the next chunk fills; a chunk that closes on time
// (chunk_duration_ns), by flush() or by close() is in the file when that call returns. The
// bytes are the same either way.
//
// Durability: schemas, channels, metadata and attachments reach the file (write(2)) when
// they are added; messages when their chunk closes: once it spans chunk_duration_ns of log
// time (checked on each message and by flush_if_due), or at chunk_size_bytes, then within the
// time it takes to compress it. A process killed with SIGKILL so loses at most the open chunk,
// and those that closed full before it if the kill came while they were being compressed (one
// per worker at most); `enact recover` rebuilds an indexed file from the rest (record::Reader
// reads files without a summary).
//
// A full disk (or a file size limit): a write that fails throws record::Error and leaves the
// file ending at the last whole record; the failed chunk's messages are lost and not counted,
// nor those written after it (when a worker's write fails, the error is thrown by the next
// call: a write, flush_if_due, flush, an add or close). close() then still writes the summary
// if the room left holds it (the failed chunk's bytes were given back), else the file stays
// readable without one.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "core/record/compression.h"
#include "core/record/mcap.h"

namespace enact::record {

// worker threads of a writer at most (one per CPU)
inline constexpr unsigned kMaxWorkers = 4;

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
  // creates (or truncates) `path`, writes the magic and the header and starts the workers;
  // throws record::Error
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
  // one message on a channel add_channel returned (another throws record::Error); log times
  // need not increase (the chunk and statistics keep min and max)
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
  // bytes in the file so far (a chunk with a worker counts once it is written)
  std::uint64_t bytes_written() const { return offset_.load(std::memory_order_relaxed); }
  // messages written so far (those of a chunk that failed to reach the disk, and after it, excluded)
  std::uint64_t message_count() const { return messages_; }
  // chunks closed so far (those that failed excluded)
  std::uint64_t chunk_count() const { return chunks_; }

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
  // a chunk's Message records and their span of log time
  struct Chunk {
    std::unique_ptr<char[]> records;
    std::size_t size = 0, capacity = 0;
    std::uint64_t messages = 0;
    std::int64_t start = 0, end = 0;
    std::string_view view() const { return {records.get(), size}; }
  };
  // a worker: the chunk handed to it and what it makes of it; its buffers keep their room
  // from chunk to chunk
  struct Worker {
    explicit Worker(Compression c) : compressor(c) {}
    Chunk chunk;
    std::uint64_t turn = 0;  // the chunk's place in the file
    bool busy = false;       // under mutex_: holds a chunk not yet written (or given up)
    Compressor compressor;
    // made from the chunk: the Chunk record up to its records, its records (compressed), the
    // records' CRC, its Message Index records; index offsets relative to the chunk record
    std::string head, indexes;
    std::string_view body;
    std::uint32_t records_crc = 0;
    ChunkIndex index;
    std::vector<std::uint64_t> counts;                                  // where each channel's entries end
    std::vector<std::pair<std::uint64_t, std::uint64_t>> by_channel;  // (log time, offset), grouped by channel
    std::thread thread;
  };
  struct Tally {  // the statistics' counts, of the messages in the file
    std::uint64_t messages = 0;
    std::int64_t first_time = 0, last_time = 0;
    std::vector<std::uint64_t> channel_counts;  // by channel id
  };

  // appends a record built by `fill` to buffer `s`
  template <class Fill>
  void append_record(std::string& s, Op op, Fill fill);
  // room for `n` more bytes at the end of the open chunk's records
  char* extend_chunk(std::size_t n);
  // closes the open chunk: hands it to the next worker; `wait`: until it is in the file
  void close_chunk(bool wait);
  // waits until every chunk handed on is written; throws (once) the failure of a worker's
  // write, the open chunk then given up too (the file keeps no messages after a hole)
  void wait_for_workers();
  // a worker thread: makes each chunk handed to `w`, writes it in its turn
  void work(Worker& w);
  // compresses and indexes w.chunk (anywhere in the file)
  void make_chunk(Worker& w);
  // writes what make_chunk made at the file's end: the chunk, its indexes, the statistics
  void append_chunk(Worker& w);
  // close() up to the file's end
  void finish();
  // the summary's records (MCAP: statistics, chunk, attachment and metadata indexes) appended to `s`
  void append_statistics(std::string& s);
  void append_chunk_indexes(std::string& s);
  void append_attachment_indexes(std::string& s);
  void append_metadata_indexes(std::string& s);
  // writes `parts` at the file's end; a failure cuts the file back to its last whole record
  // and throws record::Error
  void append_to_file(std::initializer_list<std::string_view> parts);
  // sends out_ to the file, adding it to the data-section CRC
  void drain();
  void stop_workers();

  std::string path_;
  WriterOptions options_;
  int fd_ = -1;
  // the file: written by a worker in its turn, else (every worker idle) by the writer's thread
  std::atomic<std::uint64_t> offset_ = 0;  // bytes in the file so far
  std::uint32_t data_crc_ = 0;             // of every byte written before the data end
  std::string out_;                        // bytes not yet written
  std::vector<std::string> schemas_, channels_;  // their records, repeated in the summary
  std::vector<ChunkIndex> chunk_indexes_;
  std::vector<Index> attachments_, metadata_;
  Tally written_;
  // the writer's thread: the open chunk, the counts it answers
  Chunk open_;
  std::uint64_t messages_ = 0, chunks_ = 0;
  std::uint64_t handed_ = 0;  // chunks handed to the workers, in turns 0, 1, ...
  // the workers
  std::vector<std::unique_ptr<Worker>> workers_;
  std::mutex mutex_;
  std::condition_variable changed_;  // a chunk handed on, or written
  std::uint64_t done_ = 0;           // under mutex_: turns over (written, or given up after a failure)
  bool stopping_ = false;            // under mutex_
  std::string failure_;              // under mutex_: the failed write's error, until thrown
  std::atomic<bool> failed_ = false;
};

}  // namespace enact::record
