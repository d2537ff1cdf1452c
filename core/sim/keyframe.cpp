#include "core/sim/keyframe.h"

#include <cstring>
#include <type_traits>
#include <vector>

namespace enact::sim {
namespace {

// the bytes begin with this build's layout: a keyframe only restores into the same one
struct Format {
  char magic[8] = {'k', 'e', 'y', 'f', 'r', 'm', '0', '2'};
  std::uint32_t sizes[6] = {sizeof(Keyframe), sizeof(physics::ContactState), sizeof(task::BridgeTask), sizeof(haptics::TactileDownsampler),
                            sizeof(Reengagement), sizeof(ModelChange)};
};

// every field a keyframe carries, in one order for both directions (the state's per-step
// fields: its layout (dynamic points, pair runs, culling groups) comes from the scene)
template <class K, class F>
void visit(K& k, F&& f) {
  f(k.step), f(k.sample_ns), f(k.origin_ns), f(k.model), f(k.change_ramp_s);
  f(k.stiffness_n_per_m), f(k.damping_n_s_per_m), f(k.threshold_m), f(k.feeds_device);
  auto& s = k.state;
  f(s.x), f(s.x_prev), f(s.v), f(s.f), f(s.in_contact), f(s.k_diag), f(s.z_diag), f(s.contacts), f(s.proxy_position_m), f(s.proxy_force_n);
  f(s.group_apart), f(s.steps), f(s.time_s), f(s.faults), f(s.last_fault), f(s.last_fault_point);
  f(k.task), f(k.trial_running), f(k.trial_change), f(k.tactile);
  f(k.force_n), f(k.from_n), f(k.reentering), f(k.capture), f(k.settling), f(k.offset_left), f(k.offset_total), f(k.reentry_step_m);
  f(k.felt_depth_m), f(k.felt_normal), f(k.reengage), f(k.live_values), f(k.live_changed);
}

template <class T>
struct is_vector : std::false_type {};
template <class T>
struct is_vector<std::vector<T>> : std::true_type {};

}  // namespace

void pack(const Keyframe& keyframe, std::string& out) {
  out.clear();
  auto raw = [&](const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); };
  const Format format;
  raw(&format, sizeof format);
  visit(keyframe, [&](const auto& field) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (is_vector<T>::value) {
      static_assert(std::is_trivially_copyable_v<typename T::value_type>);
      const std::uint64_t n = field.size();
      raw(&n, sizeof n);
      raw(field.data(), n * sizeof(typename T::value_type));
    } else {
      static_assert(std::is_trivially_copyable_v<T>);
      raw(&field, sizeof field);
    }
  });
}

bool unpack(const std::string& bytes, Keyframe& keyframe) {
  std::size_t at = 0;
  bool ok = true;
  auto raw = [&](void* p, std::size_t n) {
    ok = ok && at + n <= bytes.size();
    if (ok) std::memcpy(p, bytes.data() + at, n);
    at += n;
  };
  Format format;
  const Format expected;
  raw(&format, sizeof format);
  if (!ok || std::memcmp(&format, &expected, sizeof format) != 0) return false;
  visit(keyframe, [&](auto& field) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (is_vector<T>::value) {
      std::uint64_t n = 0;
      raw(&n, sizeof n);
      ok = ok && n == field.size();  // sized for this scene
      if (ok) raw(field.data(), n * sizeof(typename T::value_type));
    } else {
      raw(&field, sizeof field);
    }
  });
  return ok && at == bytes.size();
}

}  // namespace enact::sim
