#include "core/record/writer.h"

#include <fcntl.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "core/record/mcap.h"

namespace enact::record {
namespace {

std::uint64_t u64(std::int64_t t) { return static_cast<std::uint64_t>(t < 0 ? 0 : t); }

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
  try {
    drain();
  } catch (...) {
    ::close(fd_);
    throw;
  }
  // one worker per CPU: compressing is most of a chunk's cost
  const unsigned workers = std::clamp(std::thread::hardware_concurrency(), 1u, kMaxWorkers);
  try {
    for (unsigned k = 0; k < workers; ++k) {
      workers_.push_back(std::make_unique<Worker>(options_.compression));
      Worker& w = *workers_.back();
      w.thread = std::thread([this, &w] { work(w); });
    }
  } catch (...) {
    stop_workers();
    ::close(fd_);
    throw;
  }
}

Writer::~Writer() {
  try {
    close();
  } catch (...) {
  }
}

void Writer::append_to_file(std::initializer_list<std::string_view> parts) {
  iovec iov[4];
  int count = 0;
  std::size_t total = 0;
  for (const std::string_view part : parts) {
    iov[count++] = {const_cast<char*>(part.data()), part.size()};
    total += part.size();
  }
  for (iovec* at = iov; total > 0;) {
    const ssize_t n = ::writev(fd_, at, static_cast<int>(iov + count - at));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = errno;
      // a full disk: the file ends at the last whole record again (readable, and closed if
      // what is left of the room holds the summary)
      if (::ftruncate(fd_, static_cast<off_t>(offset_)) == 0) (void)::lseek(fd_, static_cast<off_t>(offset_), SEEK_SET);
      throw Error(path_ + ": cannot write: " + std::strerror(error) + "\n  fix: check the disk has room and the folder is writable");
    }
    total -= static_cast<std::size_t>(n);
    for (std::size_t left = static_cast<std::size_t>(n); left > 0;) {
      const std::size_t took = std::min(left, at->iov_len);
      at->iov_base = static_cast<char*>(at->iov_base) + took;
      at->iov_len -= took;
      left -= took;
      if (at->iov_len == 0) ++at;
    }
  }
}

void Writer::drain() {
  try {
    append_to_file({out_});
  } catch (...) {
    out_.clear();
    throw;
  }
  data_crc_ = crc32(data_crc_, out_.data(), out_.size());
  offset_ += out_.size();
  out_.clear();
}

std::uint16_t Writer::add_schema(std::string_view name, std::string_view encoding, std::string_view data) {
  wait_for_workers();
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
  wait_for_workers();
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
  written_.channel_counts.push_back(0);
  drain();
  return id;
}

char* Writer::extend_chunk(std::size_t n) {
  Chunk& c = open_;
  if (c.capacity - c.size < n) {
    // a chunk's room at first, then twice as much when a message does not fit; the next
    // chunks keep it (a chunk closes at chunk_size_bytes: its last message is in the margin)
    const std::size_t first = std::min(options_.chunk_size_bytes, std::size_t{64} << 20) + (std::size_t{64} << 10);
    const std::size_t capacity = std::max({c.capacity * 2, c.size + n, first});
    auto bigger = std::make_unique_for_overwrite<char[]>(capacity);
    if (c.size > 0) std::memcpy(bigger.get(), c.records.get(), c.size);
    c.records = std::move(bigger);
    c.capacity = capacity;
  }
  char* at = c.records.get() + c.size;
  c.size += n;
  return at;
}

void Writer::write(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns, std::int64_t publish_time_ns,
                   std::string_view data) {
  if (channel_id >= channels_.size()) throw Error(path_ + ": no channel " + std::to_string(channel_id) + "\n  fix: write on a channel add_channel returned");
  // a message past the open chunk's span closes it first
  flush_if_due(log_time_ns);
  Chunk& c = open_;
  if (c.messages == 0) c.start = c.end = log_time_ns;
  put_message(extend_chunk(message_record_size(data.size())), channel_id, sequence, u64(log_time_ns), u64(publish_time_ns), data);
  c.start = std::min(c.start, log_time_ns);
  c.end = std::max(c.end, log_time_ns);
  ++c.messages;
  ++messages_;
  if (c.size >= options_.chunk_size_bytes) close_chunk(false);
}

void Writer::flush_if_due(std::int64_t now_ns) {
  if (failed_.load(std::memory_order_relaxed)) wait_for_workers();
  if (open_.messages > 0 && now_ns - open_.start >= options_.chunk_duration_ns) close_chunk(true);
}

void Writer::flush() {
  if (open_.messages > 0) close_chunk(true);
  wait_for_workers();
}

void Writer::close_chunk(bool wait) {
  if (failed_.load(std::memory_order_relaxed)) wait_for_workers();
  // the workers take turns: this one's previous chunk is written first
  Worker& w = *workers_[handed_ % workers_.size()];
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !w.busy; });
    std::swap(open_, w.chunk);
    w.turn = handed_++;
    w.busy = true;
  }
  changed_.notify_all();
  open_.size = 0;
  open_.messages = 0;
  ++chunks_;
  if (wait) wait_for_workers();
}

void Writer::wait_for_workers() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return done_ == handed_; });
  if (failure_.empty()) return;
  const std::string failure = std::move(failure_);
  failure_.clear();
  failed_ = false;
  lock.unlock();
  open_.size = 0;
  open_.messages = 0;
  messages_ = written_.messages;
  chunks_ = chunk_indexes_.size();
  throw Error(failure);
}

void Writer::work(Worker& w) {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return w.busy || stopping_; });
    if (!w.busy) return;
    lock.unlock();
    std::string failure;
    try {
      make_chunk(w);
    } catch (const std::exception& e) {
      failure = e.what();
    }
    lock.lock();
    changed_.wait(lock, [&] { return done_ == w.turn; });
    // after a failure the chunks behind it are given up: the file has no hole
    if (failure.empty() && failure_.empty()) {
      lock.unlock();
      try {
        append_chunk(w);
      } catch (const std::exception& e) {
        failure = e.what();
      }
      lock.lock();
    }
    if (!failure.empty() && failure_.empty()) {
      failure_ = std::move(failure);
      failed_ = true;
    }
    ++done_;
    w.busy = false;
    changed_.notify_all();
  }
}

void Writer::make_chunk(Worker& w) {
  const Chunk& chunk = w.chunk;
  const std::string_view records = chunk.view();
  w.records_crc = crc32(0, records.data(), records.size());
  w.body = w.compressor.compress(records);
  const std::string_view compression = mcap_name(options_.compression);
  ChunkIndex& ci = w.index;
  ci.start_time = u64(chunk.start);
  ci.end_time = u64(chunk.end);
  ci.compressed_size = w.body.size();
  ci.uncompressed_size = records.size();
  ci.index_offsets.clear();
  // the Chunk record up to its records (which follow it in the file from where they are)
  w.head.clear();
  Out o{w.head};
  o.u8(static_cast<std::uint8_t>(Op::chunk));
  o.u64(8 + 8 + 8 + 4 + 4 + compression.size() + 8 + w.body.size());
  o.u64(ci.start_time);
  o.u64(ci.end_time);
  o.u64(ci.uncompressed_size);
  o.u32(w.records_crc);
  o.str(compression);
  o.u64(w.body.size());
  ci.length = w.head.size() + w.body.size();
  // one message index per channel with messages in the chunk, right after it: the records'
  // (log time, offset) grouped by channel, in the order written (a counting sort)
  std::vector<std::uint64_t>& ends = w.counts;
  ends.assign(channels_.size() + 1, 0);
  const auto each_record = [&](auto&& f) {
    for (std::size_t at = 0; at < records.size(); at += kRecordPrefix + get<std::uint64_t>(records.data() + at + 1)) {
      f(at, records.data() + at + kRecordPrefix);
    }
  };
  each_record([&](std::size_t, const char* fields) { ++ends[get<std::uint16_t>(fields) + 1]; });
  for (std::size_t k = 1; k < ends.size(); ++k) ends[k] += ends[k - 1];  // where each channel's entries start
  w.by_channel.resize(chunk.messages);
  each_record([&](std::size_t at, const char* fields) { w.by_channel[ends[get<std::uint16_t>(fields)]++] = {get<std::uint64_t>(fields + 2 + 4), at}; });
  // each Message Index record: op, length, channel id, the entries' byte length, then 16
  // bytes an entry, written in place (the string sized once: no append a field)
  constexpr std::size_t kIndexHead = kRecordPrefix + 2 + 4;
  std::size_t total = 0;
  for (std::size_t channel = 0, from = 0; channel + 1 < ends.size(); from = ends[channel++]) {
    if (ends[channel] != from) total += kIndexHead + 16 * (ends[channel] - from);
  }
  w.indexes.resize(total);
  char* p = w.indexes.data();
  for (std::size_t channel = 0, from = 0; channel + 1 < ends.size(); from = ends[channel++]) {
    if (ends[channel] == from) continue;
    ci.index_offsets.emplace_back(static_cast<std::uint16_t>(channel), ci.length + static_cast<std::uint64_t>(p - w.indexes.data()));
    const std::uint64_t entries = 16 * (ends[channel] - from);
    p = put(p, static_cast<std::uint8_t>(Op::message_index));
    p = put(p, std::uint64_t{2 + 4 + entries});
    p = put(p, static_cast<std::uint16_t>(channel));
    p = put(p, static_cast<std::uint32_t>(entries));
    for (std::size_t e = from; e < ends[channel]; ++e) {
      p = put(p, w.by_channel[e].first);
      p = put(p, w.by_channel[e].second);
    }
  }
  ci.index_length = w.indexes.size();
}

void Writer::append_chunk(Worker& w) {
  const std::string_view records = w.chunk.view();
  append_to_file({w.head, w.body, w.indexes});
  // in the file: where, the data-section CRC (the records' own when they went uncompressed),
  // the statistics
  ChunkIndex& ci = w.index;
  ci.offset = offset_;
  for (auto& index : ci.index_offsets) index.second += ci.offset;
  std::uint32_t crc = crc32(data_crc_, w.head.data(), w.head.size());
  crc = w.body.data() == records.data() ? crc32_concat(crc, w.records_crc, records.size()) : crc32(crc, w.body.data(), w.body.size());
  data_crc_ = crc32(crc, w.indexes.data(), w.indexes.size());
  offset_ += w.head.size() + w.body.size() + w.indexes.size();
  Tally& t = written_;
  const Chunk& chunk = w.chunk;
  t.first_time = t.messages == 0 ? chunk.start : std::min(t.first_time, chunk.start);
  t.last_time = t.messages == 0 ? chunk.end : std::max(t.last_time, chunk.end);
  t.messages += chunk.messages;
  for (std::size_t channel = 0, from = 0; channel < t.channel_counts.size(); from = w.counts[channel++]) t.channel_counts[channel] += w.counts[channel] - from;
  chunk_indexes_.push_back(ci);
}

void Writer::add_metadata(std::string_view name, const StringMap& values) {
  wait_for_workers();
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
  wait_for_workers();
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

void Writer::stop_workers() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  for (auto& w : workers_) {
    if (w->thread.joinable()) w->thread.join();
  }
}

void Writer::close() {
  if (fd_ < 0) return;
  try {
    finish();
  } catch (...) {
    stop_workers();
    ::close(fd_);
    fd_ = -1;
    throw;
  }
  stop_workers();
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
    for (std::size_t id = 0; id < written_.channel_counts.size(); ++id) {
      o.u16(static_cast<std::uint16_t>(id));
      o.u64(written_.channel_counts[id]);
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
