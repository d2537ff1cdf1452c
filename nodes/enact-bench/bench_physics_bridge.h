#pragma once
// The bridge's inputs to `enact bench physics` (bench_physics_bridge.cpp): the scene at 44 kHz
// under CM1, the hand's two motions (resting at the first turn with a wobble, and the scene's
// scripted path) and how many grid masses touch along a motion.
#include <string>
#include <vector>

#include "core/math/vec3.h"
#include "core/physics/model.h"
#include "core/task/trajectory.h"

namespace enact::cli::bridge_rows {

// the bridge step's rate
inline constexpr double kBridgeRate_hz = 44000.0;

// the hand resting 0.1 mm into the top inside the first turn, where the whole grid fits,
// wobbling along both segments (2 and 3 Hz: one period of 1 s), sampled at the model's rate
std::vector<math::Vec3> bridge_motion(const physics::Model& m);

// the built-in scripted hand path of the scene (enact path): on the top, off the edges, a
// fall and the climb back, the turns
task::Trajectory scripted_path(const std::string& scene);

// the scripted path sampled at the bridge rate
std::vector<math::Vec3> scripted_motion(const task::Trajectory& tr);

// the bridge at 44 kHz under CM1, the body starting 1 mm above the motion's first position
physics::Model bridge(const std::string& scene, const std::vector<math::Vec3>& start);

struct GridContacts {
  double mean = 0.0;      // grid masses touching, mean over the motion
  double all_share = 0.0; // share of steps with every grid mass touching
  int masses = 0;
};
GridContacts grid_contacts(const physics::Model& m, const std::vector<math::Vec3>& motion);

}  // namespace enact::cli::bridge_rows
