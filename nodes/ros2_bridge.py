"""The ROS 2 bridge process (``run = "ros2_bridge"``, or ``turtlectl ros2 bridge``): puts a running
system into a ROS 2 graph over DDS, row by row of its table (nodes.ros2_table).

* turtlectl -> ROS: one subscription per key; each message converted (nodes.ros2_mapping.TO_ROS) and
  written on its ROS 2 topic.  A topic's DDS writer is made with its first message, so a key nobody
  publishes (``clock`` without simulated time) never shows in ROS's graph.  A row of a user's own flat
  type crosses field for field (nodes.ros2_dynamic), both ways.
* ROS -> turtlectl: one DDS reader per ROS topic (nodes.ros2_link; the bridge's own DDS writers are
  ignored); each sample converted (FROM_ROS) and published on the key.  On a key that also crosses to
  ROS (``cmd_vel``), what the bridge published itself is not sent back (ros2_table.OwnEcho).
* The default table follows the turtles the simulator reports (``turtles``): a spawned turtle is
  bridged when it appears.
* The system's nodes (their presence tokens) and the bridge itself are listed in ROS's graph
  (``ros_discovery_info``); another bridge of the same name on the ROS domain is reported once.

The DDS side (Eclipse Cyclone DDS, the ``ros2`` extra) is imported when the node starts, never when
this module is (the zygote imports it): without the extra, the node says how to install it and exits
with code 4 (cannot start).
"""

from __future__ import annotations

from typing import Any

from turtlectl.messages import Ack, String, Turtles
from turtlectl.messages.keys import GRAPH, ROS2_BRIDGE, TURTLES, parse_entity_token, parse_node_token
from turtlectl.nodes.params import ROS2_BRIDGE_CLAIMS, ROS2_BRIDGE_INTERFACE, Ros2BridgeParams
from turtlectl.nodes.ros2_table import SYSTEM_ENTRIES, BridgeTopic, OwnEcho, turtle_entries, turtle_of_key
from turtlectl.runtime import Node, Request, run_main
from turtlectl.runtime.client.errors import BadInput, CannotStart

INSTALL_HINT = "pip install 'turtlectl[ros2]'"
PRESENCE_PERIOD = 2.0  # s: how often the nodes' presence tokens are asked for again


def graph_nodes(tokens: set[str], rows: list[BridgeTopic]) -> dict[str, tuple[tuple[str, ...], tuple[str, ...]]]:
    """The system's nodes as ROS's graph shows them, from their presence and entity tokens: name ->
    (the ROS topics the bridge writes for a key the node publishes, those it reads for a key the
    node subscribes to), so ``ros2 node info /sim`` lists ``/turtle1/pose``."""
    nodes: dict[str, tuple[list[str], list[str]]] = {}
    entities = []
    for key in tokens:
        info = parse_node_token(key)
        if info is not None:
            nodes.setdefault(info.name, ([], []))
        entity = parse_entity_token(key)
        if entity is not None:
            entities.append(entity)
    for entity in entities:
        if entity.node not in nodes or entity.role not in ("pub", "sub"):
            continue
        written, read = nodes[entity.node]
        for row in rows:
            if row.key.lstrip("/") != entity.key:
                continue
            if entity.role == "pub" and row.to_ros:
                written.append(row.ros)
            if entity.role == "sub" and row.from_ros:
                read.append(row.ros)
    return {name: (tuple(sorted(set(w))), tuple(sorted(set(r)))) for name, (w, r) in nodes.items()}


class MissingExtra(CannotStart):
    """The DDS side is not installed (exit code 4)."""


def open_link(node: Node[Ros2BridgeParams]) -> Any:
    """The bridge's DDS side (nodes.ros2_link.DdsLink) on its ROS domain: MissingExtra without
    Cyclone DDS, BadInput for a ``ROS_DOMAIN_ID`` that is no domain."""
    try:
        from turtlectl.nodes import ros2_dds
        from turtlectl.nodes.ros2_link import DdsLink
    except ImportError as exc:
        raise MissingExtra(
            f"the ROS 2 bridge needs Eclipse Cyclone DDS, not installed here ({exc.name}): {INSTALL_HINT}"
        ) from None
    p = node.params
    try:
        domain = ros2_dds.ros_domain_id() if p.ros_domain < 0 else p.ros_domain
    except ValueError as exc:
        raise BadInput(str(exc)) from None
    return DdsLink(domain, p.address, node.name, node.core.enqueue, node.log), domain


class Ros2Bridge:
    Params = Ros2BridgeParams
    Claims = ROS2_BRIDGE_CLAIMS
    Interface = ROS2_BRIDGE_INTERFACE

    def __init__(self, node: Node[Ros2BridgeParams]):
        self.node = node
        self.link, self.domain = open_link(node)  # first: without Cyclone DDS, one line and exit 4
        from turtlectl.nodes import ros2_mapping

        self.mapping = ros2_mapping
        self.link.on_other_bridge = self.on_other_bridge
        self.warned_other = False
        self.rows: list[BridgeTopic] = []
        self.outgoing: dict[str, list[tuple[BridgeTopic, list[Any]]]] = {}  # key -> rows, each its writer (made lazily)
        self.publishers: dict[str, Any] = {}  # key -> turtlectl publisher of what comes from ROS
        self.echo: dict[str, OwnEcho] = {}
        self.turtles: list[str] = []
        self.tokens: set[str] = set()  # the presence tokens of the system's nodes alive now
        for row in node.params.topics:
            self.add(row)
        if node.params.defaults:
            for row in SYSTEM_ENTRIES:
                self.add(row)
            node.subscribe(f"/{TURTLES}", Turtles, self.on_turtles)
        node.serve(f"/{ROS2_BRIDGE}", String, Ack, self.on_asked)  # its claim: the system's only bridge
        node.watch_liveliness(GRAPH, self.on_presence)  # the nodes and what each publishes and subscribes to
        # and the nodes there already: a watch sees only what changes once it reached the router, so the
        # tokens are asked for now and every PRESENCE_PERIOD (a start before the router answered misses none)
        self.ask_presence()
        node.timer(PRESENCE_PERIOD, self.ask_presence)
        node.on_shutdown(self.link.close)
        node.log.info(
            "bridging to ROS 2 domain %d on %s (%d rows so far)", self.domain, node.params.address, len(self.rows)
        )

    # -- the table --------------------------------------------------------------------------
    def add(self, row: BridgeTopic) -> None:
        """Bridge one row (once: the same row again is ignored)."""
        if row in self.rows:
            return
        if row.to_ros and row.key in self.outgoing:
            first = self.outgoing[row.key][0][0]
            if first.message_type != row.message_type:
                self.node.log.warning(
                    "%s -> %s not bridged: %s is already bridged as %s (to %s), one type a key",
                    row.key,
                    row.ros,
                    row.key,
                    first.message_type,
                    first.ros,
                )
                return
        self.rows.append(row)
        if row.to_ros:
            msg_type = self.mapping.to_ros_of(row.type)[0]
            rows = self.outgoing.get(row.key)
            if rows is None:
                rows = self.outgoing[row.key] = []
                self.node.subscribe(row.key, msg_type, lambda msg, key=row.key: self.to_ros(key, msg))
            rows.append((row, []))
        if row.from_ros:
            ros_type, msg_type, _convert = self.mapping.from_ros_of(row.type)
            if row.key not in self.publishers:
                self.publishers[row.key] = self.node.publisher(row.key, msg_type)
                self.echo[row.key] = OwnEcho()
            self.link.reader(row.ros, ros_type, row.qos, lambda sample, r=row: self.from_ros(r, sample))

    def on_turtles(self, msg: Turtles) -> None:
        """Bridge each new turtle's default rows (the ``turtles`` parameter's, if it lists some)."""
        listed = self.node.params.turtles
        for turtle in msg.names:
            if turtle not in self.turtles and (not listed or turtle in listed):
                self.turtles.append(turtle)
                for row in turtle_entries(turtle):
                    self.add(row)
                self.node.log.info("bridging %s", turtle)

    # -- the two ways -----------------------------------------------------------------------
    def to_ros(self, key: str, msg: Any) -> None:
        echo = self.echo.get(key)
        if echo is not None and echo.is_own(msg):
            return  # the bridge published it, from ROS: it is there already
        for row, writer in self.outgoing[key]:
            if not writer:  # made with the key's first message (and it shows in ROS's graph then)
                writer.append(self.link.writer(row.ros, self.mapping.to_ros_of(row.type)[1], row.qos))
            # nothing converted for a topic no ROS node reads, but for a latched one (/rosout), whose
            # history a reader that comes later is given
            if writer[0].readers or row.qos == "latched":
                writer[0].write(self.mapping.to_ros_of(row.type)[2](msg, turtle_of_key(row.key)))

    def from_ros(self, row: BridgeTopic, sample: Any) -> None:
        convert = self.mapping.from_ros_of(row.type)[2]
        try:
            msg = convert(sample, self.node.now_ns())
        except (ValueError, TypeError, OverflowError) as exc:  # msgspec.ValidationError is a ValueError
            self.node.log.warning("a ROS message on %s could not be converted (%s); dropped", row.ros, exc)
            return
        stamped = self.publishers[row.key].publish(msg)
        if row.key in self.outgoing:
            self.echo[row.key].sent(stamped)

    # -- the graph --------------------------------------------------------------------------
    def ask_presence(self) -> None:
        """Ask the router for the nodes' presence tokens; each reply is one alive (on Zenoh's thread: queued)."""
        enqueue = self.node.core.enqueue

        def on_reply(reply: Any) -> None:
            if reply.ok is not None:
                enqueue(self.on_presence, str(reply.ok.key_expr), True)

        self.node.session.liveliness().get(GRAPH, handler=on_reply)

    def on_presence(self, key: str, alive: bool) -> None:
        if alive == (key in self.tokens):
            return  # known already (asked again), or gone already
        if alive:
            self.tokens.add(key)
        else:
            self.tokens.discard(key)
        self.link.set_nodes(graph_nodes(self.tokens, self.rows))

    def on_asked(self, request: Request[String]) -> None:
        request.respond(Ack(detail=f"{self.node.name} bridges ROS 2 domain {self.domain}: {len(self.rows)} topics"))

    def on_other_bridge(self, participant: str) -> None:
        if not self.warned_other:
            self.warned_other = True
            self.node.log.warning(
                "another bridge named %s is on ROS 2 domain %d (participant %s): each topic it shares with this "
                "one crosses twice; stop one, or give it another name or ros_domain",
                self.node.name,
                self.domain,
                participant,
            )


def main() -> None:
    run_main(Ros2Bridge, Ros2BridgeParams)


if __name__ == "__main__":
    main()
