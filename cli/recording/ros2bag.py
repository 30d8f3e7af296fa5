"""Recordings in rosbag2's MCAP profile (``record --profile ros2``), and reading them back: the one
module that uses ``rosbags`` (the ``ros2`` extra), imported only when a ROS 2 bag is written or read.

A bag is what rosbag2 writes: a folder holding ``<folder name>.mcap`` and ``metadata.yaml``.  The MCAP
file has profile ``ros2``; each ROS type a schema of encoding ``ros2msg`` holding its full ``.msg``
text (its dependencies after ``====`` separator lines, as rosbag2 writes it); each topic a channel of
encoding ``cdr`` with the ``offered_qos_profiles`` of its ROS publisher.  Topics are the keys as ROS
names (``/turtle1/pose``), types the ROS 2 types of turtlectl.nodes.ros2_profile, fields as
turtlectl.nodes.ros2_fields converts them; a user's own flat type is its generic ROS type
(turtlectl.nodes.ros2_generic).  A message of any other type (a built-in the table does not map, a
service's request, a nested user type) is left out, said once per topic.  No Zenoh here.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from turtlectl.cli.recording.bag import RecordingError, refuse_existing
from turtlectl.messages import DecodeError, Message, decode, type_from_encoding
from turtlectl.messages.codec import type_name
from turtlectl.nodes import ros2_fields, ros2_profile
from turtlectl.nodes.ros2_msgdefs import OWN
from turtlectl.runtime.client.errors import BadInput, CannotStart

PROFILE = "ros2"  # the command line's --profile value, and the MCAP profile
INSTALL = "pip install 'turtlectl[ros2]'"


def require() -> None:
    """CannotStart (exit 4), with how to install it, if the rosbags library is missing: said before
    anything starts."""
    try:
        import rosbags.rosbag2  # noqa: F401
        import rosbags.typesys  # noqa: F401
    except ImportError:
        raise CannotStart(f"ROS 2 bags need the ros2 extra (the rosbags library): {INSTALL}") from None


def typestore() -> Any:
    """rosbags' typestore for ROS 2 Kilted, with turtlectl's own ROS types (turtlesim/msg/Pose, the
    capstone's TurtleStatus) added from their .msg text.  CannotStart (exit 4) without rosbags."""
    try:
        from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    except ImportError:
        raise CannotStart(f"ROS 2 bags need the ros2 extra (the rosbags library): {INSTALL}") from None
    store = get_typestore(Stores.ROS2_KILTED)
    for name, text in OWN.items():
        if name not in store.types:
            store.register(get_types_from_msg(text, name))
    return store


def build(store: Any, ros_type: str, fields: dict) -> Any:
    """A rosbags message of ``ros_type`` from nested dicts of its fields (ros2_fields.to_ros); a field
    not given is zero, empty or a zero message."""
    import numpy as np
    from rosbags.interfaces import Nodetype

    def value(desc: tuple, given: Any) -> Any:
        kind, arg = desc
        if kind == Nodetype.NAME:
            return build(store, arg, given or {})
        if kind == Nodetype.BASE:
            base = arg[0]
            if given is not None:
                return given
            return "" if base == "string" else False if base == "bool" else 0.0 if "float" in base else 0
        inner, length = arg  # an array or a sequence
        items = list(given or [])
        if kind == Nodetype.ARRAY and not items:
            items = [value(inner, None) for _ in range(length)]
        if inner[0] == Nodetype.BASE and inner[1][0] not in ("string", "bool"):
            return np.array(items, dtype=np.dtype(_NUMPY[inner[1][0]]))
        return [value(inner, item) for item in items]

    _consts, defs = store.fielddefs[ros_type]
    cls = store.types[ros_type]
    return cls(**{name: value(desc, fields.get(name)) for name, desc in defs})


_NUMPY = {
    "float32": "float32",
    "float64": "float64",
    "int8": "int8",
    "uint8": "uint8",
    "byte": "uint8",
    "char": "uint8",
    "int16": "int16",
    "uint16": "uint16",
    "int32": "int32",
    "uint32": "uint32",
    "int64": "int64",
    "uint64": "uint64",
}


def _qos(q: ros2_profile.Qos) -> Any:
    from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime

    never = QosTime(sec=0, nsec=0)
    return Qos(
        history=QosHistory.KEEP_LAST,
        depth=q.depth,
        reliability=QosReliability.RELIABLE if q.reliable else QosReliability.BEST_EFFORT,
        durability=QosDurability.TRANSIENT_LOCAL if q.transient_local else QosDurability.VOLATILE,
        deadline=never,
        lifespan=never,
        liveliness=QosLiveliness.AUTOMATIC,
        liveliness_lease_duration=never,
        avoid_ros_namespace_conventions=False,
    )


class Ros2BagWriter:
    """Writes a ROS 2 bag (a folder, which must not exist yet) with cli.recording.bag.BagWriter's
    methods, so that ``record`` writes either: ``add`` each sample as it was received, ``tick``,
    ``close``.  ``notes`` gathers one line per topic left out (``record`` says them)."""

    def __init__(self, path: Path, library: str = "turtlectl"):
        self.store = typestore()
        from rosbags.rosbag2 import StoragePlugin, Writer, WriterError

        refuse_existing(path)
        self.path = path
        self._writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
        self._writer.set_custom_data("recorded_by", library)
        try:
            self._writer.open()
        except (WriterError, OSError) as exc:
            raise BadInput(f"cannot write {path}: {exc}") from None
        self._connections: dict[tuple[str, str], Any] = {}
        self._skipped: set[str] = set()
        self._generic_types: dict[str, bool] = {}  # a user's ROS type -> whether it can be recorded
        self.notes: list[str] = []
        self.messages = 0
        self.raw = 0  # samples left out (no type the table maps, or no message at all)
        self.closed = False

    @property
    def size(self) -> int:
        """Bytes in the folder so far (the MCAP file is written a chunk at a time)."""
        return sum(p.stat().st_size for p in self.path.iterdir() if p.is_file())

    def add(self, key: str, encoding: str, payload: bytes, received: int) -> Message | None:
        """One sample on ``key`` received at ``received`` (ns since the epoch); the message it holds,
        or None if it is left out (said once per topic in ``notes``)."""
        msg_type = type_from_encoding(encoding)
        message: Message | None = None
        if msg_type is not None:
            try:
                message = decode(payload, msg_type)
            except DecodeError:
                message = None
        converted = ros2_fields.to_ros(message, key) if message is not None else None
        if converted is None and message is not None:
            converted = self._generic(message)
        if converted is None:
            self._skip(key, type_name(type(message)) if message is not None else "")
            return message
        ros_type, fields = converted
        topic = ros2_profile.ros_topic(key)
        connection = self._connections.get((topic, ros_type))
        if connection is None:
            row = ros2_profile.BY_ROS.get(ros_type)
            qos = row.qos if row is not None else ros2_profile.DEFAULT_QOS
            connection = self._writer.add_connection(
                topic, ros_type, typestore=self.store, offered_qos_profiles=[_qos(qos)]
            )
            self._connections[(topic, ros_type)] = connection
        data = self.store.serialize_cdr(build(self.store, ros_type, fields), ros_type)
        self._writer.write(connection, received, bytes(data))
        self.messages += 1
        return message

    def _generic(self, message: Message) -> tuple[str, dict] | None:
        """A user's own flat type as the ROS type of its generic .msg text (turtlectl.nodes.ros2_generic),
        registered once; None for a built-in, a type that is not flat, or a ROS name taken by another
        definition."""
        from turtlectl.messages import ALL_TYPES
        from turtlectl.nodes import ros2_generic

        cls = type(message)
        if cls in ALL_TYPES:
            return None
        ros_type = ros2_generic.ros_name(type_name(cls))
        if ros_type not in self._generic_types:
            text = ros2_generic.msg_text(cls)
            if text is not None:
                from rosbags.typesys import get_types_from_msg

                mine = get_types_from_msg(text, ros_type)
                if ros_type not in self.store.types:
                    self.store.register(mine)
                elif self.store.fielddefs[ros_type][1] != mine[ros_type][1]:
                    text = None  # the name is a ROS type of other fields (a standard one, the table's)
            self._generic_types[ros_type] = text is not None
        return (ros_type, ros2_generic.fields_of(message)) if self._generic_types[ros_type] else None

    def _skip(self, key: str, name: str) -> None:
        self.raw += 1
        if key not in self._skipped:
            self._skipped.add(key)
            what = f"its type {name} has no ROS 2 type here" if name else "its payload is no turtlectl message"
            self.notes.append(f"not recorded in the ROS 2 bag: {key} ({what}; see docs/how-to/ros2-bags.md)")

    def add_scene(self, topic: str, drawing: Any, when: int) -> None:
        raise BadInput("--scene cannot be recorded in a ROS 2 bag")

    def attach_world(self, document: bytes, when: int) -> None:
        """The world the run happens in, kept in metadata.yaml's custom_data (``turtlectl/world``)."""
        self._writer.set_custom_data("turtlectl/world", document.decode())

    def mark_gap(self, lost: int, back: int = 0) -> None:
        """A time without router, in metadata.yaml's custom_data (``turtlectl/gap/<n>``: ``lost back``, ns)."""
        n = sum(k.startswith("turtlectl/gap/") for k in self._writer.custom_data)
        self._writer.set_custom_data(f"turtlectl/gap/{n}", f"{lost} {back}")

    def tick(self, now: int | None = None) -> None:
        """Nothing to do: rosbags writes a chunk to disk each time one reaches 1 MiB."""
        del now

    def close(self) -> None:
        """Finish the bag: the MCAP file's summary, then metadata.yaml."""
        if not self.closed:
            self.closed = True
            self._writer.close()


# -- reading ---------------------------------------------------------------------------------


class Ros2Decoder:
    """Reads CDR messages of a bag's ``ros2msg`` schemas into turtlectl messages: ``message`` gives
    the turtlectl message for a type of the table, None for any other (``unmapped`` says which)."""

    def __init__(self) -> None:
        self.store = typestore()

    def known(self, ros_type: str, msgdef: str) -> bool:
        """Make ``ros_type`` known from the bag's own .msg text if the store lacks it; whether it can be read."""
        if ros_type in self.store.types:
            return True
        from rosbags.typesys import get_types_from_msg

        try:
            self.store.register(get_types_from_msg(msgdef, ros_type))
        except Exception:  # noqa: BLE001 - a definition rosbags cannot parse: the topic is not readable
            return False
        return ros_type in self.store.types

    def message(self, topic: str, ros_type: str, msgdef: str, data: bytes) -> Message | None:
        """The turtlectl message of one CDR payload, None for a type the table does not map.
        RecordingError (exit 2) for a payload that does not decode as its type."""
        if not ros2_fields.readable(ros_type):
            return None
        if not self.known(ros_type, msgdef):
            raise RecordingError(f"{topic}: the definition of {ros_type} in the bag cannot be read")
        try:
            ros = self.store.deserialize_cdr(data, ros_type)
            return ros2_fields.from_ros(ros_type, ros)
        except Exception as exc:  # noqa: BLE001 - rosbags raises many kinds for bad bytes
            raise RecordingError(f"a message on {topic} does not decode as {ros_type}: {exc}") from None

    def fields(self, ros_type: str, msgdef: str, data: bytes) -> dict | None:
        """A CDR payload of any ROS type the bag defines as nested dicts of its fields (sequences as
        lists), or None if it does not decode."""
        if not self.known(ros_type, msgdef):
            return None
        try:
            return _plain(self.store.deserialize_cdr(data, ros_type))
        except Exception:  # noqa: BLE001 - rosbags raises many kinds for bad bytes
            return None


def _plain(value: Any) -> Any:
    """A rosbags message as nested dicts and lists."""
    import dataclasses

    import numpy as np

    if dataclasses.is_dataclass(value):
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value
