#include "nodes/enact/mcap_copy.h"

#include <map>

namespace enact::cli {

CopyCount copy_recording(record::Reader& from, record::Writer& to, const std::function<void(const record::Message&)>& each) {
  std::map<std::uint16_t, std::uint16_t> schema_ids, channel_ids;
  CopyCount n;
  from.for_each([&](const record::Message& m) {
    auto c = channel_ids.find(m.channel->id);
    if (c == channel_ids.end()) {
      std::uint16_t schema = 0;
      if (m.schema) {
        auto s = schema_ids.find(m.schema->id);
        if (s == schema_ids.end()) s = schema_ids.emplace(m.schema->id, to.add_schema(m.schema->name, m.schema->encoding, m.schema->data)).first;
        schema = s->second;
      }
      c = channel_ids.emplace(m.channel->id, to.add_channel(schema, m.channel->topic, m.channel->message_encoding, m.channel->metadata)).first;
    }
    to.write(c->second, m.sequence, m.log_time_ns, m.publish_time_ns, m.data);
    ++n.messages;
    if (each) each(m);
    return true;
  });
  for (const auto& m : from.metadata_records()) to.add_metadata(m.name, m.values);
  for (const auto& at : from.attachments()) to.add_attachment(at.name, at.media_type, at.data, at.log_time_ns, at.create_time_ns);
  n.channels = channel_ids.size();
  return n;
}

}  // namespace enact::cli
