// Foxglove's own WebSocket client (@foxglove/ws-protocol over the `ws` package, from the npm
// registry, installed by scripts/setup.sh into .deps/npm) against `enact foxglove`: it checks
// the server info, decodes every advertised channel's schema with protobufjs, checks that
// every topic the graph lists (graph/topics, decoded with its advertised schema) is
// advertised, subscribes to every channel, decodes what arrives (counting what comes in each
// topic's first half second and its steady rate, both by the server's stamps, and how far
// its log time is from the wall clock), and publishes
// one param/set (enact.msgs.ParamUpdate) to see its param/ack; when the graph restarts, what
// arrives on the channels advertised again. Prints a JSON summary.
// Usage: ENACT_NODE_MODULES=DIR/node_modules node foxglove_client.mjs ws://127.0.0.1:PORT SECONDS
import { createRequire } from "node:module";
import path from "node:path";

const require = createRequire(path.join(process.env.ENACT_NODE_MODULES ?? ".", "x.js"));
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const WebSocket = require("ws");
const protobuf = require("protobufjs");
const descriptor = require("protobufjs/ext/descriptor");

const [url, seconds] = [process.argv[2], Number(process.argv[3] ?? "5")];
const summary = { server: null, capabilities: [], channels: {}, graph_topics: [], received: {}, scene: null, ack: null, status: [] };
const types = new Map();        // channel id -> protobufjs Type
const bySubscription = new Map(); // subscription id -> channel
const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
let publishChannel = null;
let firstStamp_s = null;  // the server's stamp (its wall clock when it sent) of the first message

function fail(message) {
  console.error(message);
  process.exit(1);
}

client.on("error", (e) => fail(`websocket error: ${e?.message ?? e}`));
client.on("status", (s) => summary.status.push(s.message));
client.on("serverInfo", (info) => {
  summary.server = info.name;
  summary.capabilities = info.capabilities;
});
// a graph that stopped and started again: its channels gone, the new ones advertised again
const readvertised = new Set();
client.on("unadvertise", (ids) => (summary.unadvertised = (summary.unadvertised ?? 0) + ids.length));
client.on("advertise", (channels) => {
  for (const ch of channels) {
    if (summary.channels[ch.topic]) readvertised.add(ch.id);
    if (ch.encoding !== "protobuf") fail(`${ch.topic}: encoding ${ch.encoding}`);
    const root = protobuf.Root.fromDescriptor(descriptor.FileDescriptorSet.decode(Buffer.from(ch.schema, "base64")));
    types.set(ch.id, root.lookupType(ch.schemaName));
    summary.channels[ch.topic] = { schema: ch.schemaName, max_rate_hz: ch.maxRateHz ?? null };
    bySubscription.set(client.subscribe(ch.id), ch);
  }
  // param/set from the client, with the graph's own schema (every enact channel carries it)
  const graphChannel = channels.find((c) => c.topic === "graph/topics");
  if (!publishChannel && summary.capabilities.includes("clientPublish") && graphChannel) {
    publishChannel = client.advertise({ topic: "param/set", encoding: "protobuf", schemaName: "enact.msgs.ParamUpdate" });
    const update = types.get(graphChannel.id).root.lookupType("enact.msgs.ParamUpdate");
    const bytes = update.encode(update.create({ name: "sim.threshold_m", number: 0.001, request_id: 4242 })).finish();
    // repeated until answered: the attach point drops what arrives before its link is up
    const timer = setInterval(() => (summary.ack ? clearInterval(timer) : client.sendMessage(publishChannel, bytes)), 200);
  }
});
client.on("message", ({ subscriptionId, timestamp, data }) => {
  const ch = bySubscription.get(subscriptionId);
  const type = types.get(ch.id);
  const message = type.toObject(type.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength)), { longs: Number, defaults: true });
  if (readvertised.has(ch.id)) summary.after_restart = { ...summary.after_restart, [ch.topic]: (summary.after_restart?.[ch.topic] ?? 0) + 1 };
  // times by the server's stamps, which say when it sent (a client starved by a busy machine
  // receives in bursts)
  const stamp_s = Number(timestamp) / 1e9;
  firstStamp_s ??= stamp_s;
  const r = (summary.received[ch.topic] ??= { count: 0, first_s: stamp_s, last_s: 0 });
  r.count += 1;
  r.last_s = stamp_s;
  // the rate limit from the first message: what came in its first half second
  if (r.last_s - r.first_s < 0.5) r.first_half_s = (r.first_half_s ?? 0) + 1;
  // the log time: the wall clock (Foxglove shows it as a date)
  summary.most_stamp_offset_s = Math.max(summary.most_stamp_offset_s ?? 0, Math.abs(Number(timestamp) / 1e9 - Date.now() / 1e3));
  // the steady rate: messages sent after the first 1.5 s
  if (r.last_s - firstStamp_s > 1.5) r.steady = (r.steady ?? 0) + 1;
  if (ch.topic === "graph/topics") summary.graph_topics = message.topics.map((t) => t.name);
  if (ch.topic === "foxglove/scene") {
    const entities = message.entities.map((e) => ({ id: e.id, frame: e.frame_id, cubes: e.cubes.length, spheres: e.spheres.length, arrows: e.arrows.length,
      red_spheres: e.spheres.filter((s) => s.color.r > 0.8 && s.color.g < 0.3).length }));
    summary.scene ??= entities;
    const body = entities.find((e) => e.id === "body");
    summary.most_red_spheres = Math.max(summary.most_red_spheres ?? 0, body?.red_spheres ?? 0);
    summary.scenes_with_arrow = (summary.scenes_with_arrow ?? 0) + (body?.arrows ?? 0 ? 1 : 0);
  }
  if (ch.topic === "param/ack" && message.request_id === 4242) summary.ack = { applied: message.applied, reason: message.reason };
});

setTimeout(() => {
  for (const r of Object.values(summary.received)) r.steady_rate_hz = (r.steady ?? 0) / Math.max(r.last_s - firstStamp_s - 1.5, 1e-9);
  console.log(JSON.stringify(summary));
  client.close();
  process.exit(0);
}, seconds * 1000);
