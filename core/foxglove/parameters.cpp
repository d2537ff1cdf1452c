#include "core/foxglove/parameters.h"

#include <cstdlib>

#include <google/protobuf/util/json_util.h>

#include "core/graph/param_bus.h"

namespace enact::foxglove {

using nlohmann::json;

json parameter(const std::string& name, const std::string& value, const std::string& type) {
  json p = {{"name", name}};
  if (value.empty()) return p;
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  if ((type == "number" || type == "integer") && *end == '\0') p["value"] = number;
  else if (type == "flag") p["value"] = value == "true";
  else p["value"] = value;
  return p;
}

json parameter(const msgs::ParamValues::Param& p) { return parameter(p.name(), p.value(), p.type()); }

bool set_value(msgs::ParamUpdate& update, const json& value) {
  if (value.is_number()) update.set_number(value.get<double>());
  else if (value.is_boolean()) update.set_flag(value.get<bool>());
  else if (value.is_string()) graph::set_value(update, value.get<std::string>());
  else if (value.is_array()) {
    std::string joined;
    for (const json& item : value) joined += (joined.empty() ? "" : ",") + (item.is_string() ? item.get<std::string>() : item.dump());
    graph::set_value(update, joined);
  } else {
    return false;
  }
  return true;
}

std::string decode(std::string_view encoding, std::string_view payload, google::protobuf::Message& msg) {
  if (encoding == "protobuf") {
    return msg.ParseFromArray(payload.data(), static_cast<int>(payload.size())) ? "" : "bytes that are not an " + msg.GetTypeName();
  }
  if (encoding != "json") return "encoding '" + std::string(encoding) + "' is not one of json, protobuf";
  const auto status = google::protobuf::util::JsonStringToMessage(google::protobuf::StringPiece(payload.data(), payload.size()), &msg);
  return status.ok() ? "" : "JSON that is not an " + msg.GetTypeName() + ": " + std::string(status.message());
}

}  // namespace enact::foxglove
