// A stage of the co-located tick, written as a user would (core/node/loop_component.h): a
// guiding spring that pulls the hand toward an anchor point, added to the model's force. A
// haptic guide of this kind (a spring and a damper toward a target, capped) is the usual
// first virtual fixture of a training study. Spring and damper are passive; the cap bounds
// what it adds, and the device's safety layer still limits the sum.
//
// Built in enact's tree, or on its own against an installed enact (find_package(enact):
// CMakeLists.txt beside it), into libenact_guide_spring.so; a launch file names it in the
// container's component list:
//   - {name: guide, plugin: guide_spring, library: PATH/libenact_guide_spring.so,
//      param: [{name: anchor_m, value: "0,0,0.05"}, {name: stiffness_n_per_m, value: "40"}]}
#include <memory>

#include "core/node/loop_component.h"

// the declarations name only the fields they set: every other one has its default
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace {

using enact::math::Vec3;

class GuideSpring final : public enact::node::LoopComponent {
 public:
  explicit GuideSpring(const enact::graph::Params& p)
      : anchor_m_(p.vec3("anchor_m")),
        k_n_per_m_(p.number("stiffness_n_per_m")),
        b_n_s_per_m_(p.number("damping_n_s_per_m")),
        max_n_(p.number("max_force_n")) {}

  void step(enact::node::Tick& tick) noexcept override {
    const Vec3 x = tick.sample->position_m - anchor_m_;
    Vec3 f = x * -k_n_per_m_ - tick.sample->velocity_m_per_s * b_n_s_per_m_;
    const double size = enact::math::norm(f);
    if (size > max_n_) f = f * (max_n_ / size);
    tick.step->force_n = tick.step->force_n + f;
  }

 private:
  Vec3 anchor_m_;
  double k_n_per_m_, b_n_s_per_m_, max_n_;
};

const enact::graph::ParamTable& guide_table() {
  using enact::graph::ParamType;
  static const enact::graph::ParamTable t{
      {.name = "anchor_m", .type = ParamType::vec3, .fallback = "0,0,0", .doc = "where the spring pulls the hand, x,y,z"},
      {.name = "stiffness_n_per_m", .fallback = "40", .min = 0, .doc = "the spring's stiffness"},
      {.name = "damping_n_s_per_m", .fallback = "0", .min = 0, .doc = "a damper on the hand's velocity"},
      {.name = "max_force_n", .fallback = "2", .min = 0, .doc = "the most the guide adds"},
  };
  return t;
}

std::unique_ptr<enact::node::LoopComponent> make_guide(const enact::graph::Params& p) { return std::make_unique<GuideSpring>(p); }

const enact::node::LoopPlugin kGuide{
    .plugin = "guide_spring",
    .what = "guiding spring toward anchor_m, added to the model's force (an example stage)",
    .table = &guide_table,
    .make = &make_guide,
};

}  // namespace

extern "C" int enact_plugin_abi() { return enact::node::kPluginAbi; }
extern "C" void enact_register_plugins(enact::node::PluginRegistry& r) { r.add(kGuide); }
