#pragma once
// The observer components: the logger, recording to an MCAP file until stopped, then closing
// it complete and indexed (`enact record` is the same from the shell), and the Foxglove
// bridge, serving the graph over WebSocket (`enact foxglove`). Both attach through the
// graph's attach point (their `attach` parameter, else $ENACT_ATTACH, set by `enact launch`).
//
// One lifecycle, wherever a component runs: made = configured (its parameters read and
// checked: bad input is refused there, nothing is bound; the launcher's --check stops there),
// activate() attaches to the graph, run() observes until `stop` says so or the graph is gone,
// deactivate() leaves what it made whole. The same class runs as its own node (enact-logger,
// enact-foxglove: ObserverNode below) or on a thread of the co-located container beside its
// loop (enact-rt: plugin logger, plugin foxglove; never on the loop's thread).
#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "core/node/host.h"
#include "core/params/params.h"

namespace enact::node {

class Observer {
 public:
  virtual ~Observer() = default;
  // attaches to the graph (throws config::Error with the fix when none answers); what it does,
  // in one line ("recording every topic to trial.mcap")
  virtual std::string activate() = 0;
  // observes until `stop` returns true or the graph is gone (then drains what is on its way);
  // false: it failed (a write failure, the graph gone under a bridge)
  virtual bool run(const std::function<bool()>& stop) = 0;
  // closes what it made; how it went, for the node's output
  struct Ending {
    std::string said;  // "" when nothing was made
    bool ok = true;    // false: what it made is not whole (a write failure)
  };
  virtual Ending deactivate() = 0;
  // it records `topic` (a loop waits for each that records its device states)
  virtual bool records(const std::string& topic) const { (void)topic; return false; }
};

// the observer of `plugin` ("logger" or "foxglove"), configured from `p` (its own parameters,
// unscoped; the ones it reads are taken); nullptr for another plugin
std::unique_ptr<Observer> make_observer(const std::string& plugin, graph::Params& p);

// observer components on threads of their own beside a container's loop: each activated on
// the caller's thread (an error there is the container's, at its start), then run on its
// thread until stop_all(), which lets each take what is on its way first
class ObserverGroup {
 public:
  explicit ObserverGroup(std::string node) : node_(std::move(node)) {}
  ObserverGroup(const ObserverGroup&) = delete;
  ObserverGroup& operator=(const ObserverGroup&) = delete;
  ~ObserverGroup();  // stops and joins any still running (what they made is closed)

  // component `name` of plugin `plugin`, configured from its parameters (`p`, scoped to it)
  void add(const std::string& name, const std::string& plugin, graph::Params& p);
  // how many record `topic`: a loop waits for each before its first tick
  int recorders(const std::string& topic) const;
  // activates the loggers (recorders: true) or the others, and starts their threads
  void start(bool recorders);
  // stops them all, closes what they made and says how each went; false: one failed
  bool stop_all();

 private:
  struct Member {
    std::string name;
    bool recorder = false;
    std::unique_ptr<Observer> observer;
    std::thread thread;
    bool ran = true;
    std::string error;  // what its run() threw
  };
  std::string node_;
  std::deque<Member> members_;  // a running thread holds its member: never moved
  std::atomic<bool> stop_{false};
};

// an observer as a node process: host_main<LoggerNode>, host_main<FoxgloveNode>
class ObserverNode {
 public:
  ObserverNode(Host& host, const char* plugin);
  // its lifecycle in the process host (host_main): an observer publishes nothing of its own
  void open_ports() {}
  void activate();
  void run();
  int deactivate();

 private:
  Host& host_;
  std::unique_ptr<Observer> observer_;
  std::string doing_;  // what activate() said it does
  bool ran_ = false;   // run() ended well
};

extern const NodeKind kLogger;
extern const NodeKind kFoxglove;
struct LoggerNode : ObserverNode {
  explicit LoggerNode(Host& host) : ObserverNode(host, "logger") {}
};
struct FoxgloveNode : ObserverNode {
  explicit FoxgloveNode(Host& host) : ObserverNode(host, "foxglove") {}
};

}  // namespace enact::node
