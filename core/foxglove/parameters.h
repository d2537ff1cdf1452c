#pragma once
// What Foxglove clients send and ask, in enact's terms: a parameter of the graph (each node's
// param/values/<node>) as a Foxglove parameter (the `parameters` capability: getParameters,
// setParameters, parameterValues), a Foxglove parameter value as the ParamUpdate `enact param
// set` sends, and a client-published message (encoding protobuf or json) as its Protobuf
// message. Spec: https://github.com/foxglove/ws-protocol/blob/main/docs/spec.md
#include <string>
#include <string_view>

#include <google/protobuf/message.h>
#include <nlohmann/json.hpp>

#include "msgs/param_update.pb.h"

namespace enact::foxglove {

// the encodings clients may publish in (serverInfo.supportedEncodings)
inline constexpr const char* kClientEncodings[] = {"json", "protobuf"};

// {"name", "value"}: a number for number and integer parameters, a boolean for flags, text
// for the others; no value when none is set
nlohmann::json parameter(const std::string& name, const std::string& value, const std::string& type);
nlohmann::json parameter(const msgs::ParamValues::Param& p);

// sets `update`'s value from a setParameters value: a number, a boolean, text (read as `enact
// param set NAME TEXT` reads it) or an array (its items joined by commas, x,y,z). False for
// anything else (no value: a parameter cannot be unset)
bool set_value(msgs::ParamUpdate& update, const nlohmann::json& value);

// `payload` in `encoding` (protobuf, or json as Protobuf's JSON mapping writes it) into `msg`:
// "" when done, else why not. In json, of a oneof's members those at their default (0, "",
// false) are left out while another is given: Foxglove's Publish panel template lists them all
std::string decode(std::string_view encoding, std::string_view payload, google::protobuf::Message& msg);

}  // namespace enact::foxglove
