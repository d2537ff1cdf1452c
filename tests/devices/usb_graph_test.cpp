// End to end: the co-located bridge graph on the USB backends with their emulators
// (launch/bridge_rt_usb_emulated.yaml: device falcon and device metec, transport emulator),
// started with the real `enact launch` and observed through the attach point like the
// graphs of tests/integration. The emulated grip moves along the bridge, the forces and pins
// follow contact as with the simulated devices, and the Metec cells show the frames.
//
// Machine assumptions: 2 noisy shared cores; only generous bounds on timing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "tests/integration/integration_util.h"
#include "tests/support/test_util.h"

namespace enact::test {
namespace {

constexpr double kReadyTimeout_s = 30.0;
constexpr double kGraphDuration_s = 20.0;  // a safety net: the test stops the graph itself
using test::kMs;

TEST(UsbGraph, FalconAndMetecOnTheirEmulatorsRunTheBridge) {
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge_rt_usb_emulated.yaml"), kGraphDuration_s);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  Observer obs(launcher.endpoint());
  obs.all_topics();
  Observed seen;
  obs.observe(4.0, seen);
  ASSERT_GE(seen.states.size(), 100u);
  ASSERT_GE(seen.scenes.size(), 100u);
  ASSERT_GE(seen.frames.size(), 50u);
  ASSERT_GE(seen.shown.size(), 100u);

  // the emulated grip moves: the scripted hand drags it along the bridge (in the enact frame)
  double span = 0.0;
  std::uint64_t healthy = 0;
  const auto& p0 = seen.states.front().position();
  for (const auto& s : seen.states) {
    span = std::max(span, std::hypot(s.position().x() - p0.x(), s.position().y() - p0.y()));
    healthy += s.faults() == 0;
  }
  std::printf("[ usb graph ] %zu device states, %llu without a fault, the grip moved %.1f mm\n", seen.states.size(), static_cast<unsigned long long>(healthy), span * 1e3);
  EXPECT_GT(span, 0.005);
  EXPECT_GT(healthy * 10, seen.states.size() * 9) << "most samples healthy";

  // forces and pins follow contact, as with the simulated devices (CM1)
  const ContactCheck contact = check_follows_contact(seen.scenes);
  std::printf("[ usb graph ] %zu scenes, %d on the top (%d of them re-synchronised, without force)\n", seen.scenes.size(), contact.on_top, contact.resting);
  EXPECT_EQ(contact.bad, 0) << contact.first_bad;
  EXPECT_LE(static_cast<std::uint64_t>(contact.resting), seen.states.size() - healthy) << "on the top without force where no fault cut the force path";
  EXPECT_GT(contact.on_top - contact.resting, 10) << "the grip never rested on the top: the checks above were vacuous";

  // the Metec cells show the frames: where two frames in a row asked for the same pins, the
  // cells show exactly those from a rise time (24 ms) plus a margin for the I/O thread
  // (12 ms) after the first, until the frame after next can change them
  std::size_t checked = 0, wrong = 0;
  std::size_t f = 0;
  int raised = 0;
  for (const auto& shown : seen.shown) {
    const std::int64_t t = static_cast<std::int64_t>(shown.header().stamp_ns());
    while (f + 2 < seen.frames.size() && static_cast<std::int64_t>(seen.frames[f + 2].header().stamp_ns()) <= t) ++f;
    if (f + 1 >= seen.frames.size()) break;
    const auto& a = seen.frames[f];
    const auto& b = seen.frames[f + 1];
    const std::int64_t ta = static_cast<std::int64_t>(a.header().stamp_ns());
    const bool same = std::equal(a.level().begin(), a.level().end(), b.level().begin(), b.level().end());
    if (!same || t < ta + 36 * kMs || t >= ta + 48 * kMs || b.header().seq() != a.header().seq() + 1) continue;
    ++checked;
    bool match = true;
    for (int i = 0; i < a.level_size(); ++i) {
      match = match && (a.level(i) > 0.5f) == (shown.level(i) > 0.5f);
      raised += a.level(i) > 0.5f && shown.level(i) == 1.0f;
    }
    wrong += !match;
  }
  std::printf("[ usb graph ] tactile/shown checked against the frames %zu times, %zu differed\n", checked, wrong);
  EXPECT_GE(checked, 20u);
  EXPECT_LE(wrong * 20, checked) << "the cells show the frames (5 % allowance for a descheduled I/O thread)";
  EXPECT_GT(raised, 0) << "no pin was ever shown up: the check above was vacuous";

  EXPECT_EQ(launcher.stop(), 0) << launcher.log();
}

}  // namespace
}  // namespace enact::test
