"""The bridge's DDS side: one Cyclone DDS participant (nodes.ros2_dds), a writer or reader per ROS 2
topic of the table, and the ``ros_discovery_info`` sample that names the nodes it holds in ROS 2's
graph.  Samples that arrive are handed, on Cyclone's thread, to ``deliver`` (the node's queue): the
bridge's logic runs on its node's thread only.

Importing this module loads the Cyclone DDS C library: only the bridge imports it, when it starts.
"""

# no `from __future__ import annotations`: cyclonedds resolves annotations at run time (ros2_types)

import logging
from collections.abc import Callable
from typing import Any

from cyclonedds.core import Listener, Policy, Qos
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from turtlectl.nodes import ros2_dds, ros2_types
from turtlectl.nodes.ros2_types import Gid, NodeEntitiesInfo, ParticipantEntitiesInfo

DISCOVERY_TOPIC = "ros_discovery_info"  # rmw_dds_common's: no rt/ prefix
TAKE = 64  # samples taken per wake-up at most


def gid(entity: Any) -> Gid:
    """The rmw gid of a DDS entity: its 16-byte GUID."""
    return Gid(data=list(entity.get_guid().bytes))


def ros_name(ros_type: type) -> str:
    """A DDS type's ROS 2 name: ``std_msgs::msg::dds_::String_`` -> ``std_msgs/msg/String``."""
    package, kind, _dds, name = ros_type.__idl_typename__.split("::")
    return f"{package}/{kind}/{name.rstrip('_')}"


def ros_node_name(name: str) -> tuple[str, str]:
    """A turtlectl node name as ROS 2's (namespace, name): ``turtle2/navigator`` -> (``/turtle2``,
    ``navigator``); characters ROS names do not allow become ``_``."""
    *space, last = name.split("/")

    def clean(part: str) -> str:
        text = "".join(c if c.isalnum() or c == "_" else "_" for c in part) or "_"
        return "_" + text if text[0].isdigit() else text

    return "/" + "/".join(clean(p) for p in space), clean(last)


class Out:
    """A DDS writer and how many readers it has matched (kept by Cyclone's listener thread: an int
    swapped whole, read by the bridge's thread)."""

    def __init__(self) -> None:
        self.writer: DataWriter | None = None
        self.readers = 0

    def on_matched(self, _writer: DataWriter, status: Any) -> None:  # Cyclone's thread
        self.readers = status.current_count

    def write(self, sample: Any) -> None:
        assert self.writer is not None
        self.writer.write(sample)


class DdsLink:
    """The participant and its entities.  ``deliver(fn, *args)`` runs ``fn(*args)`` on the bridge's
    thread (``Node.core.enqueue``)."""

    def __init__(self, domain_id: int, address: str, node_name: str, deliver: Callable[..., None], log: logging.Logger):
        self.log = log
        self.deliver = deliver
        self.participant = ros2_dds.participant(domain_id, address)
        self.me = ros_node_name(node_name)
        self.readers: list[DataReader] = []
        self.writers: list[DataWriter] = []
        self._topics: dict[str, Topic] = {}
        self._others: dict[tuple[str, str], tuple[tuple[str, ...], tuple[str, ...]]] = {}
        self._by_topic: dict[str, list[Any]] = {}  # ROS topic -> the bridge's writers and readers on it
        self._info = DataWriter(
            self.participant, self._topic(DISCOVERY_TOPIC, ParticipantEntitiesInfo, ros2_dds.GRAPH), qos=ros2_dds.GRAPH
        )
        self._heard = DataReader(
            self.participant,
            self._topic(DISCOVERY_TOPIC, ParticipantEntitiesInfo, ros2_dds.GRAPH),
            qos=ros2_dds.GRAPH,
            listener=Listener(on_data_available=self._on_discovery),
        )
        self._gid = gid(self.participant)
        self.on_other_bridge: Callable[[str], None] = lambda _name: None

    def _topic(self, name: str, cls: type, qos: Qos) -> Topic:
        if name not in self._topics:
            self._topics[name] = Topic(self.participant, name, cls, qos=qos)
        return self._topics[name]

    @staticmethod
    def qos(name: str, local_ignored: bool = False) -> Qos:
        base = {"sensor": ros2_dds.SENSOR, "latched": ros2_dds.LATCHED}.get(name, ros2_dds.RELIABLE)
        return Qos(*base, Policy.IgnoreLocal.Participant) if local_ignored else base

    def writer(self, ros_topic: str, ros_type: type, qos: str) -> "Out":
        """A writer of ``ros_type`` on ROS 2 topic ``ros_topic`` (``Out``: it knows whether any reader
        matched, so that the bridge converts nothing nobody reads)."""
        q = self.qos(qos)
        out = Out()
        w = DataWriter(
            self.participant,
            self._topic(ros2_types.dds_topic(ros_topic), ros_type, q),
            qos=q,
            listener=Listener(on_publication_matched=out.on_matched),
        )
        out.writer = w
        self.writers.append(w)
        self._by_topic.setdefault(ros_topic, []).append(w)
        self.announce()
        return out

    def reader(self, ros_topic: str, ros_type: type, qos: str, on_sample: Callable[[Any], None]) -> DataReader:
        """A reader of ``ros_type`` on ``ros_topic``: ``on_sample(msg)`` on the bridge's thread for each
        one another participant wrote (the bridge's own writers are ignored); one that does not
        decode is logged (once a topic) and dropped."""
        q = self.qos(qos, local_ignored=True)
        topic = self._topic(ros2_types.dds_topic(ros_topic), ros_type, self.qos(qos))
        warned: list[bool] = []

        def on_data(reader: DataReader) -> None:  # Cyclone's thread: take, hand over
            try:
                samples = reader.take(N=TAKE)
            except Exception as exc:  # a sample that does not decode as ros_type
                if not warned:
                    warned.append(True)
                    self.log.warning(
                        "a ROS message on %s did not decode as %s (%s); dropped, still bridging",
                        ros_topic,
                        ros_name(ros_type),
                        exc,
                    )
                return
            for sample in samples:
                if isinstance(sample, ros_type):
                    self.deliver(on_sample, sample)

        r = DataReader(self.participant, topic, qos=q, listener=Listener(on_data_available=on_data))
        self.readers.append(r)
        self._by_topic.setdefault(ros_topic, []).append(r)
        self.announce()
        return r

    def set_nodes(self, nodes: dict[str, tuple[tuple[str, ...], tuple[str, ...]]]) -> None:
        """The other nodes of the system to list in ROS 2's graph: turtlectl name -> (the ROS topics
        the bridge writes for what it publishes, those it reads for what it subscribes to)."""
        others = {ros_node_name(n): topics for n, topics in nodes.items() if ros_node_name(n) != self.me}
        if others != self._others:
            self._others = others
            self.announce()

    def _gids(self, topics: tuple[str, ...], kind: type) -> list[Gid]:
        return [gid(e) for t in topics for e in self._by_topic.get(t, ()) if isinstance(e, kind)]

    def announce(self) -> None:
        """Write ``ros_discovery_info``: this node with its readers and writers, and the system's others."""
        mine = NodeEntitiesInfo(
            node_namespace=self.me[0],
            node_name=self.me[1],
            reader_gid_seq=[gid(r) for r in self.readers],
            writer_gid_seq=[gid(w) for w in self.writers],
        )
        rest = [
            NodeEntitiesInfo(
                node_namespace=ns,
                node_name=name,
                reader_gid_seq=self._gids(read, DataReader),
                writer_gid_seq=self._gids(written, DataWriter),
            )
            for (ns, name), (written, read) in sorted(self._others.items())
        ]
        self._info.write(ParticipantEntitiesInfo(gid=self._gid, node_entities_info_seq=[mine, *rest]))

    def _on_discovery(self, reader: DataReader) -> None:  # Cyclone's thread
        try:
            samples = reader.take(N=TAKE)
        except Exception:
            return
        for info in samples:
            if not isinstance(info, ParticipantEntitiesInfo) or list(info.gid.data) == list(self._gid.data):
                continue
            for node in info.node_entities_info_seq:
                if (node.node_namespace, node.node_name) == self.me:
                    self.deliver(self.on_other_bridge, bytes(info.gid.data[:12]).hex())

    def close(self) -> None:
        """Leave the ROS 2 graph (the participant and every entity go)."""
        self.readers.clear()
        self.writers.clear()
        self.participant = None  # cyclonedds deletes the entities with their last reference
