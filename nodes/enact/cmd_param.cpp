// enact param set NAME VALUE: change a parameter of a running graph and wait for its answer.
#include <cstdio>

#include "core/bus/attach.h"
#include "core/bus/typed.h"
#include "core/graph/node.h"
#include "core/graph/param_bus.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "msgs/param_update.pb.h"
#include "nodes/enact/attach_target.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact param set NAME VALUE [--graph NAME | --attach ENDPOINT] [--key FILE.key --server-key FILE.pub]

Send a parameter change to a running graph on param/set, through its attach point, and wait
for the simulator's answer on param/ack: prints "applied from ffd/state seq N" (the state
whose step first used it; exit 0) or "refused: REASON" (exit 1); no answer within 5 s exits
1 too. VALUE is sent as a number when it is one, as a
flag for true / false, else as text. Names (SIM is the simulator's node or component name,
"sim" in the shipped launch files):
  SIM.model               CM0 CM1 CM2 CM3 P T PT, or a computer model YAML file
  SIM.threshold_m         penetration before force is felt, m (>= 0)
  SIM.stiffness_n_per_m   contact stiffness of the body, N/m   } checked against the
  SIM.damping_n_s_per_m   contact damping of the body, N s/m   } stability analysis
  SIM.reset               (any VALUE) model, pins and task back to the start: a new trial
  SIM.reposition          (any VALUE) the subject is put back at the start
  SIM.trial               start | stop
options:
)";

}  // namespace

int param(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"graph", "attach", "wait", "key", "server-key"}, {});
  if (a.flag("help") || a.positional.empty()) {
    std::fputs(kHelp, a.flag("help") ? stdout : stderr);
    std::fputs(kAttachOptionsHelp, a.flag("help") ? stdout : stderr);
    return a.flag("help") ? 0 : 2;
  }
  if (a.positional[0] != "set" || a.positional.size() != 3) throw UsageError("use: enact param set NAME VALUE");
  graph::install_stop_handlers();
  const bus::ClientKeys keys = attach_keys(a);
  const std::string endpoint = attach_target(a, "param").endpoint;
  // the answer comes on param/ack, through the same attach point
  bus::ByteSubscriber acks_bytes;
  bus::Subscriber<msgs::ParamAck> acks(acks_bytes, graph::kParamAck);
  bus::attach_connect(acks_bytes.socket(), endpoint, keys);
  graph::ParamClient client(endpoint, "enact-param", keys);
  msgs::ParamUpdate update;
  update.set_name(a.positional[1]);
  graph::set_value(update, a.positional[2]);
  client.send(update);
  msgs::ParamAck ack;
  while (true) {
    if (acks.receive(ack, 50)) {
      if (const auto answer = client.take(ack)) {
        if (answer->applied) {
          std::printf("%s = %s: applied from ffd/state seq %llu\n", update.name().c_str(), a.positional[2].c_str(),
                      static_cast<unsigned long long>(ack.state_seq()));
        }
        else std::printf("%s = %s: refused: %s\n", update.name().c_str(), a.positional[2].c_str(), answer->reason.c_str());
        return answer->applied ? 0 : 1;
      }
    }
    for (const graph::ParamAnswer& lost : client.tick(rt::now_ns())) {
      std::fprintf(stderr, "enact param: %s: %s (attach point %s)\n", lost.name.c_str(), lost.reason.c_str(), endpoint.c_str());
      return 1;
    }
  }
}

}  // namespace enact::cli
