#pragma once
// Typed reading of YAML files with errors that name the file, the line and the fix.
// Used by every loader (scenes, computer models, later launch files): bad input is
// refused at load time and never reaches the loop.
#include <array>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace enact::config {

// "FILE:LINE: problem\n  fix: what to do"
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void fail(const std::string& file, const YAML::Node& at, const std::string& problem,
                       const std::string& fix);

// parse a YAML file; a missing file or a syntax error throws Error with file:line
YAML::Node load_file(const std::string& path);

// a YAML mapping read with a fixed set of keys
class Map {
 public:
  // `what` names the mapping in messages ("scene", "mass 'm1'", ...)
  Map(const YAML::Node& node, std::string file, std::string what, std::initializer_list<const char*> keys);

  bool has(const char* key) const;
  int line() const;  // 1-based
  const std::string& file() const { return file_; }
  const YAML::Node& node() const { return node_; }
  YAML::Node get(const char* key) const;  // required

  double number(const char* key) const;  // required, finite
  double number(const char* key, double fallback) const;
  // finite and > 0 (or >= 0 when zero_ok)
  double positive(const char* key, double fallback, bool zero_ok = false) const;
  double positive(const char* key) const;
  int integer(const char* key, int fallback, int min, int max) const;
  std::string text(const char* key) const;
  std::string text(const char* key, const std::string& fallback) const;
  std::array<double, 3> vec3(const char* key, std::array<double, 3> fallback) const;
  std::array<double, 3> vec3(const char* key) const;
  bool flag(const char* key, bool fallback) const;
  // a sequence of mappings (absent: empty)
  std::vector<YAML::Node> list(const char* key) const;

  [[noreturn]] void fail(const char* key, const std::string& problem, const std::string& fix) const;

 private:
  YAML::Node node_;
  std::string file_;
  std::string what_;
};

// a scalar's text (a key, a name); a list or a map throws Error naming `what` and the line
std::string scalar(const std::string& file, const YAML::Node& node, const std::string& what);

// read a sequence of numbers of a fixed length (file:line errors)
std::vector<double> numbers(const std::string& file, const YAML::Node& node, std::size_t count, const std::string& what);

}  // namespace enact::config
