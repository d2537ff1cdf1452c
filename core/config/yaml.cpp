#include "core/config/yaml.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>

namespace enact::config {
namespace {

std::string where(const std::string& file, const YAML::Node& at) {
  const YAML::Mark mark = at.IsDefined() ? at.Mark() : YAML::Mark::null_mark();
  if (mark.is_null()) return file;
  return file + ":" + std::to_string(mark.line + 1);
}

std::string joined(const std::vector<std::string>& keys) {
  std::string out;
  for (const auto& k : keys) out += (out.empty() ? "" : ", ") + k;
  return out;
}

double finite_number(const std::string& file, const YAML::Node& n, const std::string& what) {
  double value = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, value)) {
    fail(file, n, what + " must be a number, got '" + (n.IsScalar() ? n.Scalar() : std::string("a list or map")) + "'",
         "write a plain number in SI units, e.g. 0.01");
  }
  if (!std::isfinite(value)) fail(file, n, what + " must be finite, got " + n.Scalar(), "write a finite number");
  return value;
}

// the line of the first flow bracket that is never closed (0: none); skips comments and quotes
int unclosed_bracket_line(const std::string& path) {
  std::ifstream in(path);
  std::vector<int> open;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    char quote = 0;
    for (char c : text) {
      if (quote) {
        quote = c == quote ? 0 : quote;
      } else if (c == '\'' || c == '"') {
        quote = c;
      } else if (c == '#') {
        break;
      } else if (c == '[' || c == '{') {
        open.push_back(line);
      } else if ((c == ']' || c == '}') && !open.empty()) {
        open.pop_back();
      }
    }
  }
  return open.empty() ? 0 : open.front();
}

int line_count(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  int lines = 0;
  while (std::getline(in, text)) ++lines;
  return std::max(lines, 1);
}

// refuse a mapping that repeats a key, naming both lines; an aliased node is checked once
void refuse_duplicate_keys(const std::string& file, const YAML::Node& node, std::set<std::size_t>& seen) {
  if (!node.IsMap() && !node.IsSequence()) return;
  if (!node.Mark().is_null() && !seen.insert(static_cast<std::size_t>(node.Mark().pos)).second) return;
  if (node.IsSequence()) {
    for (const auto& item : node) refuse_duplicate_keys(file, item, seen);
    return;
  }
  std::map<std::string, int> first_line;
  for (const auto& kv : node) {
    if (kv.first.IsScalar()) {
      const int line = kv.first.Mark().is_null() ? 0 : kv.first.Mark().line + 1;
      const auto [it, fresh] = first_line.emplace(kv.first.Scalar(), line);
      if (!fresh) {
        fail(file, kv.first, "duplicate key '" + kv.first.Scalar() + "' (first on line " + std::to_string(it->second) + ")",
             "keep one of the two lines: YAML would silently use only one value");
      }
    }
    refuse_duplicate_keys(file, kv.second, seen);
  }
}

}  // namespace

void fail(const std::string& file, const YAML::Node& at, const std::string& problem, const std::string& fix) {
  throw Error(where(file, at) + ": " + problem + "\n  fix: " + fix);
}

YAML::Node load_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open the file\n  fix: check the path (relative paths start from the current directory)");
  try {
    YAML::Node root = YAML::Load(in);
    if (!root.IsMap()) fail(path, root, "the file must be a YAML mapping (key: value lines)", "see the format of that file in docs/");
    std::set<std::size_t> seen;
    refuse_duplicate_keys(path, root, seen);
    return root;
  } catch (const YAML::Exception& e) {
    const int open_line = unclosed_bracket_line(path);
    if (open_line > 0) {
      throw Error(path + ":" + std::to_string(open_line) + ": malformed YAML: a '[' or '{' opened on this line is never closed" +
                  "\n  fix: close it with the matching ']' or '}'");
    }
    throw Error(path + ":" + std::to_string(std::min(e.mark.line + 1, line_count(path))) + ": malformed YAML: " + e.msg +
                "\n  fix: correct the YAML syntax on or just before that line (indentation, ':' after keys, quotes)");
  }
}

Map::Map(const YAML::Node& node, std::string file, std::string what, std::initializer_list<const char*> keys)
    : node_(node), file_(std::move(file)), what_(std::move(what)) {
  if (!node_.IsMap()) config::fail(file_, node_, what_ + " must be a mapping (key: value)", "see the format of that file in docs/");
  std::vector<std::string> allowed(keys.begin(), keys.end());
  for (const auto& kv : node_) {
    const std::string key = scalar(file_, kv.first, "a key in " + what_);
    bool known = false;
    for (const auto& a : allowed) known = known || a == key;
    if (!known) config::fail(file_, kv.first, "unknown key '" + key + "' in " + what_, "use one of: " + joined(allowed));
  }
}

bool Map::has(const char* key) const { return static_cast<bool>(node_[key]); }

int Map::line() const { return node_.Mark().is_null() ? 0 : node_.Mark().line + 1; }

YAML::Node Map::get(const char* key) const {
  YAML::Node n = node_[key];
  if (!n) config::fail(file_, node_, what_ + " is missing '" + key + "'", std::string("add '") + key + ": ...'");
  return n;
}

double Map::number(const char* key) const { return finite_number(file_, get(key), what_ + "." + key); }

double Map::number(const char* key, double fallback) const { return has(key) ? number(key) : fallback; }

double Map::positive(const char* key, double fallback, bool zero_ok) const {
  if (!has(key)) return fallback;
  const double v = number(key);
  if (v < 0.0 || (!zero_ok && v == 0.0)) {
    fail(key, what_ + "." + key + " must be " + (zero_ok ? ">= 0" : "> 0") + ", got " + node_[key].Scalar(),
         std::string("give a ") + (zero_ok ? "non-negative" : "positive") + " value");
  }
  return v;
}

double Map::positive(const char* key) const {
  get(key);
  return positive(key, 0.0);
}

int Map::integer(const char* key, int fallback, int min, int max) const {
  if (!has(key)) return fallback;
  const YAML::Node n = node_[key];
  int value = 0;
  if (!n.IsScalar() || !YAML::convert<int>::decode(n, value) || value < min || value > max) {
    fail(key, what_ + "." + key + " must be a whole number from " + std::to_string(min) + " to " + std::to_string(max),
         "write a whole number in that range");
  }
  return value;
}

std::string Map::text(const char* key) const {
  const YAML::Node n = get(key);
  if (!n.IsScalar()) fail(key, what_ + "." + key + " must be a single word or string", "write e.g. " + std::string(key) + ": name");
  return n.Scalar();
}

std::string Map::text(const char* key, const std::string& fallback) const { return has(key) ? text(key) : fallback; }

std::array<double, 3> Map::vec3(const char* key) const {
  const auto v = numbers(file_, get(key), 3, what_ + "." + key);
  return {v[0], v[1], v[2]};
}

std::array<double, 3> Map::vec3(const char* key, std::array<double, 3> fallback) const {
  return has(key) ? vec3(key) : fallback;
}

bool Map::flag(const char* key, bool fallback) const {
  if (!has(key)) return fallback;
  bool value = false;
  if (!YAML::convert<bool>::decode(node_[key], value)) fail(key, what_ + "." + key + " must be true or false", "write true or false");
  return value;
}

std::vector<YAML::Node> Map::list(const char* key) const {
  std::vector<YAML::Node> out;
  if (!has(key)) return out;
  const YAML::Node n = node_[key];
  if (!n.IsSequence()) fail(key, what_ + "." + key + " must be a list", std::string("write each entry on a line starting with '- '"));
  for (const auto& item : n) out.push_back(item);
  return out;
}

void Map::fail(const char* key, const std::string& problem, const std::string& fix) const {
  config::fail(file_, has(key) ? node_[key] : node_, problem, fix);
}

std::string scalar(const std::string& file, const YAML::Node& node, const std::string& what) {
  if (!node.IsScalar()) fail(file, node, what + " must be a single word or string, got a list or a map", "write a plain name");
  return node.Scalar();
}

std::vector<double> numbers(const std::string& file, const YAML::Node& node, std::size_t count, const std::string& what) {
  if (!node.IsSequence() || node.size() != count) {
    fail(file, node, what + " must be a list of " + std::to_string(count) + " numbers", "write e.g. [0, 0, 0.01]");
  }
  std::vector<double> out;
  for (const auto& item : node) out.push_back(finite_number(file, item, what));
  return out;
}

}  // namespace enact::config
