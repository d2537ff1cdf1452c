#include "core/record/reader.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/record/compression.h"

namespace enact::record {
namespace {

std::int64_t i64(std::uint64_t t) { return t > static_cast<std::uint64_t>(INT64_MAX) ? INT64_MAX : static_cast<std::int64_t>(t); }

StringMap read_map(In& in) {
  StringMap m;
  In block{in.take(in.u32())};
  while (!in.bad && !block.bad && block.at < block.s.size()) {
    const std::string_view k = block.str();
    const std::string_view v = block.str();
    if (!block.bad) m.emplace(k, v);
  }
  in.bad |= block.bad;
  return m;
}

// a record's kind as the specification names it: "message index", "chunk", ...; "" for an opcode it does not
const char* op_name(Op op) {
  switch (op) {
    case Op::header: return "header";
    case Op::footer: return "footer";
    case Op::schema: return "schema";
    case Op::channel: return "channel";
    case Op::message: return "message";
    case Op::chunk: return "chunk";
    case Op::message_index: return "message index";
    case Op::chunk_index: return "chunk index";
    case Op::attachment: return "attachment";
    case Op::attachment_index: return "attachment index";
    case Op::statistics: return "statistics";
    case Op::metadata: return "metadata";
    case Op::metadata_index: return "metadata index";
    case Op::summary_offset: return "summary offset";
    case Op::data_end: return "data end";
  }
  return "";
}

// "chunk record", "record of opcode 0x7f"
std::string record_name(Op op) {
  const std::string name = op_name(op);
  if (!name.empty()) return name + " record";
  char opcode[48];
  std::snprintf(opcode, sizeof opcode, "record of opcode 0x%02x", static_cast<unsigned>(op));
  return opcode;
}

// with its article: "a chunk record", "an attachment record"
std::string a_record(Op op) {
  const std::string name = record_name(op);
  return (std::string("aeiou").find(name[0]) == std::string::npos ? "a " : "an ") + name;
}

}  // namespace

Reader::Reader(const std::string& path) : path_(path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error(path + ": cannot open: " + std::strerror(errno) + "\n  fix: give the path of an MCAP recording (enact record, enact-logger)");
  struct stat st {};
  ::fstat(fd, &st);
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size > 0) {
    map_ = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
    if (map_ == MAP_FAILED) map_ = nullptr;
  }
  ::close(fd);
  if (size > 0 && !map_) throw Error(path + ": cannot map the file: " + std::strerror(errno));
  file_ = std::string_view(static_cast<const char*>(map_), size);
  if (file_.substr(0, kMagic.size()) != kMagic) {
    const bool empty = file_.empty();
    unmap();
    throw Error(path + (empty ? ": empty file, not an MCAP recording" : ": not an MCAP file (it does not start with the MCAP magic 0x89 'MCAP0')") +
                "\n  fix: give a recording made by `enact record` (or another MCAP writer)");
  }
  index();
}

Reader::~Reader() { unmap(); }

void Reader::unmap() {
  if (map_) ::munmap(map_, file_.size());
  map_ = nullptr;
}

void Reader::report(std::uint64_t offset, const std::string& what) { damage_.push_back("offset " + std::to_string(offset) + ": " + what); }

bool Reader::add_schema(In in) {
  Schema s;
  s.id = in.u16();
  s.name = in.str();
  s.encoding = in.str();
  s.data = in.str();
  if (in.bad || s.id == 0) return !in.bad;  // id 0 is invalid and ignored (spec)
  schemas_.insert_or_assign(s.id, std::move(s));
  return true;
}

bool Reader::add_channel(In in) {
  Channel c;
  c.id = in.u16();
  c.schema_id = in.u16();
  c.topic = in.str();
  c.message_encoding = in.str();
  c.metadata = read_map(in);
  if (in.bad) return false;
  channels_.insert_or_assign(c.id, std::move(c));
  return true;
}

void Reader::index() {
  std::size_t at = kMagic.size();
  bool header = true, data_end = false;
  while (at < file_.size()) {
    if (file_.size() - at < kRecordPrefix) {
      if (header) break;
      report(at, "truncated: " + std::to_string(file_.size() - at) + " bytes left, not a whole record (the recording was cut off)");
      break;
    }
    In prefix{file_.substr(at, kRecordPrefix)};
    const auto op = static_cast<Op>(prefix.u8());
    const std::uint64_t length = prefix.u64();
    if (length > file_.size() - at - kRecordPrefix) {
      if (header) break;
      report(at, "truncated: " + a_record(op) + " of " + std::to_string(length) + " bytes runs past the end of the file (the recording was cut off)");
      break;
    }
    const std::string_view content = file_.substr(at + kRecordPrefix, static_cast<std::size_t>(length));
    if (header) {
      In in{content};
      profile_ = in.str();
      library_ = in.str();
      if (op != Op::header || in.bad) break;
      header = false;
      at += kRecordPrefix + content.size();
      continue;
    }
    bool ok = true;
    switch (op) {
      case Op::schema: ok = add_schema(In{content}); break;
      case Op::channel: ok = add_channel(In{content}); break;
      case Op::message:
      case Op::chunk: items_.push_back({op, at, content}); break;
      case Op::metadata: {
        In in{content};
        Metadata m;
        m.name = in.str();
        m.values = read_map(in);
        ok = !in.bad;
        if (ok) metadata_.push_back(std::move(m));
        break;
      }
      case Op::attachment: {
        In in{content};
        Attachment a;
        a.log_time_ns = i64(in.u64());
        a.create_time_ns = i64(in.u64());
        a.name = in.str();
        a.media_type = in.str();
        a.data = in.bytes64();
        const std::size_t fields = in.at;
        const std::uint32_t crc = in.u32();
        ok = !in.bad;
        if (ok && crc != 0 && crc != crc32(0, content.data(), fields)) {
          report(at, "attachment '" + a.name + "': CRC mismatch (corrupted), skipped");
        } else if (ok) {
          attachments_.push_back(std::move(a));
        }
        break;
      }
      case Op::data_end: data_end = true; break;
      default: break;  // indexes, summary records and unknown opcodes: nothing to read here
    }
    if (!ok) report(at, "malformed " + record_name(op) + ", skipped");
    at += kRecordPrefix + content.size();
    if (data_end || op == Op::footer) break;
  }
  if (header) {
    unmap();
    throw Error(path_ + ": not an MCAP file (no header record after the magic)\n  fix: give a recording made by `enact record`");
  }
  // a closed file ends with a 20-byte footer and the magic
  const std::size_t tail = kRecordPrefix + 20 + kMagic.size();
  complete_ = data_end && file_.size() >= at + tail - kMagic.size() && file_.substr(file_.size() - kMagic.size()) == kMagic &&
              static_cast<Op>(file_[file_.size() - tail]) == Op::footer;
  if (!data_end && damage_.empty()) report(at, "no data end record: the recording was not closed (`enact recover` rebuilds its index)");
  index_damage_ = damage_;
}

std::pair<std::int64_t, std::int64_t> Reader::time_span() const {
  std::int64_t first = INT64_MAX, last = INT64_MIN;
  for (const Item& item : items_) {
    In in{item.content};
    // a chunk begins with its messages' start and end times; a message has its channel
    // and sequence before its log time
    if (item.op == Op::message) in.u16(), in.u32();
    const std::int64_t begin = i64(in.u64());
    const std::int64_t end = item.op == Op::chunk ? i64(in.u64()) : begin;
    if (in.bad || (item.op == Op::chunk && end == 0)) continue;
    first = std::min(first, begin);
    last = std::max(last, end);
  }
  return first <= last ? std::pair{first, last} : std::pair<std::int64_t, std::int64_t>{0, 0};
}

bool Reader::emit_message(std::uint64_t offset, std::string_view content, const std::function<bool(const Message&)>& fn, bool& go_on) {
  In in{content};
  Message m;
  const std::uint16_t channel_id = in.u16();
  m.sequence = in.u32();
  m.log_time_ns = i64(in.u64());
  m.publish_time_ns = i64(in.u64());
  if (in.bad) return false;
  m.data = in.rest();
  const auto c = channels_.find(channel_id);
  if (c == channels_.end()) {
    report(offset, "message on unknown channel " + std::to_string(channel_id) + ", skipped");
    return true;
  }
  m.channel = &c->second;
  m.topic = m.channel->topic;
  if (m.channel->schema_id != 0) {
    const auto s = schemas_.find(m.channel->schema_id);
    if (s == schemas_.end()) {
      report(offset, "channel '" + m.channel->topic + "' refers to unknown schema " + std::to_string(m.channel->schema_id) +
                         ": its message is given without a schema");
    } else {
      m.schema = &s->second;
      m.schema_name = m.schema->name;
    }
  }
  go_on = fn(m);
  return true;
}

void Reader::for_each(const std::function<bool(const Message&)>& fn) {
  damage_ = index_damage_;
  bool go_on = true;
  for (const Item& item : items_) {
    if (!go_on) return;
    if (item.op == Op::message) {
      if (!emit_message(item.offset, item.content, fn, go_on)) report(item.offset, "malformed message record, skipped");
      continue;
    }
    In in{item.content};
    in.u64();  // message start and end times
    in.u64();
    const std::uint64_t size = in.u64();
    const std::uint32_t crc = in.u32();
    const std::string_view compression = in.str();
    const std::string_view records = in.bytes64();
    if (in.bad) {
      report(item.offset, "malformed chunk record, skipped");
      continue;
    }
    if (!decompress(compression, records, size, chunk_buffer_)) {
      report(item.offset, "chunk cannot be decompressed (" + (compression.empty() ? std::string("none") : std::string(compression)) +
                              "; corrupted or unsupported): its messages are skipped");
      continue;
    }
    if (crc != 0 && crc != crc32(0, chunk_buffer_.data(), chunk_buffer_.size())) {
      report(item.offset, "chunk CRC mismatch (corrupted): its messages are skipped");
      continue;
    }
    // the records inside: schemas, channels, messages
    std::size_t at = 0;
    const std::string_view inner = chunk_buffer_;
    while (go_on && at < inner.size()) {
      In prefix{inner.substr(at, kRecordPrefix)};
      const auto op = static_cast<Op>(prefix.u8());
      const std::uint64_t length = prefix.u64();
      if (prefix.bad || length > inner.size() - at - kRecordPrefix) {
        report(item.offset, "chunk holds a cut record at " + std::to_string(at) + ": the rest of the chunk is skipped");
        break;
      }
      const std::string_view content = inner.substr(at + kRecordPrefix, static_cast<std::size_t>(length));
      bool ok = true;
      if (op == Op::schema) ok = add_schema(In{content});
      if (op == Op::channel) ok = add_channel(In{content});
      if (op == Op::message) ok = emit_message(item.offset, content, fn, go_on);
      if (!ok) report(item.offset, "malformed " + record_name(op) + " inside the chunk, skipped");
      at += kRecordPrefix + content.size();
    }
  }
}

StringMap Reader::metadata(std::string_view name) const {
  for (const Metadata& m : metadata_) {
    if (m.name == name) return m.values;
  }
  return {};
}

std::optional<std::string> Reader::attachment(std::string_view name) const {
  for (const Attachment& a : attachments_) {
    if (a.name == name) return a.data;
  }
  return std::nullopt;
}

}  // namespace enact::record
