#include "core/haptics/tactile.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace enact::haptics {
namespace {

// pushes `pins(step)` for `steps` steps; returns the steps that emitted and the frames
struct Emitted {
  std::vector<int> steps;
  std::vector<std::uint32_t> frames;
};

template <class Pins>
Emitted run(TactileDownsampler& d, int steps, Pins pins) {
  Emitted out;
  for (int n = 0; n < steps; ++n) {
    if (d.push(pins(n))) {
      out.steps.push_back(n);
      out.frames.push_back(d.frame());
    }
  }
  return out;
}

TEST(TactileDownsampler, OneFramePerPeriodAndTheFirstStepEmits) {
  TactileDownsampler d;
  d.configure({0.024, TactileMode::sample}, 5000.0);
  EXPECT_EQ(d.steps_per_frame(), 120);
  const Emitted e = run(d, 600, [](int) { return 0u; });
  EXPECT_EQ(e.steps, (std::vector<int>{0, 120, 240, 360, 480}));
}

TEST(TactileDownsampler, AtLeastOneStepPerFrame) {
  TactileDownsampler d;
  d.configure({0.0001, TactileMode::sample}, 1000.0);
  EXPECT_EQ(d.steps_per_frame(), 1);
  EXPECT_EQ(run(d, 5, [](int) { return 0u; }).steps.size(), 5u);
}

TEST(TactileDownsampler, SampleModeGivesThePinsOfTheFrameStep) {
  TactileDownsampler d;
  d.configure({0.024, TactileMode::sample}, 5000.0);
  const Emitted e = run(d, 241, [](int n) { return static_cast<std::uint32_t>(n); });
  EXPECT_EQ(e.frames, (std::vector<std::uint32_t>{0, 120, 240}));
}

// a contact on steps 30..39, between the frames at steps 0 and 120
std::uint32_t brief_contact(int n) { return n >= 30 && n < 40 ? 0x5u : 0u; }

TEST(TactileDownsampler, SampleModeLosesABriefContactBetweenFrames) {
  TactileDownsampler d;
  d.configure({0.024, TactileMode::sample}, 5000.0);
  const Emitted e = run(d, 241, brief_contact);
  EXPECT_EQ(e.frames, (std::vector<std::uint32_t>{0, 0, 0}));
}

TEST(TactileDownsampler, AnyModeKeepsABriefContactForOneFrame) {
  TactileDownsampler d;
  d.configure({0.024, TactileMode::any}, 5000.0);
  const Emitted e = run(d, 241, brief_contact);
  EXPECT_EQ(e.steps, (std::vector<int>{0, 120, 240}));
  EXPECT_EQ(e.frames, (std::vector<std::uint32_t>{0, 0x5u, 0}));
}

TEST(TactileDownsampler, ResetStartsFramesAgain) {
  TactileDownsampler d;
  d.configure({0.024, TactileMode::any}, 5000.0);
  run(d, 50, [](int) { return 0x1u; });
  d.reset();
  EXPECT_EQ(d.frame(), 0u);
  EXPECT_TRUE(d.push(0x2u));  // the first step after a reset emits
  EXPECT_EQ(d.frame(), 0x2u);  // pins from before the reset are forgotten
}

TEST(ParseTactileMode, AcceptsTheTwoModes) {
  EXPECT_EQ(parse_tactile_mode("sample"), TactileMode::sample);
  EXPECT_EQ(parse_tactile_mode("any"), TactileMode::any);
}

TEST(ParseTactileMode, RejectsJunk) {
  for (const char* junk : {"", "Any", "samples", "all", "sample "}) {
    EXPECT_THROW(parse_tactile_mode(junk), std::invalid_argument) << "'" << junk << "'";
  }
}

}  // namespace
}  // namespace enact::haptics
