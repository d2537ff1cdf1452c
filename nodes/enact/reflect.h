#pragma once
// Protobuf messages by field name, for the command line (enact topic echo --field, topic pub):
// field paths read out of a message, YAML mapped onto one, both through reflection.
#include <google/protobuf/message.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

namespace enact::cli {

// a path of fields in a message type: "force.x", "header.seq", "pins", "contacts[2].depth_m"
struct FieldPath {
  struct Step {
    const google::protobuf::FieldDescriptor* field;
    int index;  // of a repeated field; -1: all its elements, as a list
  };
  std::string text;
  std::vector<Step> steps;
};

// `path` resolved in `type`; UsageError naming the message's fields where it fails, and
// the closest one ("did you mean")
FieldPath resolve_field(const google::protobuf::Descriptor& type, const std::string& path);
// the columns `path` gives: itself for a value or a list, one per leaf for a message
// (position: position.x, position.y, position.z)
std::vector<FieldPath> resolve_columns(const google::protobuf::Descriptor& type, const std::string& path);

// the value at `path` in `m` as text: numbers, true / false, enum names, text; a repeated
// field (or a path through one) as a list "[a, b, c]", a message as {field: value ...};
// an index past the end gives ""
std::string field_text(const google::protobuf::Message& m, const FieldPath& path);

// `text` quoted for a CSV cell when it holds a comma, a quote or a line break (RFC 4180)
std::string csv_cell(const std::string& text);

// `m` filled from `node`, a YAML mapping of field names (nested mappings for messages,
// sequences for repeated fields, enum names or numbers); UsageError naming the field,
// what it needs and, for an unknown one, the message's fields
void fill_from_yaml(const YAML::Node& node, google::protobuf::Message& m);

}  // namespace enact::cli
