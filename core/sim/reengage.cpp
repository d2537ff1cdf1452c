#include "core/sim/reengage.h"

#include <algorithm>
#include <cmath>

#include "core/physics/contact.h"
#include "core/sim/simulator.h"

namespace enact::sim {
namespace {

// projections: enough for a body against a corner of up to three faces
constexpr int kIterations = 4;

}  // namespace

Reengagement::Reengagement(double duration_s) : duration_ns_(std::llround(std::max(0.0, duration_s) * 1e9)) {}

void Reengagement::late(const math::Vec3& body_m, std::int64_t gap_ns) {
  if (pending_ == Pending::cut) return;
  pending_ = Pending::late;
  body_m_ = body_m;
  ++late_count_;
  longest_gap_ns_ = std::max(longest_gap_ns_, gap_ns);
}

math::Vec3 Reengagement::position(const Simulator& sim, std::int64_t time_ns, const math::Vec3& device_m) {
  if (pending_ == Pending::cut) {
    offset_m_ = resync_offset(sim.model(), sim.state(), device_m);
    from_ns_ = time_ns;
    ++count_;
    largest_m_ = std::max(largest_m_, math::norm(offset_m_));
  } else if (pending_ == Pending::late) {
    // out of the objects by what the device went deeper than the body was: along the way
    // out, at least nothing and at most all of it (a device that came out needs no offset)
    const math::Vec3 out_now = resync_offset(sim.model(), sim.state(), device_m);
    const math::Vec3 out_before = resync_offset(sim.model(), sim.state(), body_m_);
    const double out_now_m = math::norm(out_now);
    const double deeper_m = out_now_m > 0.0 ? std::clamp(math::dot(out_now - out_before, out_now) / out_now_m, 0.0, out_now_m) : 0.0;
    // a re-synchronisation still shrinking keeps the larger of the two
    const math::Vec3 held = out_now_m > 0.0 ? out_now * (deeper_m / out_now_m) : math::Vec3{};
    const math::Vec3 left = offset_at(time_ns);
    offset_m_ = math::norm(left) > math::norm(held) ? left : held;
    from_ns_ = time_ns;
    largest_late_m_ = std::max(largest_late_m_, math::norm(held));
  }
  pending_ = Pending::none;
  return device_m + offset_at(time_ns);
}

math::Vec3 Reengagement::offset_at(std::int64_t time_ns) const {
  const std::int64_t since_ns = time_ns - from_ns_;
  if (since_ns >= duration_ns_) return {};
  // a smooth step (zero speed at both ends): the body enters the objects without a speed of
  // its own, so the contacts' damping adds no step to the force
  const double u = since_ns <= 0 ? 0.0 : static_cast<double>(since_ns) / static_cast<double>(duration_ns_);
  return offset_m_ * (1.0 - u * u * (3.0 - 2.0 * u));
}

math::Vec3 resync_offset(const physics::Model& model, const physics::State& state, const math::Vec3& device_m) {
  math::Vec3 offset;
  if (model.proxies.empty() || state.contacts.size() != model.contacts.size()) return offset;
  // each penetrating pair of the body pushes the offset out along its normal by what is left
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    bool moved = false;
    for (std::size_t i = 0; i < model.contacts.size(); ++i) {
      const physics::ContactPair& pair = model.contacts[i];
      const physics::Point& point = model.points[pair.point];
      if (point.proxy != 0) continue;
      physics::ContactState contact = state.contacts[i];
      const math::Vec3 x = device_m + offset + point.offset_m;
      const double depth = physics::update_contact(model, model.objects[pair.object], state.x[pair.point], x, pair.edge_skin_m, contact);
      if (depth <= 0.0) continue;
      offset += contact.normal * depth;
      moved = true;
    }
    if (!moved) break;
  }
  return offset;
}

}  // namespace enact::sim
