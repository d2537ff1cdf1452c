#include "core/record/writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/record/mcap.h"

namespace enact::record {
namespace {

std::uint64_t u64(std::int64_t t) { return static_cast<std::uint64_t>(t < 0 ? 0 : t); }

void write_all(int fd, const std::string& path, const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw Error(path + ": cannot write: " + std::strerror(errno) + "\n  fix: check the disk has room and the folder is writable");
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

void map_field(Out& o, const StringMap& m) {
  const std::size_t at = o.begin_block();
  for (const auto& [k, v] : m) {
    o.str(k);
    o.str(v);
  }
  o.end_block(at);
}

}  // namespace

template <class Fill>
void Writer::append_record(std::string& s, Op op, Fill fill) {
  Out o{s};
  const std::size_t at = o.begin_record(op);
  fill(o);
  o.end_record(at);
}

Writer::Writer(const std::string& path, WriterOptions options) : path_(path), options_(std::move(options)) {
  if (options_.chunk_size_bytes < 1 || options_.chunk_duration_ns < 1) throw Error(path + ": chunk size and duration must be > 0");
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error(path + ": cannot create: " + std::strerror(errno) + "\n  fix: check the folder exists and is writable");
  out_.append(kMagic);
  append_record(out_, Op::header, [&](Out& o) {
    o.str(options_.profile);
    o.str(options_.library);
  });
  drain();
}

Writer::~Writer() {
  try {
    close();
  } catch (...) {
  }
}

void Writer::drain() {
  try {
    write_all(fd_, path_, out_.data(), out_.size());
  } catch (...) {
    // a full disk: the file ends at the last whole record again (readable, and closed if what
    // is left of the room holds the summary)
    if (::ftruncate(fd_, static_cast<off_t>(offset_)) == 0) (void)::lseek(fd_, static_cast<off_t>(offset_), SEEK_SET);
    out_.clear();
    throw;
  }
  data_crc_ = crc32(data_crc_, out_.data(), out_.size());
  offset_ += out_.size();
  out_.clear();
}

std::uint16_t Writer::add_schema(std::string_view name, std::string_view encoding, std::string_view data) {
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
  std::string rec;
  append_record(rec, Op::schema, [&](Out& o) {
    o.u16(id);
    o.str(name);
    o.str(encoding);
    o.str(data);
  });
  out_ += rec;
  schemas_.push_back(std::move(rec));
  drain();
  return id;
}

std::uint16_t Writer::add_channel(std::uint16_t schema_id, std::string_view topic, std::string_view message_encoding,
                                  const StringMap& metadata) {
  const auto id = static_cast<std::uint16_t>(channels_.size());
  std::string rec;
  append_record(rec, Op::channel, [&](Out& o) {
    o.u16(id);
    o.u16(schema_id);
    o.str(topic);
    o.str(message_encoding);
    map_field(o, metadata);
  });
  out_ += rec;
  channels_.push_back(std::move(rec));
  tally_.channel_counts[id];
  written_.channel_counts[id];
  drain();
  return id;
}

void Writer::write(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns, std::int64_t publish_time_ns,
                   std::string_view data) {
  // a message past the open chunk's span closes it first
  flush_if_due(log_time_ns);
  if (!chunk_open_) {
    chunk_open_ = true;
    chunk_start_ = chunk_end_ = log_time_ns;
  }
  message_index_[channel_id].emplace_back(u64(log_time_ns), chunk_.size());
  append_record(chunk_, Op::message, [&](Out& o) {
    o.u16(channel_id);
    o.u32(sequence);
    o.u64(u64(log_time_ns));
    o.u64(u64(publish_time_ns));
    o.s.append(data);
  });
  chunk_start_ = std::min(chunk_start_, log_time_ns);
  chunk_end_ = std::max(chunk_end_, log_time_ns);
  Tally& t = tally_;
  t.first_time = t.messages == 0 ? log_time_ns : std::min(t.first_time, log_time_ns);
  t.last_time = t.messages == 0 ? log_time_ns : std::max(t.last_time, log_time_ns);
  ++t.messages;
  ++t.channel_counts[channel_id];
  if (chunk_.size() >= options_.chunk_size_bytes) flush();
}

void Writer::flush_if_due(std::int64_t now_ns) {
  if (chunk_open_ && now_ns - chunk_start_ >= options_.chunk_duration_ns) flush();
}

void Writer::flush() {
  if (!chunk_open_) return;
  compress(options_.compression, chunk_, compressed_);
  ChunkIndex ci;
  ci.start_time = u64(chunk_start_);
  ci.end_time = u64(chunk_end_);
  ci.offset = offset_;
  ci.compressed_size = compressed_.size();
  ci.uncompressed_size = chunk_.size();
  append_record(out_, Op::chunk, [&](Out& o) {
    o.u64(ci.start_time);
    o.u64(ci.end_time);
    o.u64(ci.uncompressed_size);
    o.u32(crc32(0, chunk_.data(), chunk_.size()));
    o.str(mcap_name(options_.compression));
    o.bytes64(compressed_);
  });
  ci.length = out_.size();
  // one message index per channel with messages in the chunk, right after it
  // (named pairs, not structured bindings: clang 14, the fuzz build's, cannot capture those)
  for (auto& index : message_index_) {
    const std::uint16_t channel = index.first;
    auto& entries = index.second;
    if (entries.empty()) continue;
    ci.index_offsets.emplace_back(channel, offset_ + out_.size());
    append_record(out_, Op::message_index, [&](Out& o) {
      o.u16(channel);
      const std::size_t at = o.begin_block();
      for (const auto& [time, offset] : entries) {
        o.u64(time);
        o.u64(offset);
      }
      o.end_block(at);
    });
    entries.clear();
  }
  ci.index_length = out_.size() - ci.length;
  chunk_.clear();
  chunk_open_ = false;
  try {
    drain();
  } catch (...) {
    tally_ = written_;  // the chunk's messages are not in the file
    throw;
  }
  chunk_indexes_.push_back(std::move(ci));
  written_ = tally_;
}

void Writer::add_metadata(std::string_view name, const StringMap& values) {
  Index ix;
  ix.offset = offset_ + out_.size();
  ix.name = name;
  append_record(out_, Op::metadata, [&](Out& o) {
    o.str(name);
    map_field(o, values);
  });
  ix.length = offset_ + out_.size() - ix.offset;
  drain();
  metadata_.push_back(std::move(ix));
}

void Writer::add_attachment(std::string_view name, std::string_view media_type, std::string_view data, std::int64_t log_time_ns,
                            std::int64_t create_time_ns) {
  Index ix;
  ix.offset = offset_ + out_.size();
  ix.log_time = log_time_ns;
  ix.create_time = create_time_ns;
  ix.data_size = data.size();
  ix.name = name;
  ix.media_type = media_type;
  append_record(out_, Op::attachment, [&](Out& o) {
    const std::size_t fields = o.s.size();
    o.u64(u64(log_time_ns));
    o.u64(u64(create_time_ns));
    o.str(name);
    o.str(media_type);
    o.bytes64(data);
    o.u32(crc32(0, o.s.data() + fields, o.s.size() - fields));  // of the fields before it
  });
  ix.length = offset_ + out_.size() - ix.offset;
  drain();
  attachments_.push_back(std::move(ix));
}

void Writer::close() {
  if (fd_ < 0) return;
  try {
    finish();
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
  ::close(fd_);
  fd_ = -1;
}

void Writer::append_statistics(std::string& s) {
  append_record(s, Op::statistics, [&](Out& o) {
    o.u64(written_.messages);
    o.u16(static_cast<std::uint16_t>(schemas_.size()));
    o.u32(static_cast<std::uint32_t>(channels_.size()));
    o.u32(static_cast<std::uint32_t>(attachments_.size()));
    o.u32(static_cast<std::uint32_t>(metadata_.size()));
    o.u32(static_cast<std::uint32_t>(chunk_indexes_.size()));
    o.u64(u64(written_.first_time));
    o.u64(u64(written_.last_time));
    const std::size_t at = o.begin_block();
    for (const auto& [id, n] : written_.channel_counts) {
      o.u16(id);
      o.u64(n);
    }
    o.end_block(at);
  });
}

void Writer::append_chunk_indexes(std::string& s) {
  for (const ChunkIndex& c : chunk_indexes_) {
    append_record(s, Op::chunk_index, [&](Out& o) {
      o.u64(c.start_time);
      o.u64(c.end_time);
      o.u64(c.offset);
      o.u64(c.length);
      const std::size_t at = o.begin_block();
      for (const auto& [id, off] : c.index_offsets) {
        o.u16(id);
        o.u64(off);
      }
      o.end_block(at);
      o.u64(c.index_length);
      o.str(mcap_name(options_.compression));
      o.u64(c.compressed_size);
      o.u64(c.uncompressed_size);
    });
  }
}

void Writer::append_attachment_indexes(std::string& s) {
  for (const Index& a : attachments_) {
    append_record(s, Op::attachment_index, [&](Out& o) {
      o.u64(a.offset);
      o.u64(a.length);
      o.u64(u64(a.log_time));
      o.u64(u64(a.create_time));
      o.u64(a.data_size);
      o.str(a.name);
      o.str(a.media_type);
    });
  }
}

void Writer::append_metadata_indexes(std::string& s) {
  for (const Index& m : metadata_) {
    append_record(s, Op::metadata_index, [&](Out& o) {
      o.u64(m.offset);
      o.u64(m.length);
      o.str(m.name);
    });
  }
}

void Writer::finish() {
  flush();  // drains: data_crc_ now covers every byte before the data end record
  // the data end, the summary and the footer in one write: on a full disk the file ends
  // at the last chunk or metadata record instead
  append_record(out_, Op::data_end, [&](Out& o) { o.u32(data_crc_); });
  // summary: records grouped by opcode, each group located by a summary offset record
  const std::uint64_t summary_start = offset_ + out_.size();
  std::vector<std::pair<Op, std::pair<std::uint64_t, std::uint64_t>>> groups;
  std::string s;
  auto group = [&](Op op, auto&& body) {
    const std::size_t start = s.size();
    body();
    if (s.size() > start) groups.push_back({op, {summary_start + start, s.size() - start}});
  };
  group(Op::schema, [&] { for (const auto& r : schemas_) s += r; });
  group(Op::channel, [&] { for (const auto& r : channels_) s += r; });
  group(Op::statistics, [&] { append_statistics(s); });
  group(Op::chunk_index, [&] { append_chunk_indexes(s); });
  group(Op::attachment_index, [&] { append_attachment_indexes(s); });
  group(Op::metadata_index, [&] { append_metadata_indexes(s); });
  const std::uint64_t summary_offset_start = summary_start + s.size();
  for (const auto& offsets : groups) {
    append_record(s, Op::summary_offset, [&](Out& o) {
      o.u8(static_cast<std::uint8_t>(offsets.first));
      o.u64(offsets.second.first);
      o.u64(offsets.second.second);
    });
  }
  // footer: the summary CRC covers the summary up to and including summary_offset_start
  Out o{s};
  o.u8(static_cast<std::uint8_t>(Op::footer));
  o.u64(20);
  o.u64(summary_start);
  o.u64(summary_offset_start);
  o.u32(crc32(0, s.data(), s.size()));
  s.append(kMagic);
  out_ += s;
  drain();
}

}  // namespace enact::record
