#include "nodes/enact/reflect.h"

#include <google/protobuf/descriptor.h>

#include <cstdio>
#include <cstdlib>

#include "core/config/suggest.h"
#include "nodes/enact/args.h"

namespace enact::cli {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

// "unknown field 'x' in enact.msgs.T (did you mean y?); its fields: a, b, c"
[[noreturn]] void unknown_field(const Descriptor& type, const std::string& name, const std::string& where) {
  std::vector<std::string> names;
  std::string list;
  for (int i = 0; i < type.field_count(); ++i) {
    names.push_back(type.field(i)->name());
    list += (i ? ", " : "") + names.back();
  }
  throw UsageError(where + "unknown field '" + name + "' in " + type.full_name() + config::did_you_mean(name, names) + "; its fields: " + list);
}

// a number in the shortest text that reads back the same
std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  for (int digits = 6; digits < 17; ++digits) {
    char shorter[32];
    std::snprintf(shorter, sizeof shorter, "%.*g", digits, v);
    if (std::strtod(shorter, nullptr) == v) return shorter;
  }
  return buf;
}

// one scalar of field `f` (element `i` of a repeated field, -1 for a singular one)
std::string scalar_text(const Message& m, const FieldDescriptor& f, int i) {
  const Reflection& r = *m.GetReflection();
  const bool rep = i >= 0;
  switch (f.cpp_type()) {
    case FieldDescriptor::CPPTYPE_INT32: return std::to_string(rep ? r.GetRepeatedInt32(m, &f, i) : r.GetInt32(m, &f));
    case FieldDescriptor::CPPTYPE_INT64: return std::to_string(rep ? r.GetRepeatedInt64(m, &f, i) : r.GetInt64(m, &f));
    case FieldDescriptor::CPPTYPE_UINT32: return std::to_string(rep ? r.GetRepeatedUInt32(m, &f, i) : r.GetUInt32(m, &f));
    case FieldDescriptor::CPPTYPE_UINT64: return std::to_string(rep ? r.GetRepeatedUInt64(m, &f, i) : r.GetUInt64(m, &f));
    case FieldDescriptor::CPPTYPE_DOUBLE: return number_text(rep ? r.GetRepeatedDouble(m, &f, i) : r.GetDouble(m, &f));
    case FieldDescriptor::CPPTYPE_FLOAT: return number_text(rep ? r.GetRepeatedFloat(m, &f, i) : r.GetFloat(m, &f));
    case FieldDescriptor::CPPTYPE_BOOL: return (rep ? r.GetRepeatedBool(m, &f, i) : r.GetBool(m, &f)) ? "true" : "false";
    case FieldDescriptor::CPPTYPE_ENUM: return (rep ? r.GetRepeatedEnum(m, &f, i) : r.GetEnum(m, &f))->name();
    case FieldDescriptor::CPPTYPE_STRING: return rep ? r.GetRepeatedString(m, &f, i) : r.GetString(m, &f);
    case FieldDescriptor::CPPTYPE_MESSAGE: return "{" + (rep ? r.GetRepeatedMessage(m, &f, i) : r.GetMessage(m, &f)).ShortDebugString() + "}";
  }
  return "";
}

// the value of steps[at...] in m
std::string value_of(const Message& m, const std::vector<FieldPath::Step>& steps, std::size_t at) {
  const FieldPath::Step& s = steps[at];
  const Reflection& r = *m.GetReflection();
  const bool last = at + 1 == steps.size();
  auto element = [&](int i) { return last ? scalar_text(m, *s.field, i) : value_of(r.GetRepeatedMessage(m, s.field, i), steps, at + 1); };
  if (!s.field->is_repeated()) return last ? scalar_text(m, *s.field, -1) : value_of(r.GetMessage(m, s.field), steps, at + 1);
  const int size = r.FieldSize(m, s.field);
  if (s.index >= 0) return s.index < size ? element(s.index) : "";
  std::string out = "[";
  for (int i = 0; i < size; ++i) out += (i ? ", " : "") + element(i);
  return out + "]";
}

// one YAML scalar into field `f` (added to a repeated field when `add`)
void set_scalar(Message& m, const FieldDescriptor& f, const YAML::Node& v, bool add) {
  const Reflection& r = *m.GetReflection();
  try {
    switch (f.cpp_type()) {
      case FieldDescriptor::CPPTYPE_INT32: add ? r.AddInt32(&m, &f, v.as<std::int32_t>()) : r.SetInt32(&m, &f, v.as<std::int32_t>()); return;
      case FieldDescriptor::CPPTYPE_INT64: add ? r.AddInt64(&m, &f, v.as<std::int64_t>()) : r.SetInt64(&m, &f, v.as<std::int64_t>()); return;
      case FieldDescriptor::CPPTYPE_UINT32: add ? r.AddUInt32(&m, &f, v.as<std::uint32_t>()) : r.SetUInt32(&m, &f, v.as<std::uint32_t>()); return;
      case FieldDescriptor::CPPTYPE_UINT64: add ? r.AddUInt64(&m, &f, v.as<std::uint64_t>()) : r.SetUInt64(&m, &f, v.as<std::uint64_t>()); return;
      case FieldDescriptor::CPPTYPE_DOUBLE: add ? r.AddDouble(&m, &f, v.as<double>()) : r.SetDouble(&m, &f, v.as<double>()); return;
      case FieldDescriptor::CPPTYPE_FLOAT: add ? r.AddFloat(&m, &f, v.as<float>()) : r.SetFloat(&m, &f, v.as<float>()); return;
      case FieldDescriptor::CPPTYPE_BOOL: add ? r.AddBool(&m, &f, v.as<bool>()) : r.SetBool(&m, &f, v.as<bool>()); return;
      case FieldDescriptor::CPPTYPE_STRING: add ? r.AddString(&m, &f, v.as<std::string>()) : r.SetString(&m, &f, v.as<std::string>()); return;
      case FieldDescriptor::CPPTYPE_ENUM: {
        const auto* e = f.enum_type()->FindValueByName(v.as<std::string>());
        if (!e) throw YAML::BadConversion(v.Mark());
        add ? r.AddEnum(&m, &f, e) : r.SetEnum(&m, &f, e);
        return;
      }
      case FieldDescriptor::CPPTYPE_MESSAGE: fill_from_yaml(v, add ? *r.AddMessage(&m, &f) : *r.MutableMessage(&m, &f)); return;
    }
  } catch (const YAML::Exception&) {
    std::string needs = f.cpp_type_name();
    if (f.enum_type()) {
      needs = "one of";
      for (int i = 0; i < f.enum_type()->value_count(); ++i) needs += " " + f.enum_type()->value(i)->name();
    }
    throw UsageError("field " + f.full_name() + " needs " + needs + ", got '" + (v.IsScalar() ? v.Scalar() : "a list or mapping") + "'");
  }
}

}  // namespace

FieldPath resolve_field(const Descriptor& type, const std::string& path) {
  FieldPath out{path, {}};
  const Descriptor* at = &type;
  std::size_t begin = 0;
  while (true) {
    const std::size_t dot = path.find('.', begin);
    std::string name = path.substr(begin, dot == std::string::npos ? std::string::npos : dot - begin);
    int index = -1;
    // name[i]: one element of a repeated field
    if (const auto open = name.find('['); open != std::string::npos && name.back() == ']') {
      index = std::atoi(name.c_str() + open + 1);
      name = name.substr(0, open);
    }
    if (!at) throw UsageError("field path '" + path + "': " + out.steps.back().field->name() + " has no fields");
    const FieldDescriptor* f = at->FindFieldByName(name);
    if (!f) unknown_field(*at, name, "field path '" + path + "': ");
    if (index >= 0 && !f->is_repeated()) throw UsageError("field path '" + path + "': " + name + " is not a list, it takes no [index]");
    out.steps.push_back({f, index});
    at = f->message_type();
    if (dot == std::string::npos) return out;
    begin = dot + 1;
  }
}

std::vector<FieldPath> resolve_columns(const Descriptor& type, const std::string& path) {
  FieldPath whole = resolve_field(type, path);
  const FieldPath::Step& last = whole.steps.back();
  const Descriptor* sub = last.field->message_type();
  if (!sub || (last.field->is_repeated() && last.index < 0)) return {whole};
  std::vector<FieldPath> out;
  for (int i = 0; i < sub->field_count(); ++i) {
    for (FieldPath& leaf : resolve_columns(type, path + "." + sub->field(i)->name())) out.push_back(std::move(leaf));
  }
  return out;
}

std::string field_text(const Message& m, const FieldPath& path) { return value_of(m, path.steps, 0); }

std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

void fill_from_yaml(const YAML::Node& node, Message& m) {
  const Descriptor& type = *m.GetDescriptor();
  if (!node.IsMap()) throw UsageError(type.full_name() + " needs a mapping of its fields, e.g. '{" + type.field(type.field_count() > 1 ? 1 : 0)->name() + ": ...}'");
  for (const auto& item : node) {
    const std::string name = item.first.as<std::string>();
    const FieldDescriptor* f = type.FindFieldByName(name);
    if (!f) unknown_field(type, name, "");
    if (!f->is_repeated()) {
      set_scalar(m, *f, item.second, false);
      continue;
    }
    if (!item.second.IsSequence()) throw UsageError("field " + f->full_name() + " is a list: give [a, b, ...]");
    for (const auto& v : item.second) set_scalar(m, *f, v, true);
  }
}

}  // namespace enact::cli
