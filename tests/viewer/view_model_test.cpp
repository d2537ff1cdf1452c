// The viewer's model of a graph, fed with messages: histories, the task state from events,
// node statuses, the link state; the ring buffer under the histories.
#include "core/viewer/view_model.h"

#include <gtest/gtest.h>

#include "core/viewer/panels.h"
#include "core/viewer/ring.h"

namespace enact::viewer {
namespace {

msgs::SceneState scene(std::int64_t t_ns, double x, bool on_top, int touching, double fz) {
  msgs::SceneState s;
  s.mutable_header()->set_stamp_ns(t_ns);
  s.mutable_body_position()->set_x(x);
  s.mutable_resultant_force()->set_z(fz);
  for (int i = 0; i < 16; ++i) s.add_in_contact(i < touching);
  s.set_on_top(on_top);
  s.set_progress(0.25);
  return s;
}

msgs::TaskEvent event(msgs::TaskEvent::Kind kind, const std::string& detail = "") {
  msgs::TaskEvent e;
  e.set_kind(kind);
  e.set_detail(detail);
  return e;
}

TEST(Ring, KeepsTheLatestInOrderAndGivesThePlotOffset) {
  Ring<int, 4> r;
  EXPECT_TRUE(r.empty());
  for (int i = 1; i <= 3; ++i) r.push(i);
  EXPECT_EQ(r.size(), 3u);
  EXPECT_EQ(r.offset(), 0u);
  EXPECT_EQ(r[0], 1);
  for (int i = 4; i <= 6; ++i) r.push(i);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0], 3);
  EXPECT_EQ(r.back(), 6);
  // the storage read from offset() wraps around in order, as ImGui::PlotLines reads it
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(r.data()[(r.offset() + i) % 4], static_cast<int>(3 + i));
}

TEST(ViewModel, ScenesFillTheTrailAndTheHistories) {
  ViewModel m;
  EXPECT_FALSE(m.has_scene());
  m.on_scene(scene(1'000'000, 0.001, true, 5, 0.3));
  m.on_scene(scene(2'000'000, 0.002, true, 7, -0.4));
  ASSERT_TRUE(m.has_scene());
  ASSERT_EQ(m.trail().size(), 2u);
  EXPECT_EQ(m.trail()[1].x, 0.002);
  EXPECT_FLOAT_EQ(m.force_history().back(), 0.4f);
  EXPECT_FLOAT_EQ(m.contact_history()[0], 5.0f);
  EXPECT_FLOAT_EQ(m.contact_history().back(), 7.0f);
  EXPECT_TRUE(m.task().on_top);
  EXPECT_EQ(m.task().time_ns, 2'000'000);
}

TEST(ViewModel, EventsCountFallsAndRestartTheTrialClock) {
  ViewModel m;
  m.on_scene(scene(5'000'000'000, 0, false, 0, 0));
  m.on_event(event(msgs::TaskEvent::FALL_START));
  EXPECT_EQ(m.task().falls, 1);
  EXPECT_TRUE(m.task().falling);
  m.on_event(event(msgs::TaskEvent::FALL_END));
  EXPECT_FALSE(m.task().falling);
  // a repositioning keeps the trial, a reset starts a new one at the next scene
  m.on_event(event(msgs::TaskEvent::RESET, "repositioned at the start"));
  EXPECT_EQ(m.task().falls, 1);
  m.on_event(event(msgs::TaskEvent::RESET, "reset"));
  EXPECT_EQ(m.task().falls, 0);
  m.on_scene(scene(6'000'000'000, 0, true, 16, 1));
  m.on_scene(scene(6'500'000'000, 0, true, 16, 1));
  EXPECT_EQ(m.task().time_ns, 500'000'000);
  // stopped: the clock freezes; completed only when the simulator ended it itself
  m.on_event(event(msgs::TaskEvent::TRIAL_END, "stopped"));
  m.on_scene(scene(7'000'000'000, 0, true, 16, 1));
  EXPECT_FALSE(m.task().running);
  EXPECT_FALSE(m.task().completed);
  EXPECT_EQ(m.task().time_ns, 500'000'000);
  m.on_event(event(msgs::TaskEvent::TRIAL_START));
  m.on_event(event(msgs::TaskEvent::TRIAL_END));
  EXPECT_TRUE(m.task().completed);
  EXPECT_EQ(m.log().back(), "trial end");
}

// a discrimination trial's events are named in the log (not "event")
TEST(ViewModel, DiscriminationEventsAreNamedInTheLog) {
  ViewModel m;
  m.on_event(event(msgs::TaskEvent::INTERVAL_START, "1: 660"));
  EXPECT_EQ(m.log().back(), "interval start: 1: 660");
  m.on_event(event(msgs::TaskEvent::INTERVAL_END));
  EXPECT_EQ(m.log().back(), "interval end");
  m.on_event(event(msgs::TaskEvent::ANSWER, "2"));
  EXPECT_EQ(m.log().back(), "answer: 2");
}

TEST(ViewModel, LinkIsWaitingThenConnectedThenLost) {
  ViewModel m;
  EXPECT_EQ(m.link(0), LinkState::waiting);
  msgs::GraphInfo g;
  g.set_graph("bridge_rt");
  m.on_graph(g, 1'000'000'000);
  EXPECT_EQ(m.link(2'000'000'000), LinkState::connected);
  EXPECT_EQ(m.graph_name(), "bridge_rt");
  EXPECT_EQ(m.link(1'000'000'000 + ViewModel::kLost_ns + 1), LinkState::lost);
  m.clear();
  EXPECT_EQ(m.link(2'000'000'000), LinkState::waiting);
}

// the header names the graph once, with its endpoint; before it attaches, what it waits for
TEST(TaskWindow, TheLinkLineNamesTheGraphOnce) {
  const std::string attached = link_line(LinkState::connected, "bridge_rt", "tcp://127.0.0.1:5555");
  EXPECT_EQ(attached, "graph 'bridge_rt' at tcp://127.0.0.1:5555");
  EXPECT_EQ(link_line(LinkState::waiting, "", "graph bridge_rt"), "waiting for graph bridge_rt");
  EXPECT_EQ(link_line(LinkState::lost, "bridge_rt", "tcp://127.0.0.1:5555"), "graph 'bridge_rt' lost (no answer for 3 s)");
}

// a scene without a task says so instead of "OFF the bridge"
TEST(TaskWindow, ASceneWithoutATaskSaysSo) {
  TaskView t;
  t.on_top = false;
  EXPECT_EQ(place_line(t, ""), "no task in this scene: nothing is counted");
  EXPECT_EQ(place_line(t, "bridge"), "OFF the bridge  falls 0");
  t.on_top = true;
  t.falls = 2;
  t.falling = true;
  EXPECT_EQ(place_line(t, "bridge"), "ON the bridge  falls 2 (falling)");
  EXPECT_EQ(place_line(t, "grating"), "ON the grating  falls 2 (falling)") << "the task's own surface, not the bridge";
}

TEST(ViewModel, KeepsTheLastStatusOfEveryNodeAndLogsAnswers) {
  ViewModel m;
  msgs::NodeStatus a, b;
  a.set_node("sim");
  a.set_faults(1);
  b.set_node("ffd");
  m.on_status(a, 10);
  m.on_status(b, 20);
  a.set_faults(3);
  m.on_status(a, 30);
  ASSERT_EQ(m.nodes().size(), 2u);
  EXPECT_EQ(m.nodes().at("sim").status.faults(), 3u);
  EXPECT_EQ(m.nodes().at("sim").received_ns, 30);
  m.on_answer({7, "sim.stiffness_n_per_m", false, "too stiff", true});
  EXPECT_EQ(m.log().back(), "sim.stiffness_n_per_m: refused: too stiff");
  EXPECT_EQ(format_ns(1234), "1.23 us");
  EXPECT_EQ(format_ns(25'000'000), "25.0 ms");
}

TEST(ViewModel, TakesTheSceneTheGraphNames) {
  EXPECT_EQ(sim_of_scene_key("rt.sim.scene"), "sim");
  EXPECT_EQ(sim_of_scene_key("simulator.scene"), "simulator");
  EXPECT_EQ(sim_of_scene_key("rt.ffd.hand_path"), "");
  EXPECT_EQ(sim_of_scene_key(".scene"), "");
  ViewModel m;
  msgs::GraphInfo g;
  auto* hand = g.add_files();
  hand->set_name("rt.ffd.hand_path");
  hand->set_data("t_s,x_m,y_m,z_m");
  m.on_graph(g, 1);
  EXPECT_FALSE(m.graph_scene());
  auto* scene = g.add_files();
  scene->set_name("rt.sim.scene");
  scene->set_data("scene: bridge");
  m.on_graph(g, 2);
  ASSERT_TRUE(m.graph_scene());
  EXPECT_EQ(m.graph_scene()->sim, "sim");
  EXPECT_EQ(m.graph_scene()->data, "scene: bridge");
  EXPECT_TRUE(m.graph_scene()->beside.empty());
  // the files it reads beside it come with it, at their paths relative to it; a parameter
  // whose name merely starts the same is not one of them
  auto* heights = g.add_files();
  heights->set_name("rt.sim.scene/maps/heights.png");
  heights->set_data("PNG");
  auto* other = g.add_files();
  other->set_name("rt.sim.scenery/x.png");
  other->set_data("no");
  m.on_graph(g, 3);
  ASSERT_TRUE(m.graph_scene());
  ASSERT_EQ(m.graph_scene()->beside.size(), 1u);
  EXPECT_EQ(m.graph_scene()->beside[0].first, "maps/heights.png");
  EXPECT_EQ(m.graph_scene()->beside[0].second, "PNG");
}

}  // namespace
}  // namespace enact::viewer
