#!/usr/bin/python3
"""Attach to a running enact graph and print what it carries.

    attach_example.py [--graph NAME | --attach ENDPOINT] [TOPIC ...] [--count N] [--timeout S]
                      [--key FILE.key --server-key FILE.pub]

Finds the graph like every enact tool (docs/concepts.md, "Graphs by name"): --graph NAME in this
user's registry of running graphs, --attach ENDPOINT as printed by the graph (e.g.
tcp://127.0.0.1:40123; a first positional argument with "://" is taken as one too), or the
only graph running (several: they are listed, exit 2; none: it waits for one). It prints
the graph and endpoint it attached to, connects a SUB socket there, reads one GraphInfo from "graph/topics" to list the topics and load every message schema,
then prints N messages of each TOPIC given, decoded from those schemas alone: no .proto
files, no generated code. For a graph launched with --access, --key (your secret key) and
--server-key (the graph's public key) make the connection a CURVE client's (files made by
`enact keys new`). Needs python3-zmq and python3-protobuf (Debian).
Wire format and protocol: core/bus/README.md.
"""
import argparse
import glob
import os
import sys
import tempfile
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


def registry_dir():
    """The registry of running graphs (core/session/registry.h): one small YAML file each."""
    return os.environ.get("ENACT_REGISTRY") or os.path.join(tempfile.gettempdir(), f"enact-{os.getuid()}", "graphs")


def process_start(pid):
    """The start time of process `pid` (/proc/PID/stat field 22), 0 when there is none."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            stat = f.read()
    except OSError:
        return 0
    return int(stat[stat.rindex(")") + 2:].split()[19])


def running_graphs():
    """The entries of the running graphs (those of dead processes are left out)."""
    graphs = []
    for path in sorted(glob.glob(os.path.join(registry_dir(), "*.yaml"))):
        entry = {}
        with open(path) as f:
            for line in f:
                key, _, value = line.rstrip("\n").partition(": ")
                entry[key] = value.strip('"')
        if entry.get("pid") and process_start(int(entry["pid"])) == int(entry.get("pid_start", -1)):
            graphs.append(entry)
    return graphs


def find_graph(name, timeout):
    """The endpoint of graph `name`, or of the only graph running; waits for it until timeout."""
    deadline = time.monotonic() + timeout
    said = False
    while True:
        graphs = [g for g in running_graphs() if not name or g["name"] == name]
        if len(graphs) == 1:
            return graphs[0]["name"], graphs[0]["endpoint"]
        if len(graphs) > 1:
            listing = "".join(f"\n  {g['name']}  {g['endpoint']}" for g in graphs)
            print(f"several graphs run; name one with --graph NAME:{listing}", file=sys.stderr)
            sys.exit(2)
        if not said:
            print(f"waiting for {'graph ' + name if name else 'a graph'} to start", file=sys.stderr)
            said = True
        if time.monotonic() >= deadline:
            sys.exit(f"no {'graph ' + name if name else 'graph'} started within {timeout} s")
        time.sleep(0.2)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("topics", nargs="*", help="topics to print (default: only list them)")
    parser.add_argument("--graph", help="the running graph's name (enact graph list)")
    parser.add_argument("--attach", help="an attach endpoint, e.g. tcp://127.0.0.1:40123")
    parser.add_argument("--count", type=int, default=5, help="messages to print per topic (default 5)")
    parser.add_argument("--timeout", type=float, default=10.0, help="give up after this many seconds")
    parser.add_argument("--key", help="your secret key (FILE.key), for a graph launched with --access")
    parser.add_argument("--server-key", help="the graph's public key (FILE.pub)")
    args = parser.parse_args()
    if (args.key is None) != (args.server_key is None):
        parser.error("give both --key and --server-key, or neither")
    if not args.attach and args.topics and "://" in args.topics[0]:
        args.attach = args.topics.pop(0)
    if args.graph and args.attach:
        parser.error("give --graph or --attach, not both")
    name, endpoint = ("(given)", args.attach) if args.attach else find_graph(args.graph, args.timeout)
    print(f"attached to graph {name} at {endpoint}", file=sys.stderr)
    args.endpoint = endpoint
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
