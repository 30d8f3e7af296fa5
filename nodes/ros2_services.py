"""Calling a ROS 2 service over DDS, as a ROS 2 client does: the request written on the service's
``rq/<name>Request`` topic, the answer read on ``rr/<name>Reply`` (``ros2_requests`` names them and
holds the service types; this module is the DDS side).

What a Fast DDS server (the pip-installed rclpy wheels) needs and gives, measured:

* both topics reliable, volatile (``ros2_dds.RELIABLE``), the types keyless final XCDR1 structs
  named ``<package>::srv::dds_::<Name>_Request_`` / ``_Response_``;
* the payload carries no request header: Fast DDS puts the request's identity in RTPS metadata
  (the reply's related-sample-identity), which the Python binding neither writes nor reads.  So a
  reply is matched to its call by having one call in flight, and a reply the server sends another
  client of the same service at that moment would be taken for ours;
* matching is per side: the call waits for the request writer's and the reply reader's own match,
  and for a sign that the server's reply writer matched the reply reader too (its participant's
  ``ros_discovery_info``), before writing, or the reply can be lost;
* the reply reader is best effort: a reliable Cyclone reader that matched a Fast DDS writer late
  holds a reply numbered after the writer's earlier replies (to other clients) until a heartbeat
  says where to start, seconds later or never (measured: 1 of 10 fresh processes got its reply);
  best effort takes it as it comes, and on loopback nothing is lost (measured: 8 of 8);
* the participant is deleted when the call ends, so its peers drop it at once rather than when its
  lease ends.

Importing this module loads the Cyclone DDS C library (~0.35 s): the command imports it when it runs.
"""

import time
from dataclasses import dataclass
from functools import cache
from typing import Any

import cyclonedds.idl.types as t
from cyclonedds.core import DDSException
from cyclonedds.idl import IdlMeta, IdlStruct
from cyclonedds.idl.annotations import final
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy, Qos
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from turtlectl.nodes import ros2_dds
from turtlectl.nodes import ros2_requests as rq
from turtlectl.nodes.ros2_dds import GRAPH
from turtlectl.nodes.ros2_types import XCDR1, ParticipantEntitiesInfo

#: the cyclonedds type of each .srv field type
IDL_TYPES: dict[str, Any] = {
    "bool": bool,
    "string": str,
    "float32": t.float32,
    "float64": t.float64,
    "byte": t.uint8,
    "char": t.uint8,
    "uint8": t.uint8,
    "int8": t.int8,
    "uint16": t.uint16,
    "int16": t.int16,
    "uint32": t.uint32,
    "int32": t.int32,
    "uint64": t.uint64,
    "int64": t.int64,
}

GRAPH_TOPIC = "ros_discovery_info"  # each ROS 2 participant's nodes (rmw_dds_common), transient local
MATCH_POLL = 0.005  # s between looks at the match counts while waiting for a server


class NoServer(TimeoutError):
    """No server of the service matched within the timeout."""


class NoReply(TimeoutError):
    """A server matched but no reply came within the timeout."""


def _struct(ros_type: str, side: str, typename: str, fields: rq.Fields) -> type[IdlStruct]:
    """A keyless final struct named ``typename``, its fields at ROS's defaults (as ``ros2_types``'
    classes, written out: ``@dataclass @final class ...(IdlStruct, typename=...)``)."""
    name = ros_type.rsplit("/", 1)[1] + "_" + side
    namespace = IdlMeta.__prepare__(name, (IdlStruct,), typename=typename)
    for field, kind in rq.wire_fields(fields):
        namespace["__annotations__"][field] = IDL_TYPES[kind]
        namespace[field] = rq.default(kind)
    return dataclass(final(IdlMeta(name, (IdlStruct,), namespace, typename=typename)))


@cache
def idl_types(ros_type: str) -> tuple[type[IdlStruct], type[IdlStruct]]:
    """The request and response structs of ``ros_type`` (``std_srvs/srv/SetBool``) with the DDS names
    Fast DDS matches; ValueError if the type is not in ``ros2_requests.SERVICE_TYPES``."""
    request, response = rq.check_service_type(ros_type)
    return (
        _struct(ros_type, "Request", rq.request_type_name(ros_type), request),
        _struct(ros_type, "Response", rq.response_type_name(ros_type), response),
    )


def _server_ready(writer: DataWriter, reader: DataReader, graph: DataReader, seen: set[bytes]) -> bool:
    """Whether a server can answer: the request writer and the reply reader matched (as this side
    sees it), and the server's own reply writer matched the reply reader too.  That last one this side
    cannot see, and a reply written before it is lost (measured: most calls of a fresh process lose
    their reply when they write at their own match).  Its sign: the server's participant's
    ``ros_discovery_info`` sample (transient local) has reached ``graph``, whose discovery this
    participant sent after the reply reader's, in order, on the same reliable stream.  ``seen``:
    the GUID prefixes of the participants whose sample came."""
    seen.update(bytes(sample.gid.data[:12]) for sample in graph.take(N=16))
    if writer.get_publication_matched_status().current_count == 0:
        return False
    if reader.get_subscription_matched_status().current_count == 0:
        return False
    servers = {
        reader.get_matched_publication_data(h).participant_key.bytes[:12] for h in reader.get_matched_publications()
    }
    return bool(servers & seen)


def _fields(sample: IdlStruct, fields: rq.Fields) -> dict[str, Any]:
    return {name: getattr(sample, name) for name, _ in fields}


def call(service: str, ros_type: str, request: dict[str, Any], timeout: float, domain_id: int) -> dict[str, Any]:
    """Call the ROS service ``service`` of type ``ros_type`` with ``request`` (its fields, as
    ``ros2_requests.fit_request`` gives them) on ROS domain ``domain_id``; the response's fields.

    ``timeout`` (s) bounds the whole call: NoServer if no server matched in it, NoReply if one did
    but sent no reply.  ValueError on a service name or type that cannot be used."""
    deadline = time.monotonic() + timeout
    request_type, response_type = idl_types(ros_type)
    _, response_fields = rq.check_service_type(ros_type)
    request_topic, reply_topic = rq.service_topics(service)
    participant = ros2_dds.participant(domain_id)
    try:
        qos = ros2_dds.RELIABLE
        # created in this order: the reply reader's discovery reaches the server before the graph reader's
        reply_qos = Qos(Policy.Reliability.BestEffort, Policy.Durability.Volatile, Policy.History.KeepLast(10), XCDR1)
        reader = DataReader(participant, Topic(participant, reply_topic, response_type, qos=qos), qos=reply_qos)
        graph = DataReader(participant, Topic(participant, GRAPH_TOPIC, ParticipantEntitiesInfo, qos=GRAPH), qos=GRAPH)
        writer = DataWriter(participant, Topic(participant, request_topic, request_type, qos=qos), qos=qos)
        seen: set[bytes] = set()
        while not _server_ready(writer, reader, graph, seen):
            if time.monotonic() >= deadline:
                raise NoServer(f"no server of {service} ({ros_type}) within {timeout:g} s")
            time.sleep(MATCH_POLL)
        writer.write(request_type(**request))
        left = max(deadline - time.monotonic(), 0.001)
        try:
            reply = reader.take_one(timeout=duration(seconds=left))
        except (StopIteration, TimeoutError, DDSException):
            raise NoReply(f"{service} ({ros_type}) sent no reply within {timeout:g} s") from None
        return _fields(reply, response_fields)
    finally:
        # deleted, not left to the interpreter's exit: its peers hear it leave at once
        participant.__del__()
