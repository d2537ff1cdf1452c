#pragma once
// An MCAP reader (https://mcap.dev/spec) that reads what is there: it walks the data section
// record by record, so it reads files that were never closed (no summary) and files damaged
// part-way. Damage never throws: a corrupted chunk (CRC mismatch, bad compression) is
// skipped, a truncated file ends the walk, a message on an unknown channel or schema is
// reported, and everything readable is still read; damage() lists each problem with its
// byte offset. Only a file that is not MCAP at all (missing magic or header) throws.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/record/mcap.h"
#include "core/record/writer.h"

namespace enact::record {

struct Schema {
  std::uint16_t id = 0;
  std::string name;      // e.g. "enact.msgs.DeviceState"
  std::string encoding;  // e.g. "protobuf"
  std::string data;      // e.g. a serialized FileDescriptorSet
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  // 0: none
  std::string topic;
  std::string message_encoding;
  StringMap metadata;
};

// one message, valid during the for_each callback only
struct Message {
  const Channel* channel = nullptr;
  const Schema* schema = nullptr;  // null when the channel has none (or it is unknown)
  std::string_view topic;
  std::string_view schema_name;    // "" when schema is null
  std::uint32_t sequence = 0;
  std::int64_t log_time_ns = 0;
  std::int64_t publish_time_ns = 0;
  std::string_view data;
};

struct Attachment {
  std::string name;
  std::string media_type;
  std::string data;
  std::int64_t log_time_ns = 0;
  std::int64_t create_time_ns = 0;
};

// an attachment's name and data, for what reads kept files of any kind (graph::files_beside)
inline std::string_view name_of(const Attachment& a) { return a.name; }
inline std::string_view data_of(const Attachment& a) { return a.data; }

struct Metadata {
  std::string name;
  StringMap values;
};

class Reader {
 public:
  // maps the file and indexes its data section (chunks are read by for_each). Throws Error
  // naming the file when it cannot be opened or is not MCAP (magic or header missing).
  explicit Reader(const std::string& path);
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  // every readable message in file order; `fn` returns false to stop early
  void for_each(const std::function<bool(const Message&)>& fn);

  // the log times of the first and the last message, from the chunks' headers and the
  // messages outside chunks (nothing is decompressed); {0, 0} when there is none
  std::pair<std::int64_t, std::int64_t> time_span() const;

  // problems found so far ("offset N: what"); empty for a sound file
  const std::vector<std::string>& damage() const { return damage_; }
  // the data end, the footer and the closing magic are there: the file was closed
  bool complete() const { return complete_; }
  // the schemas and channels seen so far (all of them after a full for_each)
  const std::map<std::uint16_t, Schema>& schemas() const { return schemas_; }
  const std::map<std::uint16_t, Channel>& channels() const { return channels_; }
  const std::vector<Metadata>& metadata_records() const { return metadata_; }
  // the values of the first metadata record called `name` (empty when there is none)
  StringMap metadata(std::string_view name) const;
  const std::vector<Attachment>& attachments() const { return attachments_; }
  // the data of the first attachment called `name`
  std::optional<std::string> attachment(std::string_view name) const;

  const std::string& path() const { return path_; }
  std::uint64_t size_bytes() const { return file_.size(); }
  const std::string& profile() const { return profile_; }
  const std::string& library() const { return library_; }

 private:
  // a Message or Chunk record of the data section, in file order
  struct Item {
    Op op;
    std::uint64_t offset;
    std::string_view content;
  };
  void index();
  void unmap();
  bool add_schema(In in);
  bool add_channel(In in);
  // parses a message record; false when malformed
  bool emit_message(std::uint64_t offset, std::string_view content, const std::function<bool(const Message&)>& fn, bool& go_on);
  void report(std::uint64_t offset, const std::string& what);

  std::string path_;
  std::string_view file_;   // the mapped file
  void* map_ = nullptr;
  std::string profile_, library_;
  std::vector<Item> items_;
  std::vector<std::string> index_damage_, damage_;
  bool complete_ = false;
  std::map<std::uint16_t, Schema> schemas_;
  std::map<std::uint16_t, Channel> channels_;
  std::vector<Metadata> metadata_;
  std::vector<Attachment> attachments_;
  std::string chunk_buffer_;
};

}  // namespace enact::record
