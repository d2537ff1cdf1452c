#include "core/foxglove/parameters.h"

#include <algorithm>
#include <cstdlib>
#include <vector>

#include <google/protobuf/util/json_util.h>

#include "core/params/param_bus.h"

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
    for (const json& item : value) {
      if (!joined.empty()) joined += ',';
      joined += item.is_string() ? item.get<std::string>() : item.dump();
    }
    graph::set_value(update, joined);
  } else {
    return false;
  }
  return true;
}

namespace {

bool is_default(const json& v) { return v.is_null() || (v.is_number() && v.get<double>() == 0.0) || v == "" || v == false; }

// Studio's Publish panel writes every field of the schema into its template, each member of
// a oneof included: of a oneof's members, those at their default are dropped while another
// is present (all at their default: the first one is kept), so the one the user filled is
// the one set. Members set to two values are left for the parser to refuse.
void keep_one_of_each_oneof(json& object, const google::protobuf::Descriptor& type) {
  for (int o = 0; o < type.oneof_decl_count(); ++o) {
    const google::protobuf::OneofDescriptor& oneof = *type.oneof_decl(o);
    std::vector<std::string> present;
    for (int f = 0; f < oneof.field_count(); ++f) {
      for (const std::string& key : {oneof.field(f)->name(), oneof.field(f)->json_name()}) {
        if (object.contains(key) && std::find(present.begin(), present.end(), key) == present.end()) present.push_back(key);
      }
    }
    const bool all_default = std::all_of(present.begin(), present.end(), [&](const std::string& k) { return is_default(object[k]); });
    for (std::size_t i = all_default ? 1 : 0; i < present.size(); ++i) {
      if (is_default(object[present[i]])) object.erase(present[i]);
    }
  }
}

}  // namespace

std::string decode(std::string_view encoding, std::string_view payload, google::protobuf::Message& msg) {
  if (encoding == "protobuf") {
    return msg.ParseFromArray(payload.data(), static_cast<int>(payload.size())) ? "" : "bytes that are not an " + msg.GetTypeName();
  }
  if (encoding != "json") return "encoding '" + std::string(encoding) + "' is not one of json, protobuf";
  json object = json::parse(payload, nullptr, false);
  if (object.is_object()) keep_one_of_each_oneof(object, *msg.GetDescriptor());
  const std::string text = object.is_discarded() ? std::string(payload) : object.dump();
  const auto status = google::protobuf::util::JsonStringToMessage(text, &msg);
  return status.ok() ? "" : "JSON that is not an " + msg.GetTypeName() + ": " + std::string(status.message());
}

}  // namespace enact::foxglove
