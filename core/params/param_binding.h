#pragma once
// Each parameter declared once: its row of a table (param_table.h) bound to the field of the
// component's config struct that holds it. The table (--help, the checks of a launch file,
// `enact param list/dump`, docs/cli.md) comes from the bindings; a row's type and default
// come from the field (its value in a default-made Config); read() fills a Config from a
// node's Params. Adding a parameter is a field in the struct and its one line of bindings.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/config/format.h"
#include "core/params/param_table.h"
#include "core/params/params.h"
#include "core/math/vec3.h"

namespace enact::graph {

// how a field's type is declared, written as a default and read from Params; specialise it
// for another type (an enum: type choice, its words)
template <class T>
struct ParamCodec;

template <>
struct ParamCodec<double> {
  static constexpr ParamType type = ParamType::number;
  static std::string text(double v) { return config::number(v); }
  static double read(const Params& p, const std::string& name) { return p.number(name); }
};
template <>
struct ParamCodec<int> {
  static constexpr ParamType type = ParamType::integer;
  static std::string text(int v) { return std::to_string(v); }
  static int read(const Params& p, const std::string& name) { return p.integer(name); }
};
template <>
struct ParamCodec<std::uint64_t> {
  static constexpr ParamType type = ParamType::integer;
  static std::string text(std::uint64_t v) { return std::to_string(v); }
  static std::uint64_t read(const Params& p, const std::string& name) { return static_cast<std::uint64_t>(p.integer(name)); }
};
template <>
struct ParamCodec<bool> {
  static constexpr ParamType type = ParamType::flag;
  static std::string text(bool v) { return v ? "true" : "false"; }
  static bool read(const Params& p, const std::string& name) { return p.flag(name); }
};
template <>
struct ParamCodec<std::string> {
  static constexpr ParamType type = ParamType::text;
  static std::string text(const std::string& v) { return v; }
  static std::string read(const Params& p, const std::string& name) { return p.text(name); }
};
// a number that may be left out: empty (its row's default) when not given
template <>
struct ParamCodec<std::optional<double>> {
  static constexpr ParamType type = ParamType::number;
  static std::string text(const std::optional<double>& v) { return v ? config::number(*v) : std::string{}; }
  static std::optional<double> read(const Params& p, const std::string& name) {
    return p.text(name).empty() ? std::nullopt : std::optional(p.number(name));
  }
};
template <>
struct ParamCodec<math::Vec3> {
  static constexpr ParamType type = ParamType::vec3;
  static std::string text(const math::Vec3& v) { return config::number(v.x) + "," + config::number(v.y) + "," + config::number(v.z); }
  static math::Vec3 read(const Params& p, const std::string& name) { return p.vec3(name); }
};

template <class Config>
class ParamBindings {
 public:
  // a field: `&Config::rate_hz`, or a nested one through its accessor,
  // `[](Config& c) -> double& { return c.task.min_fall_s; }`. The row's type is the field's
  // (a text field may say choice), its default the field's default unless the row gives one
  // (or is required)
  template <class Access>
  ParamBindings& field(Access access, ParamSpec spec) {
    Config defaults{};
    using T = std::remove_cvref_t<decltype(at(access, defaults))>;
    if (!(std::is_same_v<T, std::string> && spec.type == ParamType::choice)) spec.type = ParamCodec<T>::type;
    if (spec.fallback.empty() && !spec.required) spec.fallback = ParamCodec<T>::text(at(access, defaults));
    readers_.push_back([access, name = spec.name](const Params& p, Config& c) { at(access, c) = ParamCodec<T>::read(p, name); });
    table_.push_back(std::move(spec));
    return *this;
  }
  // a row the component reads itself (live-only parameters, commands, node plumbing)
  ParamBindings& declared(ParamSpec spec) {
    table_.push_back(std::move(spec));
    return *this;
  }

  const ParamTable& table() const { return table_; }

  // declares the table on `p` (checking every value given) and reads every bound field
  Config read(const Params& p) const {
    p.declare(table_);
    Config c{};
    for (const auto& r : readers_) r(p, c);
    return c;
  }

 private:
  template <class Access>
  static auto& at(Access access, Config& c) {
    if constexpr (std::is_member_object_pointer_v<Access>) return c.*access;
    else return access(c);
  }

  ParamTable table_;
  std::vector<std::function<void(const Params&, Config&)>> readers_;
};

}  // namespace enact::graph
