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

math::Vec3 Reengagement::position(const Simulator& sim, std::int64_t time_ns, const math::Vec3& device_m) {
  if (pending_) {
    pending_ = false;
    offset_m_ = resync_offset(sim.model(), sim.state(), device_m);
    from_ns_ = time_ns;
    ++count_;
    largest_m_ = std::max(largest_m_, math::norm(offset_m_));
  }
  const std::int64_t since_ns = time_ns - from_ns_;
  if (since_ns >= duration_ns_) return device_m;
  // a smooth step (zero speed at both ends): the body enters the objects without a speed of
  // its own, so the contacts' damping adds no step to the force
  const double u = since_ns <= 0 ? 0.0 : static_cast<double>(since_ns) / static_cast<double>(duration_ns_);
  return device_m + offset_m_ * (1.0 - u * u * (3.0 - 2.0 * u));
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
