#pragma once
// Self-describing schemas: serialized google.protobuf.FileDescriptorSet values, so a client
// (or a recording) decodes bus messages without the .proto files.
#include <string>

namespace google::protobuf {
class Descriptor;
}

namespace enact::bus {

// every msgs/*.proto file, each after the files it imports (the order
// google.protobuf.descriptor_pool.Add needs); sent in GraphInfo.descriptor_set
std::string msgs_descriptor_set();

// the file defining `type` and the files it imports, in the same order
std::string descriptor_set_of(const google::protobuf::Descriptor& type);

}  // namespace enact::bus
