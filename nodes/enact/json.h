#pragma once
// A minimal streaming JSON writer for command output (numbers with %.9g, strings escaped).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace enact::cli {

class Json {
 public:
  Json& begin_object() { return open('{'); }
  Json& end_object() { return close('}'); }
  Json& begin_array() { return open('['); }
  Json& end_array() { return close(']'); }
  Json& key(const std::string& k) {
    comma();
    out_ += quoted(k) + ": ";
    after_key_ = true;
    return *this;
  }
  Json& value(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return raw(std::isfinite(v) ? buf : "null");
  }
  Json& value(long long v) { return raw(std::to_string(v)); }
  Json& value(int v) { return raw(std::to_string(v)); }
  Json& value(bool v) { return raw(v ? "true" : "false"); }
  Json& value(const std::string& v) { return raw(quoted(v)); }
  Json& value(const char* v) { return raw(quoted(v)); }
  template <class T>
  Json& field(const std::string& k, const T& v) {
    return key(k).value(v);
  }
  const std::string& str() const { return out_; }

 private:
  static std::string quoted(const std::string& s) {
    std::string q = "\"";
    for (char c : s) {
      if (c == '"' || c == '\\') q += '\\';
      if (c == '\n') {
        q += "\\n";
        continue;
      }
      q += c;
    }
    return q + "\"";
  }
  void comma() {
    if (!after_key_ && !first_.empty() && !first_.back()) out_ += ", ";
    if (!after_key_ && !first_.empty()) first_.back() = false;
  }
  Json& raw(const std::string& s) {
    comma();
    out_ += s;
    after_key_ = false;
    return *this;
  }
  Json& open(char c) {
    comma();
    out_ += c;
    first_.push_back(true);
    after_key_ = false;
    return *this;
  }
  Json& close(char c) {
    out_ += c;
    first_.pop_back();
    return *this;
  }
  std::string out_;
  std::vector<bool> first_;
  bool after_key_ = false;
};

}  // namespace enact::cli
