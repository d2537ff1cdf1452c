// An independent reader of enact's MCAP recordings: the foxglove @mcap/core library reads
// every record with CRC validation (chunks, data section, summary), once streaming and once
// through the summary's indexes, and protobufjs decodes every message with the schema
// (a FileDescriptorSet) stored in the file. Prints a JSON summary; exits 1 on any problem.
// Usage: ENACT_NODE_MODULES=DIR/node_modules node read_mcap.mjs FILE.mcap
import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import path from "node:path";

const require = createRequire(path.join(process.env.ENACT_NODE_MODULES ?? ".", "x.js"));
const { McapStreamReader, McapIndexedReader } = require("@mcap/core");
const { loadDecompressHandlers } = require("@mcap/support");
const protobuf = require("protobufjs");
const descriptor = require("protobufjs/ext/descriptor");

const file = process.argv[2];
const bytes = new Uint8Array(await readFile(file));
const decompressHandlers = await loadDecompressHandlers();

// 1. streaming, every record, CRCs validated
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
const schemas = new Map();
const channels = new Map();
const types = new Map();
const summary = { messages: 0, decoded: 0, topics: {}, seq_sum: 0, metadata: [], attachments: [], footer: false, data_end: false };
for (let record; (record = stream.nextRecord()); ) {
  switch (record.type) {
    case "Schema": schemas.set(record.id, record); break;
    case "Channel": channels.set(record.id, record); break;
    case "Metadata": summary.metadata.push(record.name); break;
    case "Attachment": summary.attachments.push(record.name); break;
    case "DataEnd": summary.data_end = true; break;
    case "Footer": summary.footer = true; break;
    case "Message": {
      const channel = channels.get(record.channelId);
      const schema = schemas.get(channel.schemaId);
      if (schema.encoding !== "protobuf" || channel.messageEncoding !== "protobuf") throw new Error(`unexpected encodings on ${channel.topic}`);
      let type = types.get(schema.id);
      if (!type) {
        const root = protobuf.Root.fromDescriptor(descriptor.FileDescriptorSet.decode(schema.data));
        type = root.lookupType(schema.name);
        types.set(schema.id, type);
      }
      const message = type.toObject(type.decode(record.data), { longs: Number });
      summary.messages += 1;
      summary.decoded += 1;
      summary.topics[channel.topic] = (summary.topics[channel.topic] ?? 0) + 1;
      summary.seq_sum += message.header?.seq ?? 0;
      break;
    }
    default: break;
  }
}
if (!stream.done()) throw new Error("the stream reader did not reach the end of the file");

// 2. indexed: the footer, the summary (statistics, chunk indexes), every message again
const indexed = await McapIndexedReader.Initialize({
  readable: { size: async () => BigInt(bytes.length), read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)) },
  decompressHandlers,
});
let indexedMessages = 0;
for await (const _ of indexed.readMessages({ validateCrcs: true })) indexedMessages += 1;
summary.indexed_messages = indexedMessages;
summary.statistics_messages = Number(indexed.statistics?.messageCount ?? -1);
summary.chunks = indexed.chunkIndexes.length;
console.log(JSON.stringify(summary));
