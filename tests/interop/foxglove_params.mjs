// Foxglove's own WebSocket client (@foxglove/ws-protocol, installed by scripts/setup.sh into
// .deps/npm) as Foxglove's Parameters and Publish panels use it, against `enact foxglove`:
// getParameters (every parameter of the graph), subscribeParameterUpdates, setParameters on
// a live parameter, a fixed one and a misspelt one, then param/set published in json (what
// the Publish panel sends) and a malformed json message; the channels Foxglove Studio's 3D
// panel advertises on every connect (/clicked_point, /initialpose, /move_base_simple/goal),
// with a message on one. Prints a JSON summary.
// Usage: ENACT_NODE_MODULES=DIR/node_modules node foxglove_params.mjs ws://127.0.0.1:PORT SECONDS
import { createRequire } from "node:module";
import path from "node:path";

const require = createRequire(path.join(process.env.ENACT_NODE_MODULES ?? ".", "x.js"));
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const WebSocket = require("ws");
const protobuf = require("protobufjs");
const descriptor = require("protobufjs/ext/descriptor");

const [url, seconds] = [process.argv[2], Number(process.argv[3] ?? "5")];
const summary = { capabilities: [], supported_encodings: [], params: {}, answers: {}, updates: {}, statuses: [], acks: {} };
const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
const ackChannel = { id: null, type: null, subscription: null };
let published = false;

client.on("error", (e) => {
  console.error(`websocket error: ${e?.message ?? e}`);
  process.exit(1);
});
client.on("status", (s) => summary.statuses.push({ level: s.level, message: s.message }));
client.on("serverInfo", (info) => {
  summary.capabilities = info.capabilities;
  summary.supported_encodings = info.supportedEncodings ?? [];
  client.subscribeParameterUpdates([]);
  // the parameters arrive from the nodes: ask until the list has them
  const timer = setInterval(() => (Object.keys(summary.params).length ? clearInterval(timer) : client.getParameters([], "all")), 200);
});
client.on("advertise", (channels) => {
  const ack = channels.find((c) => c.topic === "param/ack");
  if (!ack || ackChannel.id !== null) return;
  const root = protobuf.Root.fromDescriptor(descriptor.FileDescriptorSet.decode(Buffer.from(ack.schema, "base64")));
  Object.assign(ackChannel, { id: ack.id, type: root.lookupType(ack.schemaName), subscription: client.subscribe(ack.id) });
});
client.on("message", ({ subscriptionId, data }) => {
  if (subscriptionId !== ackChannel.subscription) return;
  const a = ackChannel.type.toObject(ackChannel.type.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength)), { longs: String });
  summary.acks[a.request_id] = { applied: a.applied ?? false, reason: a.reason ?? "", number: a.number ?? null };
});
client.on("parameterValues", ({ parameters, id }) => {
  if (id === undefined) {
    for (const p of parameters) summary.updates[p.name] = p.value;
    return;
  }
  if (id !== "all") {
    summary.answers[id] = parameters;
    return;
  }
  if (parameters.length === 0 || Object.keys(summary.params).length) return;
  for (const p of parameters) summary.params[p.name] = p.value;
  client.setParameters([{ name: "sim.stiffness_n_per_m", value: 2500 }], "set-live");
  client.setParameters([{ name: "sim.min_fall_s", value: 2 }], "set-fixed");
  client.setParameters([{ name: "sim.stifness_n_per_m", value: 1 }], "set-typo");
  publishJson();
});

// the Publish panel's way: a json channel on param/set with the message's schema name
function publishJson() {
  if (published) return;
  published = true;
  const channel = client.advertise({ topic: "param/set", encoding: "json", schemaName: "enact.msgs.ParamUpdate" });
  const text = (o) => new TextEncoder().encode(JSON.stringify(o));
  client.sendMessage(channel, text({ name: "sim.threshold_m", number: 0.002, requestId: "4343" }));
  client.sendMessage(channel, text({ nmae: "sim.threshold_m" }));
  const panel = ["/clicked_point", "/initialpose", "/move_base_simple/goal"].map((topic) =>
    client.advertise({ topic, encoding: "json", schemaName: topic === "/clicked_point" ? "geometry_msgs/PointStamped" : "geometry_msgs/PoseStamped" }));
  client.sendMessage(panel[0], text({ point: { x: 0.01, y: 0.02, z: 0.0 } }));
}

setTimeout(() => {
  console.log(JSON.stringify(summary));
  client.close();
  process.exit(0);
}, seconds * 1000);
