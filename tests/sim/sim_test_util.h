#pragma once
// What the simulator's tests share: the bridge scene's parameters and a point pressed into it.
#include <string>

#include "core/math/vec3.h"
#include "core/sim/simulator.h"
#include "tests/support/test_util.h"

namespace enact::sim::test_util {

// the shipped bridge scene with computer model `model`, at rate_hz (0: the scene's rate)
inline SimParams bridge(const std::string& model = "CM1", double rate_hz = 0.0) {
  SimParams p;
  p.scene = test::source_path("launch/scenes/bridge.yaml");
  p.model = model;
  p.rate_hz = rate_hz;
  return p;
}

// a point pressed 1 mm into the middle of the first segment's top. The segment runs at 45
// degrees and is 10 mm wide, so the grid's far-left (r0c0) and near-right (r3c3) corners,
// 5.2 mm from its centreline, overhang: 14 grid masses touch.
inline const math::Vec3 kPressed{0.0, -0.0148492, 0.011};

}  // namespace enact::sim::test_util
