#!/usr/bin/python3
"""Attach to a running enact graph and print what it carries.

    attach_example.py ENDPOINT [TOPIC ...] [--count N] [--timeout S]
                      [--key FILE.key --server-key FILE.pub]

Connects a SUB socket to the attach endpoint the graph prints (e.g. tcp://127.0.0.1:40123),
reads one GraphInfo from "graph/topics" to list the topics and load every message schema,
then prints N messages of each TOPIC given, decoded from those schemas alone: no .proto
files, no generated code. For a graph launched with --access, --key (your secret key) and
--server-key (the graph's public key) make the connection a CURVE client's (files made by
`enact keys new`). Needs python3-zmq and python3-protobuf (Debian).
Wire format and protocol: core/bus/README.md.
"""
import argparse
import sys
import time

import zmq
from google.protobuf import descriptor_pb2, descriptor_pool, message_factory, text_format

GRAPH_TOPIC = "graph/topics"
GRAPH_TYPE = "enact.msgs.GraphInfo"

# the one field of GraphInfo a client must know beforehand: descriptor_set = 4 (bytes); it
# holds the schema of everything else, GraphInfo included
BOOTSTRAP = """
name: "enact_bootstrap.proto"
package: "enact_bootstrap"
syntax: "proto3"
message_type {
  name: "GraphInfoSchemas"
  field { name: "descriptor_set" number: 4 type: TYPE_BYTES label: LABEL_OPTIONAL }
}
"""


def message_class(pool, full_name):
    """The Python class of message type `full_name` in `pool` (protobuf 3.x/4.x APIs)."""
    desc = pool.FindMessageTypeByName(full_name)
    if hasattr(message_factory, "GetMessageClass"):
        return message_factory.GetMessageClass(desc)
    return message_factory.MessageFactory(pool).GetPrototype(desc)


def pool_from(descriptor_set):
    """A descriptor pool holding every file of a serialized FileDescriptorSet."""
    pool = descriptor_pool.DescriptorPool()
    for file_proto in descriptor_pb2.FileDescriptorSet.FromString(descriptor_set).file:
        pool.Add(file_proto)  # the files come after the files they import
    return pool


def read_key(path):
    """The key in an enact key file: the first line that is not a '#' comment (Z85)."""
    with open(path, encoding="ascii") as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                return line.encode()
    sys.exit(f"{path}: holds no key (make one with `enact keys new NAME`)")


def use_keys(sock, key_file, server_key_file):
    """Makes `sock` a CURVE client: our secret key and its public key, the graph's public key."""
    secret = read_key(key_file)
    sock.curve_secretkey = secret
    sock.curve_publickey = zmq.curve_public(secret)
    server = read_key(server_key_file)
    sock.curve_serverkey = zmq.curve_public(server) if server_key_file.endswith(".key") else server


def receive(sub, topics, deadline):
    """The next (topic, type, payload) on one of `topics`, or None at the deadline.

    ZeroMQ filters by prefix: "ffd/state" also lets "ffd/state2" through, so the topic
    frame is checked exactly. Messages without exactly 3 frames are skipped.
    """
    while True:
        left_ms = int((deadline - time.monotonic()) * 1000)
        if left_ms <= 0 or not sub.poll(left_ms):
            return None
        frames = sub.recv_multipart()
        if len(frames) != 3:
            continue
        topic = frames[0].decode("utf-8", "replace")
        if topic in topics:
            return topic, frames[1].decode("utf-8", "replace"), frames[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("endpoint", help="attach endpoint printed by the graph, e.g. tcp://127.0.0.1:40123")
    parser.add_argument("topics", nargs="*", help="topics to print (default: only list them)")
    parser.add_argument("--count", type=int, default=5, help="messages to print per topic (default 5)")
    parser.add_argument("--timeout", type=float, default=10.0, help="give up after this many seconds")
    parser.add_argument("--key", help="your secret key (FILE.key), for a graph launched with --access")
    parser.add_argument("--server-key", help="the graph's public key (FILE.pub)")
    args = parser.parse_args()
    if (args.key is None) != (args.server_key is None):
        parser.error("give both --key and --server-key, or neither")
    deadline = time.monotonic() + args.timeout

    sub = zmq.Context.instance().socket(zmq.SUB)
    sub.linger = 0
    if args.key:
        use_keys(sub, args.key, args.server_key)
    sub.connect(args.endpoint)

    # the graph: topics and schemas
    sub.subscribe(GRAPH_TOPIC.encode())
    got = receive(sub, {GRAPH_TOPIC}, deadline)
    if got is None:
        sys.exit(f"no GraphInfo from {args.endpoint} within {args.timeout} s: is the graph running?")
    bootstrap_pool = descriptor_pool.DescriptorPool()
    bootstrap_pool.Add(text_format.Parse(BOOTSTRAP, descriptor_pb2.FileDescriptorProto()))
    schemas = message_class(bootstrap_pool, "enact_bootstrap.GraphInfoSchemas").FromString(got[2])
    pool = pool_from(schemas.descriptor_set)
    info = message_class(pool, GRAPH_TYPE).FromString(got[2])
    print(f"graph {info.graph}")
    for t in info.topics:
        print(f"  {t.name}  {t.type}  from {t.publisher}")

    # the topics asked for, decoded with the classes built from the schemas
    left = {topic: args.count for topic in args.topics}
    for topic in left:
        sub.subscribe(topic.encode())
    while any(left.values()):
        got = receive(sub, set(left), deadline)
        if got is None:
            sys.exit(f"timed out waiting for {[t for t, n in left.items() if n]}")
        topic, type_name, payload = got
        if left[topic] == 0:
            continue
        left[topic] -= 1
        msg = message_class(pool, type_name).FromString(payload)
        print(f"--- {topic} ({type_name}) seq {msg.header.seq} from {msg.header.source}")
        print(text_format.MessageToString(msg), end="")


if __name__ == "__main__":
    main()
