#include "core/haptics/computer_model.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/config/yaml.h"
#include "core/physics/scene.h"
#include "core/physics/state.h"
#include "tests/support/test_util.h"

namespace enact::haptics {
namespace {

constexpr std::uint32_t kGrid16 = 0xffffu;

// the message of the config::Error thrown by resolving `path` (empty when nothing is thrown)
std::string resolve_error(const std::string& path) {
  try {
    resolve_computer_model(path);
  } catch (const config::Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("not a config::Error: ") + e.what();
  }
  return {};
}

void expect_model(const std::string& name, std::uint32_t force_mask, bool centre, std::uint32_t pin_mask, PinDrive drive,
                  double threshold_m) {
  SCOPED_TRACE(name);
  const auto cm = preset(name);
  ASSERT_TRUE(cm.has_value());
  EXPECT_EQ(cm->name, name);
  EXPECT_EQ(cm->force_grid_mask, force_mask);
  EXPECT_EQ(cm->force_center, centre);
  EXPECT_EQ(cm->pin_mask, pin_mask);
  EXPECT_EQ(cm->pins, drive);
  EXPECT_DOUBLE_EQ(cm->threshold_m, threshold_m);
}

TEST(ComputerModelPreset, MatchesTheDocumentedConditions) {
  expect_model("CM0", kGrid16, false, 0, PinDrive::none, 0.0);
  expect_model("CM1", kGrid16, false, kGrid16, PinDrive::contact, 0.0);
  expect_model("CM2", kGrid16, false, kGrid16, PinDrive::contact, 0.003);
  expect_model("CM3", kGrid16, false, kGrid16, PinDrive::inverted, 0.0);
  expect_model("P", 0, true, 0, PinDrive::none, 0.0);
  expect_model("T", 0, false, kGrid16, PinDrive::contact, 0.0);
  expect_model("PT", 0, true, kGrid16, PinDrive::contact, 0.0);
}

TEST(ComputerModelPreset, MasksFollowTheGridSize) {
  EXPECT_EQ(preset("CM1", 9)->force_grid_mask, 0x1ffu);
  EXPECT_EQ(preset("CM1", 9)->pin_mask, 0x1ffu);
  EXPECT_EQ(preset("CM1", 32)->force_grid_mask, 0xffffffffu);
  EXPECT_EQ(preset("T", 1)->pin_mask, 0x1u);
}

TEST(ComputerModelPreset, UnknownNamesAreNotPresets) {
  EXPECT_FALSE(preset("CM4").has_value());
  EXPECT_FALSE(preset("cm1").has_value());
  EXPECT_EQ(preset_names(), (std::vector<std::string>{"CM0", "CM1", "CM2", "CM3", "P", "T", "PT"}));
}

TEST(ResolveComputerModel, PresetNameGivesThePreset) {
  const ComputerModel cm = resolve_computer_model("CM2");
  EXPECT_EQ(cm.name, "CM2");
  EXPECT_DOUBLE_EQ(cm.threshold_m, 0.003);
}

TEST(ResolveComputerModel, ReadsAYamlFile) {
  const test::TempDir dir;
  const std::string path = dir.file("mine.yaml");
  test::write_file(path,
                   "name: mine\n"
                   "description: two force masses, inverted pins on two masses\n"
                   "force: [0, 5]\n"
                   "pins: inverted\n"
                   "pin_masses: [1, 2]\n"
                   "threshold_m: 0.002\n");
  const ComputerModel cm = resolve_computer_model(path);
  EXPECT_EQ(cm.name, "mine");
  EXPECT_EQ(cm.force_grid_mask, (1u << 0) | (1u << 5));
  EXPECT_FALSE(cm.force_center);
  EXPECT_EQ(cm.pins, PinDrive::inverted);
  EXPECT_EQ(cm.pin_mask, (1u << 1) | (1u << 2));
  EXPECT_DOUBLE_EQ(cm.threshold_m, 0.002);
}

TEST(ResolveComputerModel, PinsWithoutPinMassesDriveTheWholeGrid) {
  const test::TempDir dir;
  const std::string path = dir.file("centre.yaml");
  test::write_file(path, "name: centre\nforce: center\npins: contact\n");
  const ComputerModel cm = resolve_computer_model(path, 9);
  EXPECT_EQ(cm.force_grid_mask, 0u);
  EXPECT_TRUE(cm.force_center);
  EXPECT_EQ(cm.pins, PinDrive::contact);
  EXPECT_EQ(cm.pin_mask, 0x1ffu);
  EXPECT_DOUBLE_EQ(cm.threshold_m, 0.0);
}

TEST(ResolveComputerModel, UnknownKeyNamesFileLineAndFix) {
  const test::TempDir dir;
  const std::string path = dir.file("bad.yaml");
  test::write_file(path, "name: bad\nforce: grid\n\nthreshold: 0.003\n");
  const std::string msg = resolve_error(path);
  EXPECT_NE(msg.find(path + ":4:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("threshold"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST(ResolveComputerModel, AThresholdDeeperThanAnyDeviceReachesIsRefused) {
  const test::TempDir dir;
  const std::string path = dir.file("deep.yaml");
  test::write_file(path, "name: deep\nforce: grid\nthreshold_m: 1e12\n");
  const std::string msg = resolve_error(path);
  EXPECT_NE(msg.find(path + ":3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("at most 0.05 m"), std::string::npos) << msg;
  // the largest allowed is taken
  test::write_file(path, "name: deep\nforce: grid\nthreshold_m: 0.05\n");
  EXPECT_DOUBLE_EQ(resolve_computer_model(path).threshold_m, 0.05);
}

TEST(ResolveComputerModel, BadPinsValueNamesFileLineAndFix) {
  const test::TempDir dir;
  const std::string path = dir.file("bad.yaml");
  test::write_file(path, "name: bad\nforce: grid\npins: sometimes\n");
  const std::string msg = resolve_error(path);
  EXPECT_NE(msg.find(path + ":3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sometimes"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST(ResolveComputerModel, ForceIndexOutOfRangeNamesItsLine) {
  const test::TempDir dir;
  const std::string path = dir.file("bad.yaml");
  test::write_file(path, "name: bad\nforce:\n  - 0\n  - 16\npins: none\n");
  const std::string msg = resolve_error(path);
  EXPECT_NE(msg.find(path + ":4:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("0 to 15"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST(ResolveComputerModel, PinIndexOutOfRangeNamesItsLine) {
  const test::TempDir dir;
  const std::string path = dir.file("bad.yaml");
  test::write_file(path, "name: bad\nforce: none\npins: contact\npin_masses:\n  - 3\n  - -1\n");
  const std::string msg = resolve_error(path);
  EXPECT_NE(msg.find(path + ":6:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

// `pin_masses: 3` (a scalar) is refused at its line, not read as an empty mask
TEST(ResolveComputerModel, PinMassesMustBeAList) {
  const test::TempDir dir;
  const std::string path = dir.file("bad.yaml");
  test::write_file(path, "name: bad\nforce: grid\npins: contact\npin_masses: 3\n");
  const std::string msg = resolve_error(path);
  EXPECT_NE(msg.find(path + ":4:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

// `force: {a: 1}` is refused at its line with a fix, not with a bare yaml-cpp error
TEST(ResolveComputerModel, ForceMustBeAWordOrAList) {
  const test::TempDir dir;
  const std::string path = dir.file("bad.yaml");
  test::write_file(path, "name: bad\nforce: {a: 1}\n");
  const std::string msg = resolve_error(path);
  EXPECT_NE(msg.find(path + ":2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST(ResolveComputerModel, UnknownPresetListsThePresets) {
  const std::string msg = resolve_error("CM9");
  EXPECT_NE(msg.find("CM9"), std::string::npos) << msg;
  for (const auto& name : preset_names()) EXPECT_NE(msg.find(name), std::string::npos) << name << " missing from: " << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST(ResolveComputerModel, MissingFileNamesTheFile) {
  const test::TempDir dir;
  const std::string path = dir.file("absent.yaml");
  const std::string msg = resolve_error(path);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

// a scene with a free mass and a 2 x 3 body, so that row-major indices are not symmetric
class ApplyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string path = dir_.file("scene.yaml");
    test::write_file(path,
                     "masses:\n"
                     "  - {name: free, mass_kg: 0.01, position_m: [0, 0, 1]}\n"
                     "body:\n"
                     "  name: finger\n"
                     "  position_m: [0, 0, 0.01]\n"
                     "  grid: {rows: 2, cols: 3, pitch_m: 0.002}\n");
    model_ = physics::load_scene(path);
    ASSERT_EQ(model_.proxies.size(), 1u);
  }
  const physics::Point& grid(int i) const { return model_.points[model_.proxies[0].first_body + i]; }
  const physics::Point& centre() const { return model_.points[model_.proxies[0].point]; }
  const physics::Point& free_mass() const { return model_.points[model_.find_point("free")]; }

  test::TempDir dir_;
  physics::Model model_;
};

TEST_F(ApplyTest, GridModelFeedsTheGridNotTheCentre) {
  apply(*preset("CM2", 6), model_);
  EXPECT_FALSE(centre().feeds_device);
  EXPECT_DOUBLE_EQ(centre().contact_threshold_m, 0.003);
  for (int i = 0; i < 6; ++i) {
    EXPECT_TRUE(grid(i).feeds_device) << i;
    EXPECT_DOUBLE_EQ(grid(i).contact_threshold_m, 0.003) << i;
  }
  EXPECT_TRUE(free_mass().feeds_device);  // untouched default
  EXPECT_DOUBLE_EQ(free_mass().contact_threshold_m, 0.0);
}

TEST_F(ApplyTest, PointModelFeedsOnlyTheCentre) {
  apply(*preset("CM2", 6), model_);
  apply(*preset("P", 6), model_);
  EXPECT_TRUE(centre().feeds_device);
  for (int i = 0; i < 6; ++i) {
    EXPECT_FALSE(grid(i).feeds_device) << i;
    EXPECT_DOUBLE_EQ(grid(i).contact_threshold_m, 0.0) << i;  // CM2's threshold is cleared
  }
}

TEST_F(ApplyTest, MaskSelectsRowMajorGridMasses) {
  ComputerModel cm;
  cm.force_grid_mask = (1u << 1) | (1u << 5);  // row 0 col 1, row 1 col 2
  cm.threshold_m = 0.001;
  apply(cm, model_);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(grid(i).feeds_device, i == 1 || i == 5) << i;
  EXPECT_EQ(grid(1).name, physics::grid_point_name("finger", 0, 1));
  EXPECT_EQ(grid(5).name, physics::grid_point_name("finger", 1, 2));
  EXPECT_FALSE(centre().feeds_device);
}

TEST_F(ApplyTest, PinsFollowContactsByDrive) {
  physics::State state = physics::make_state(model_);
  const int first = model_.proxies[0].first_body;
  state.in_contact[first + 0] = 1;
  state.in_contact[first + 4] = 1;
  EXPECT_EQ(pins(*preset("CM1", 6), model_, state), (1u << 0) | (1u << 4));
  EXPECT_EQ(pins(*preset("CM3", 6), model_, state), 0x3fu & ~((1u << 0) | (1u << 4)));
  EXPECT_EQ(pins(*preset("CM0", 6), model_, state), 0u);
  ComputerModel some = *preset("CM1", 6);
  some.pin_mask = 1u << 4;
  EXPECT_EQ(pins(some, model_, state), 1u << 4);
}

}  // namespace
}  // namespace enact::haptics
