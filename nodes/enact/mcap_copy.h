#pragma once
// Copying a recording into a new file: every message (schemas and channels as they come),
// the metadata records and the attachments. Used by `enact recover` and `enact export
// --foxglove`.
#include <cstdint>
#include <functional>

#include "core/record/reader.h"
#include "core/record/writer.h"

namespace enact::cli {

// copies everything readable of `from` into `to` (not closed); `each` (if any) sees every
// message after it was written. Returns the number of messages and of channels copied.
struct CopyCount {
  std::uint64_t messages = 0;
  std::size_t channels = 0;
};
CopyCount copy_recording(record::Reader& from, record::Writer& to, const std::function<void(const record::Message&)>& each = {});

}  // namespace enact::cli
