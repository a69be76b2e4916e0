#!/usr/bin/env python3
# requirements: cyclonedds==11.0.1 (as tests/peer/cyclone_bridge.py)
"""What an independent DDS participant (Eclipse Cyclone DDS, not RustDDS) sees of a ROS 2 node, the way
`ros2 node list`, `ros2 topic list -t` and `ros2 param get` find it:

- nodes from `ros_discovery_info` (rmw_dds_common/ParticipantEntitiesInfo: each participant's nodes
  with their namespaces and the GIDs of their readers and writers; Gid is uint8[16] since Iron);
- topics from DDS discovery (the DCPSPublication / DCPSSubscription built-in topics), mapped to the
  node through those GIDs, names and types turned back into ROS form (`rt/a/b` -> `/a/b`,
  `pkg::msg::dds_::T_` -> `pkg/msg/T`);
- parameters by calling the node's `list_parameters` and `get_parameters` services
  (rcl_interfaces), request and reply without a header in the payload (the request/reply mapping
  ros2-client's parameter services use, as rmw_fastrtps does).

usage (inside launch-free-scripts/netns-run):
  ros_graph.py --node /cell1/m1 [--domain-id N] [--timeout-s 20] [--min-nodes N]
  (--min-nodes: wait, within the timeout, until N nodes of the domain are known too)
Prints one JSON object: {"node": {...} or null, "nodes": [...], "publications": [...], "domain_publications": [...],
"subscriptions": [...], "participant_subscriptions": [...], "parameters": {name: value} or null, "parameter_types": {name: type}}.
"""
import argparse
import json
import os
import sys
import time
from dataclasses import dataclass

from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, BuiltinTopicDcpsSubscription
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, float64, int64, sequence, uint8, uint64
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration


@dataclass
class Gid(IdlStruct, typename="rmw_dds_common::msg::dds_::Gid_"):
    data: array[uint8, 16]


@dataclass
class NodeEntitiesInfo(IdlStruct, typename="rmw_dds_common::msg::dds_::NodeEntitiesInfo_"):
    node_namespace: str
    node_name: str
    reader_gid_seq: sequence[Gid]
    writer_gid_seq: sequence[Gid]


@dataclass
class ParticipantEntitiesInfo(IdlStruct, typename="rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_"):
    gid: Gid
    node_entities_info_seq: sequence[NodeEntitiesInfo]


@dataclass
class ParameterValue(IdlStruct, typename="rcl_interfaces::msg::dds_::ParameterValue_"):
    type: uint8
    bool_value: bool
    integer_value: int64
    double_value: float64
    string_value: str
    byte_array_value: sequence[uint8]
    bool_array_value: sequence[bool]
    integer_array_value: sequence[int64]
    double_array_value: sequence[float64]
    string_array_value: sequence[str]


@dataclass
class ListParametersRequest(IdlStruct, typename="rcl_interfaces::srv::dds_::ListParameters_Request_"):
    prefixes: sequence[str]
    depth: uint64


@dataclass
class ListParametersResult(IdlStruct, typename="rcl_interfaces::msg::dds_::ListParametersResult_"):
    names: sequence[str]
    prefixes: sequence[str]


@dataclass
class ListParametersResponse(IdlStruct, typename="rcl_interfaces::srv::dds_::ListParameters_Response_"):
    result: ListParametersResult


@dataclass
class GetParametersRequest(IdlStruct, typename="rcl_interfaces::srv::dds_::GetParameters_Request_"):
    names: sequence[str]


@dataclass
class GetParametersResponse(IdlStruct, typename="rcl_interfaces::srv::dds_::GetParameters_Response_"):
    values: sequence[ParameterValue]


TYPE_NAMES = {0: "not_set", 1: "bool", 2: "integer", 3: "double", 4: "string", 5: "byte_array",
              6: "bool_array", 7: "integer_array", 8: "double_array", 9: "string_array"}


def value_of(v):
    """A ParameterValue as a plain JSON value (None when not set)."""
    return {0: None, 1: v.bool_value, 2: v.integer_value, 3: v.double_value, 4: v.string_value,
            5: list(v.byte_array_value), 6: list(v.bool_array_value), 7: list(v.integer_array_value),
            8: list(v.double_array_value), 9: list(v.string_array_value)}.get(v.type)


def ros_topic(dds_name):
    for prefix in ("rt/", "rq/", "rr/"):
        if dds_name.startswith(prefix):
            return "/" + dds_name[len(prefix):]
    return dds_name


def ros_type(dds_type):
    # pkg::msg::dds_::T_ -> pkg/msg/T
    parts = dds_type.split("::")
    if len(parts) == 4 and parts[2] == "dds_" and parts[3].endswith("_"):
        return f"{parts[0]}/{parts[1]}/{parts[3][:-1]}"
    return dds_type


def call(dp, service, req_type, resp_type, request, timeout_s):
    """One service call, request and reply payloads without a header; the reply is the first sample
    that arrives on the reply topic after the request (one call at a time)."""
    qos = Qos(Policy.Reliability.Reliable(max_blocking_time=duration(seconds=1)), Policy.Durability.Volatile,
              Policy.History.KeepLast(10))
    base = service.lstrip("/")
    wt = Topic(dp, f"rq/{base}Request", req_type, qos=qos)
    rt = Topic(dp, f"rr/{base}Reply", resp_type, qos=qos)
    reader = DataReader(dp, rt, qos=qos)
    writer = DataWriter(dp, wt, qos=qos)
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        if writer.get_publication_matched_status().current_count > 0 and reader.get_subscription_matched_status().current_count > 0:
            break
        time.sleep(0.05)
    else:
        return None
    time.sleep(0.3)  # let the server's reply writer match our reader too
    writer.write(request)
    while time.monotonic() < end:
        for s in reader.take(N=10):
            return s
        time.sleep(0.02)
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--node", required=True, help="fully qualified node name, e.g. /cell1/m1")
    ap.add_argument("--domain-id", type=int, default=int(os.environ.get("ROS_DOMAIN_ID", "0") or 0))
    ap.add_argument("--timeout-s", type=float, default=20.0)
    ap.add_argument("--min-nodes", type=int, default=0)
    a = ap.parse_args()
    ns, _, name = a.node.rpartition("/")
    ns = ns or "/"
    dp = DomainParticipant(a.domain_id, qos=Qos(Policy.Userdata(data=b"enclave=/;")))
    info_qos = Qos(Policy.Reliability.Reliable(max_blocking_time=duration(seconds=1)), Policy.Durability.TransientLocal,
                   Policy.History.KeepLast(100))
    info = DataReader(dp, Topic(dp, "ros_discovery_info", ParticipantEntitiesInfo, qos=info_qos), qos=info_qos)
    pubs_r = BuiltinDataReader(dp, BuiltinTopicDcpsPublication)
    subs_r = BuiltinDataReader(dp, BuiltinTopicDcpsSubscription)
    nodes, pubs, subs = {}, {}, {}
    end = time.monotonic() + a.timeout_s
    node = None
    while time.monotonic() < end:
        for s in info.take(N=100):
            for n in s.node_entities_info_seq:
                nodes[(n.node_namespace, n.node_name)] = {
                    "namespace": n.node_namespace, "name": n.node_name,
                    "writers": [bytes(g.data).hex() for g in n.writer_gid_seq],
                    "readers": [bytes(g.data).hex() for g in n.reader_gid_seq]}
        for s in pubs_r.take(N=100):
            pubs[s.key.bytes.hex()] = {"topic": ros_topic(s.topic_name), "type": ros_type(s.type_name)}
        for s in subs_r.take(N=100):
            subs[s.key.bytes.hex()] = {"topic": ros_topic(s.topic_name), "type": ros_type(s.type_name)}
        node = nodes.get((ns, name))
        # Seen once the node and every one of its writers is known from discovery.
        if node and node["writers"] and all(w in pubs for w in node["writers"]) and len(nodes) >= a.min_nodes:
            time.sleep(0.5)
            break
        time.sleep(0.1)
    out = {"node": None, "nodes": sorted(f"{k[0].rstrip('/')}/{k[1]}" for k in nodes), "publications": [], "subscriptions": [],
           "parameters": None, "parameter_types": None,
           # Every topic any participant of the domain writes (the fleet test: what a cell's domain holds).
           "domain_publications": sorted({p["topic"] for p in pubs.values()})}
    if node:
        for s in pubs_r.take(N=100):
            pubs[s.key.bytes.hex()] = {"topic": ros_topic(s.topic_name), "type": ros_type(s.type_name)}
        for s in subs_r.take(N=100):
            subs[s.key.bytes.hex()] = {"topic": ros_topic(s.topic_name), "type": ros_type(s.type_name)}
        out["node"] = {"namespace": node["namespace"], "name": node["name"]}
        out["publications"] = sorted({(p["topic"], p["type"]) for w in node["writers"] if (p := pubs.get(w))})
        out["subscriptions"] = sorted({(p["topic"], p["type"]) for r in node["readers"] if (p := subs.get(r))})
        # Every reader of the node's participant (GUID prefix: the first 12 bytes), listed in the
        # node's entry or not (the recorder's raw readers are not).
        prefix = node["writers"][0][:24]
        out["participant_subscriptions"] = sorted({(p["topic"], p["type"]) for k, p in subs.items() if k.startswith(prefix)})
        left = max(1.0, end - time.monotonic())
        listed = call(dp, f"{a.node}/list_parameters", ListParametersRequest, ListParametersResponse,
                      ListParametersRequest(prefixes=[], depth=0), left)
        if listed is not None:
            names = list(listed.result.names)
            got = call(dp, f"{a.node}/get_parameters", GetParametersRequest, GetParametersResponse,
                       GetParametersRequest(names=names), max(1.0, end - time.monotonic()))
            if got is not None and len(got.values) == len(names):
                out["parameters"] = {n: value_of(v) for n, v in zip(names, got.values)}
                out["parameter_types"] = {n: TYPE_NAMES.get(v.type, str(v.type)) for n, v in zip(names, got.values)}
    json.dump(out, sys.stdout)
    print()


if __name__ == "__main__":
    main()
