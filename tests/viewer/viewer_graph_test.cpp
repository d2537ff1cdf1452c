// The viewer and parameter changes against the real co-located graph (launch/bridge_rt.yaml
// started with the real `enact launch`), the viewer's window on an Xvfb display of its own:
// a snapshot shows the bridge and the grid where the scene says they are, live and from a
// recording; a parameter change round-trips (applied by the simulator, acknowledged; an
// unstable stiffness refused with the reason); killing the viewer leaves the graph running
// with no fault; a viewer started before the graph connects when the graph appears.
#include <poll.h>
#include <signal.h>
#include <stb_image.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "core/physics/scene.h"
#include "core/record/reader.h"
#include "core/viewer/draw.h"
#include "core/viewer/layout.h"
#include "core/viewer/scene_geometry.h"
#include "msgs/task_state.pb.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

constexpr double kReadyTimeout_s = 20.0;

// a program in the background (spawn), killed when destroyed
class Process {
 public:
  Process(std::vector<std::string> argv, const std::string& out, const std::string& err, const std::vector<std::string>& env = {})
      : pid_(spawn(std::move(argv), out, err, env)) {}
  ~Process() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  bool running() {
    if (pid_ > 0 && waitpid(pid_, &status_, WNOHANG) == pid_) pid_ = -1;
    return pid_ > 0;
  }
  // the exit code once it ended within timeout_s, else nullopt
  std::optional<int> wait(double timeout_s) {
    const auto end = after(timeout_s);
    while (running()) {
      if (Clock::now() > end) return std::nullopt;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
  }
  void kill_now() {
    if (pid_ > 0) kill(pid_, SIGKILL);
    wait(5.0);
  }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
};

// an X server of our own (Xvfb picks a free display and tells it through -displayfd)
class Xvfb {
 public:
  Xvfb() {
    if (run("command -v Xvfb").exit_code != 0) return;
    int fds[2];
    if (pipe(fds) != 0) return;
    const TempDir& dir = dir_;
    server_ = std::make_unique<Process>(std::vector<std::string>{"/bin/sh", "-c", "exec Xvfb -displayfd " + std::to_string(fds[1]) + " -screen 0 1280x800x24 -nolisten tcp"},
                                        dir.file("xvfb.out"), dir.file("xvfb.err"));
    close(fds[1]);
    // the display number, one line, once the server accepts clients
    std::string number;
    pollfd p{fds[0], POLLIN, 0};
    char c = 0;
    while (poll(&p, 1, 10000) > 0 && read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    close(fds[0]);
    if (!number.empty()) display_ = ":" + number;
  }
  // "" when there is no Xvfb
  const std::string& display() const { return display_; }

 private:
  TempDir dir_;
  std::unique_ptr<Process> server_;
  std::string display_;
};

// a viewer on a display of its own, its output in the test's folder
class ViewerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (x_.display().empty()) GTEST_SKIP() << "Xvfb is not installed or did not start (apt-get install xvfb): the viewer's window tests need a display";
  }
  std::unique_ptr<Process> viewer(const std::vector<std::string>& args) {
    std::vector<std::string> argv{ENACT_VIEWER};
    argv.insert(argv.end(), args.begin(), args.end());
    // one rendering thread for Mesa's llvmpipe: the graphs of other tests share the processors
    return std::make_unique<Process>(argv, dir_.file("viewer.out"), dir_.file("viewer.err"), std::vector<std::string>{"DISPLAY=" + x_.display(), "LP_NUM_THREADS=1"});
  }
  std::string viewer_out() const { return read_file(dir_.file("viewer.out")); }
  std::string viewer_err() const { return read_file(dir_.file("viewer.err")); }

  Xvfb x_;
  TempDir dir_;
};

// what the viewer says it showed in its snapshot
struct Shown {
  math::Vec3 body_m;
  std::uint32_t contact = 0;
  std::string model;
};
std::optional<Shown> parse_snapshot_line(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex("body (\\S+) (\\S+) (\\S+) m, contact mask 0x([0-9a-f]+), model (\\S+)"))) return std::nullopt;
  return Shown{{std::stod(m[1]), std::stod(m[2]), std::stod(m[3])}, static_cast<std::uint32_t>(std::stoul(m[4], nullptr, 16)), m[5]};
}

// an RGB image read back
struct Image {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;
  explicit Image(const std::string& path) {
    int n = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 3);
    if (!data) throw std::runtime_error("cannot read " + path);
    rgb.assign(data, data + static_cast<std::size_t>(w) * h * 3);
    stbi_image_free(data);
  }
  // the pixel under a scene point of the top view is `colour` (to 3 per channel)
  bool is(const viewer::Pixel& p, ImU32 colour) const {
    const int x = static_cast<int>(p.x), y = static_cast<int>(p.y);
    if (x < 0 || y < 0 || x >= w || y >= h) return false;
    const unsigned char* px = &rgb[(static_cast<std::size_t>(y) * w + x) * 3];
    const int want[3] = {static_cast<int>(colour & 0xff), static_cast<int>((colour >> 8) & 0xff), static_cast<int>((colour >> 16) & 0xff)};
    for (int c = 0; c < 3; ++c) {
      if (std::abs(px[c] - want[c]) > 3) return false;
    }
    return true;
  }
};

// the snapshot `png` shows the bridge where the scene file says it is, nothing far from it,
// and the grid where `shown` puts the body, each mass in its contact colour
void expect_bridge_and_grid(const std::string& png, const Shown& shown) {
  const Image img(png);
  ASSERT_EQ(img.w, 1280);
  ASSERT_EQ(img.h, 800);
  // the scene, read from its file here, and where the layout puts the top view
  const physics::Model model = physics::load_scene(source_path("launch/scenes/bridge.yaml"));
  const viewer::TopView view(viewer::geometry_of(model), viewer::layout(1280, 800).top_view);
  std::vector<task::Point2> line;
  for (const auto& p : model.objects[model.find_object("bridge")].path.centerline_m) line.push_back({p.x, p.y});
  const task::Polyline path(line);
  // the bridge: 3.5 mm either side of its centreline (inside its 10 mm width), away from
  // the grid; the trail may cross a few of these points
  int bridge = 0, bridge_samples = 0;
  for (double s = 0.002; s < path.length_m() - 0.002; s += 0.001) {
    const task::Point2 p = path.at(s), d = path.direction_at(s);
    for (const double side : {-0.0035, 0.0035}) {
      const double qx = p.x_m - d.y_m * side, qy = p.y_m + d.x_m * side;
      if (std::hypot(qx - shown.body_m.x, qy - shown.body_m.y) < 0.009) continue;
      ++bridge_samples;
      bridge += img.is(view.to_screen(qx, qy), viewer::palette::kBridge);
    }
  }
  ASSERT_GT(bridge_samples, 60);
  EXPECT_GT(bridge, bridge_samples * 85 / 100) << bridge << " of " << bridge_samples << " points on the bridge have its colour";
  // off the bridge: workspace points over 12 mm from the centreline show the panel
  int empty = 0, empty_samples = 0;
  for (double px = -0.028; px <= 0.028; px += 0.002) {
    for (double py = -0.028; py <= 0.028; py += 0.002) {
      if (std::abs(path.project(px, py).lateral_m) < 0.012) continue;
      ++empty_samples;
      empty += img.is(view.to_screen(px, py), viewer::palette::kPanel);
    }
  }
  ASSERT_GT(empty_samples, 100);
  EXPECT_GT(empty, empty_samples * 90 / 100) << empty << " of " << empty_samples << " points off the bridge are empty";
  // the grid: each mass where the body and its offset put it, in its contact colour
  for (int i = 0; i < 16; ++i) {
    const math::Vec3& offset = model.points[model.proxies[0].first_body + i].offset_m;
    const viewer::Pixel at = view.to_screen(shown.body_m.x + offset.x, shown.body_m.y + offset.y);
    const bool touching = (shown.contact >> i) & 1u;
    EXPECT_TRUE(img.is(at, touching ? viewer::palette::kMassContact : viewer::palette::kMassFree)) << "mass " << i << (touching ? " (in contact)" : " (free)");
  }
}

TEST_F(ViewerTest, SnapshotShowsTheBridgeAndTheGridWhereTheSceneSays) {
  // no --scene: the viewer draws the scene the graph's GraphInfo carries
  Launcher launcher(dir_, source_path("launch/bridge_rt.yaml"), 30.0);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  const std::string png = dir_.file("snap.png");
  ASSERT_EQ(viewer({"--attach", launcher.endpoint(), "--snapshot", png, "--after", "2.5"})->wait(30.0), 0) << viewer_err();
  const auto shown = parse_snapshot_line(viewer_out());
  ASSERT_TRUE(shown) << "the viewer showed no scene: " << viewer_out();
  EXPECT_EQ(shown->model, "CM1");
  expect_bridge_and_grid(png, *shown);
}

// a viewer attached after the trial's end shows its falls and completion (task/state is
// latched at the attach point), not "falls 0, running"
TEST_F(ViewerTest, AViewerAttachedLateShowsTheTrialsFallsAndCompletion) {
  setenv("ENACT_REGISTRY", dir_.file("registry").c_str(), 1);
  Launcher launcher(dir_, source_path("launch/bridge_rt.yaml"), 60.0);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  // the scripted hand completes the bridge, after a fall, in about 10 s
  Observer watch(launcher.endpoint());
  bus::Subscriber<msgs::TaskState> states(watch.bytes(), "task/state");
  msgs::TaskState s;
  const auto end = after(50.0);
  while (Clock::now() < end && !(states.receive(s, 100) && s.phase() == msgs::TaskState::COMPLETED)) {
  }
  ASSERT_EQ(s.phase(), msgs::TaskState::COMPLETED);
  ASSERT_GT(s.falls(), 0) << "the scripted walk falls once: a late viewer counting events alone would show 0";
  // the only graph running (this test's registry): no option needed
  ASSERT_EQ(viewer({"--snapshot", dir_.file("late.png"), "--after", "1.5"})->wait(30.0), 0) << viewer_err();
  EXPECT_NE(viewer_out().find("task: falls " + std::to_string(s.falls()) + ", trial"), std::string::npos) << viewer_out();
  EXPECT_NE(viewer_out().find("(completed)"), std::string::npos) << viewer_out();
  EXPECT_NE(viewer_err().find("attached to graph bridge_rt at " + launcher.endpoint()), std::string::npos) << viewer_err();
}

TEST_F(ViewerTest, AGraphWithAnAccessFileIsShownOnlyToAViewerWithKeys) {
  for (const char* name : {"graph", "desk"}) ASSERT_EQ(run(std::string(ENACT_CLI) + " keys new " + name + " --dir " + dir_.path()).exit_code, 0);
  write_file(dir_.file("access.yaml"), "server_key: graph.key\nclients:\n  - {name: desk, public_key_file: desk.pub, role: operate}\n");
  Launcher launcher(dir_, source_path("launch/bridge_rt.yaml"), 30.0, {}, "", {"--access", dir_.file("access.yaml")});
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  // without keys: refused, and told why
  const std::string png = dir_.file("snap.png");
  EXPECT_EQ(viewer({"--attach", launcher.endpoint(), "--snapshot", png, "--after", "1"})->wait(30.0), 1);
  EXPECT_NE(viewer_err().find("requires keys"), std::string::npos) << viewer_err();
  // with keys: the scene, as on a graph without an access file
  ASSERT_EQ(viewer({"--attach", launcher.endpoint(), "--key", dir_.file("desk.key"), "--server-key", dir_.file("graph.pub"), "--snapshot", png, "--after", "2.5"})->wait(30.0), 0)
      << viewer_err();
  const auto shown = parse_snapshot_line(viewer_out());
  ASSERT_TRUE(shown) << "the viewer showed no scene: " << viewer_out();
  EXPECT_EQ(shown->model, "CM1");
}

TEST_F(ViewerTest, ARecordingShowsTheSceneRecordedAtTheTimeAsked) {
  Launcher launcher(dir_, source_path("launch/bridge_rt.yaml"), 30.0);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  const std::string mcap = dir_.file("trial.mcap");
  const RunResult rec = run(std::string(ENACT_CLI) + " record -o " + mcap + " --attach " + launcher.endpoint() + " --duration 4");
  ASSERT_EQ(rec.exit_code, 0) << rec.out << rec.err;
  launcher.stop();
  // what the recording holds 2 s after its first message the viewer reads
  record::Reader r(mcap);
  std::int64_t first_ns = -1;
  msgs::SceneState at_2s;
  r.for_each([&](const record::Message& m) {
    if (m.topic != "sim/scene" && m.topic != "task/event" && m.topic != "node/status" && m.topic != "tactile/shown") return true;
    if (first_ns < 0) first_ns = m.log_time_ns;
    if (m.topic == "sim/scene" && m.log_time_ns <= first_ns + 2'000'000'000) at_2s.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()));
    return true;
  });
  ASSERT_TRUE(at_2s.has_body_position());
  // the viewer alone with the recording (no graph), paused at 2 s
  const std::string png = dir_.file("snap.png");
  ASSERT_EQ(viewer({mcap, "--at", "2", "--snapshot", png, "--after", "0.5"})->wait(30.0), 0) << viewer_err();
  const auto shown = parse_snapshot_line(viewer_out());
  ASSERT_TRUE(shown) << viewer_out();
  EXPECT_NEAR(shown->body_m.x, at_2s.body_position().x(), 1e-6);
  EXPECT_NEAR(shown->body_m.y, at_2s.body_position().y(), 1e-6);
  EXPECT_NEAR(shown->body_m.z, at_2s.body_position().z(), 1e-6);
  expect_bridge_and_grid(png, *shown);
}

// a recording of a scene that reads a file beside it (the ridge's height map): the viewer
// and the Foxglove export put the file back beside the scene and show it, as resim does
TEST_F(ViewerTest, ARecordingOfAHeightMapSceneShowsItsScene) {
  Launcher launcher(dir_, source_path("launch/bridge_rt.yaml"), 30.0, {"scene=" + source_path("launch/scenes/ridge.yaml")});
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  const std::string mcap = dir_.file("ridge.mcap");
  const RunResult rec = run(std::string(ENACT_CLI) + " record -o " + mcap + " --attach " + launcher.endpoint() + " --duration 2");
  ASSERT_EQ(rec.exit_code, 0) << rec.out << rec.err;
  launcher.stop();
  ASSERT_EQ(viewer({mcap, "--at", "1", "--snapshot", dir_.file("ridge.png"), "--after", "0.5"})->wait(30.0), 0) << viewer_err();
  EXPECT_TRUE(parse_snapshot_line(viewer_out())) << viewer_out() << viewer_err();
  const RunResult fox = run(std::string(ENACT_CLI) + " export " + mcap + " --foxglove " + dir_.file("ridge_foxglove.mcap"));
  ASSERT_EQ(fox.exit_code, 0) << fox.out << fox.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(fox.out, m, std::regex("(\\d+) scene updates"))) << fox.out;
  EXPECT_GT(std::stoi(m[1]), 0) << fox.out;
}

TEST(ParamGraph, ParameterChangesRoundTripAndAnUnstableStiffnessIsRefused) {
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge_rt.yaml"), 30.0);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  const std::string cli = std::string(ENACT_CLI) + " param set ";
  const std::string at = " --attach " + launcher.endpoint();
  const RunResult soft = run(cli + "sim.stiffness_n_per_m 3000" + at);
  EXPECT_EQ(soft.exit_code, 0) << soft.out << soft.err;
  EXPECT_NE(soft.out.find("applied"), std::string::npos) << soft.out;
  const RunResult wild = run(cli + "sim.stiffness_n_per_m 1e6" + at);
  EXPECT_EQ(wild.exit_code, 1) << wild.out << wild.err;
  EXPECT_NE(wild.out.find("refused"), std::string::npos) << wild.out;
  EXPECT_NE(wild.out.find("Colgate & Schenkel"), std::string::npos) << wild.out;
  EXPECT_NE(wild.out.find("fix: at most 6000 N/m"), std::string::npos) << wild.out;
  const RunResult unknown = run(cli + "sim.stifness 1" + at);
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.out.find("unknown parameter"), std::string::npos) << unknown.out;
  // the simulator applies a model switch: the scene says so from then on, and a task event
  Observer obs(launcher.endpoint());
  obs.scenes.emplace(obs.bytes(), "sim/scene");
  obs.events.emplace(obs.bytes(), "task/event");
  Observed seen;
  obs.observe(1.0, seen);
  ASSERT_FALSE(seen.scenes.empty());
  EXPECT_EQ(seen.scenes.back().model(), "CM1");
  const RunResult cm3 = run(cli + "sim.model CM3" + at);
  ASSERT_EQ(cm3.exit_code, 0) << cm3.out << cm3.err;
  Observed after_switch;
  obs.observe(1.0, after_switch);
  ASSERT_FALSE(after_switch.scenes.empty());
  EXPECT_EQ(after_switch.scenes.back().model(), "CM3");
  bool condition = false;
  for (const auto& e : after_switch.events) condition = condition || (e.kind() == msgs::TaskEvent::CONDITION && e.condition() == "CM3");
  EXPECT_TRUE(condition) << "no CONDITION event for CM3";
  // every scene names the model its pins come from: CM1 raises the pins of the masses in
  // contact, CM3 those of the masses not in contact (the scenes taken before the switch
  // are still queued for this observer)
  int cm3_scenes = 0;
  for (const auto& s : after_switch.scenes) {
    ASSERT_TRUE(s.model() == "CM1" || s.model() == "CM3") << s.model();
    cm3_scenes += s.model() == "CM3";
    for (int i = 0; i < s.pin_level_size(); ++i) EXPECT_EQ(s.pin_level(i) > 0.5f, s.in_contact(i) == (s.model() == "CM1")) << s.ShortDebugString();
  }
  EXPECT_GT(cm3_scenes, 30);
}

TEST_F(ViewerTest, KillingTheViewerLeavesTheGraphRunningWithoutFault) {
  Launcher launcher(dir_, source_path("launch/bridge_rt.yaml"), 6.0);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  const auto running = viewer({"--attach", launcher.endpoint()});
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  ASSERT_TRUE(running->running()) << viewer_err();
  running->kill_now();
  // the graph runs to its end: a clean stop, no model fault, nothing dropped between threads
  const auto code = launcher.wait_exit(20.0);
  ASSERT_TRUE(code) << launcher.log();
  EXPECT_EQ(*code, 0) << launcher.log();
  const std::string out = launcher.out();
  EXPECT_NE(out.find("model faults 0, queue drops 0"), std::string::npos) << out;
  EXPECT_EQ(launcher.log().find("exited"), std::string::npos) << launcher.log();
}

TEST_F(ViewerTest, AViewerStartedBeforeTheGraphConnectsWhenItAppears) {
  const std::string endpoint = "tcp://127.0.0.1:" + std::to_string(free_port());
  const auto early = viewer({"--attach", endpoint, "--scene", source_path("launch/scenes/bridge.yaml"), "--snapshot", dir_.file("snap.png"), "--after", "7"});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_TRUE(early->running()) << viewer_err();
  Launcher launcher(dir_, source_path("launch/bridge_rt.yaml"), 20.0, {}, endpoint);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  ASSERT_EQ(early->wait(30.0), 0) << viewer_err();
  const std::string out = viewer_out();
  EXPECT_TRUE(parse_snapshot_line(out)) << "the viewer never showed the graph's scene: " << out;
}

}  // namespace
}  // namespace enact::test
