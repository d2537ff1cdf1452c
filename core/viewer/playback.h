#pragma once
// The recording view: a recording (MCAP, core/record) played into the viewer's model as if
// live, on a timeline: play, pause, seek, speed. It reads the topics the live viewer shows
// (sim/scene, task/event, node/status, tactile/shown) and the scene file recorded with them.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/viewer/layout.h"
#include "core/viewer/scene_geometry.h"
#include "core/viewer/view_model.h"

namespace enact::viewer {

class Playback {
 public:
  // reads the recording; throws record::Error when it is not MCAP, config::Error when it
  // holds none of the viewer's topics. A damaged recording plays what can be read.
  explicit Playback(const std::string& path);

  const std::string& path() const { return path_; }
  // the recorded span, from its first message of those topics to its last
  std::int64_t duration_ns() const { return duration_ns_; }
  // the playhead, from the start
  std::int64_t position_ns() const { return position_ns_; }
  // the time of the playhead on the recording's clock (its messages' log time)
  std::int64_t clock_ns() const { return start_ns_ + position_ns_; }
  // the scene the recorded simulator ran (attached by the logger), if any
  const std::optional<NamedScene>& scene() const { return scene_; }

  // moves the playhead (clamped to the recording) and brings `model` to that instant:
  // forward by playing the messages in between, backward by replaying from the start
  void seek(std::int64_t position_ns, ViewModel& model);
  // while playing, the playhead moves on by wall_ns x speed; it stops at the end
  void advance(std::int64_t wall_ns, ViewModel& model);

  bool playing() const { return playing_; }
  void set_playing(bool playing) { playing_ = playing; }
  double speed() const { return speed_; }
  // 0.1 to 10
  void set_speed(double speed);

  // the timeline window: play / pause, the position slider, the speed
  void draw(const Rect& r, ViewModel& model);
  // keys: space plays / pauses, ',' and '.' seek 5 s back / on, '<' '>' halve / double the speed
  void on_key(char key, ViewModel& model);

 private:
  enum class Topic : std::uint8_t { scene, event, status, shown };
  struct Item {
    std::int64_t time_ns;
    Topic topic;
    std::string data;
  };
  void play_until(std::int64_t clock_ns, ViewModel& model);

  std::string path_;
  std::vector<Item> items_;  // by log time
  std::optional<NamedScene> scene_;
  std::int64_t start_ns_ = 0, duration_ns_ = 0, position_ns_ = 0;
  std::size_t next_ = 0;     // the first item not yet played
  bool playing_ = false;
  double speed_ = 1.0;
};

}  // namespace enact::viewer
