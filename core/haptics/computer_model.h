#pragma once
// Computer models are data: which masses of the exploratory body give force, which drive
// pins and how, and the penetration past which force is felt. The experimental conditions
// of Khatchatourov et al. (2009) (CM0-CM3) and of the TactPHANTOM pilot (Declerck & Lenay
// 2006: P, T, PT) are presets of this one mechanism; users define their own in YAML.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/physics/model.h"
#include "core/physics/state.h"

namespace enact::haptics {

enum class PinDrive : std::uint8_t {
  none,      // pins stay down
  contact,   // pin i up while mass i touches (no threshold)
  inverted,  // pin i up while mass i does not touch
};

struct ComputerModel {
  std::string name;
  std::uint32_t force_grid_mask = 0;  // bit i: grid mass i (row-major) gives force
  bool force_center = false;          // the body's centre point gives force (single-point rendering)
  std::uint32_t pin_mask = 0;         // bit i: grid mass i drives pin i
  PinDrive pins = PinDrive::none;
  double threshold_m = 0.0;           // penetration before force is felt (pins ignore it)
};

// the largest threshold a computer model may have: deeper than any device here reaches into
// an object (the ERGOS workspace is 25 mm high, the Falcon's about 100 mm across)
inline constexpr double kMaxThreshold_m = 0.05;

// CM0, CM1, CM2, CM3, P, T, PT for a body of `masses` grid masses; nullopt for other names
std::optional<ComputerModel> preset(const std::string& name, int masses = 16);
std::vector<std::string> preset_names();

// a preset name, or a YAML file defining one model (format: docs/scenes-and-models.md, "Computer models");
// throws config::Error naming the file and line, or listing the presets
ComputerModel resolve_computer_model(const std::string& name_or_path, int masses = 16);

// set which body points feed the device and their force threshold (between steps)
void apply(const ComputerModel& cm, physics::Model& model, int proxy = 0);

// pin levels as a bitmask (bit i = pin i up) from the state's contacts; allocates nothing
std::uint32_t pins(const ComputerModel& cm, const physics::Model& model, const physics::State& state, int proxy = 0);

}  // namespace enact::haptics
