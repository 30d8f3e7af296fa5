"""The one way turtlectl joins a ROS 2 graph over DDS: a Cyclone DDS participant that Fast DDS peers
(the pip-installed rclpy wheels) match, on loopback unless told otherwise.

* :func:`cyclone_config` is the XML every turtlectl participant uses: the interface to listen on
  (127.0.0.1 unless told otherwise), no multicast, unicast discovery to the same address with
  per-index ports (what Fast DDS's ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` sends to), and
  ``IgnoreTypeInformation`` for eProsima's vendor id 1.15 (without it no type holding a sequence,
  such as ``sensor_msgs/msg/LaserScan``, ever matches Fast DDS).
* :func:`participant` opens one on the ROS domain (``ROS_DOMAIN_ID``, 0 unless set), with the
  ``enclave=/;`` USER_DATA rclpy's graph reads.
* :data:`RELIABLE` is rclpy's default QoS (``10``: reliable, volatile, keep last 10), :data:`SENSOR`
  its sensor-data QoS (best effort, keep last 5), :data:`LATCHED` /rosout's, :data:`GRAPH` the QoS of ``ros_discovery_info``.

Importing this module loads the Cyclone DDS C library (~0.35 s): only the processes that speak DDS
import it, lazily.
"""

import os

from cyclonedds.domain import DomainParticipant
from cyclonedds.qos import Policy, Qos

from turtlectl.nodes.ros2_types import XCDR1

ROS_DOMAIN_ENV = "ROS_DOMAIN_ID"
ROS_DOMAIN_RANGE = (0, 232)  # the ROS 2 domain ids whose ports fit (REP 2000's 0-101 and 215-232 are the safe ones)
LOOPBACK = "127.0.0.1"
MAX_PARTICIPANTS = 20  # per host and domain: Cyclone's highest participant index, so its highest port

RELIABLE = Qos(Policy.Reliability.Reliable(0), Policy.Durability.Volatile, Policy.History.KeepLast(10), XCDR1)
SENSOR = Qos(Policy.Reliability.BestEffort, Policy.Durability.Volatile, Policy.History.KeepLast(5), XCDR1)
#: what rcl's /rosout publishers offer (reliable, transient local, keep last 1000): a late subscriber
#: asking for transient local (as rqt_console does) gets the last lines, and matches at all
#: (Cyclone gives a late reader what its durability service keeps, one sample unless told: told 1000 too)
LATCHED = Qos(
    Policy.Reliability.Reliable(0),
    Policy.Durability.TransientLocal,
    Policy.History.KeepLast(1000),
    Policy.DurabilityService(0, Policy.History.KeepLast(1000), -1, -1, -1),
    XCDR1,
)
GRAPH = Qos(Policy.Reliability.Reliable(0), Policy.Durability.TransientLocal, Policy.History.KeepLast(1), XCDR1)


def ros_domain_id(environ: dict[str, str] | None = None) -> int:
    """The ROS 2 domain (``ROS_DOMAIN_ID``, 0 unless set); ValueError naming the variable if it is no
    whole number in ``ROS_DOMAIN_RANGE``."""
    text = (os.environ if environ is None else environ).get(ROS_DOMAIN_ENV, "").strip()
    if not text:
        return 0
    low, high = ROS_DOMAIN_RANGE
    if not text.isdigit() or not low <= int(text) <= high:
        raise ValueError(f"{ROS_DOMAIN_ENV}={text!r}: give a whole number from {low} to {high}")
    return int(text)


def cyclone_config(address: str = LOOPBACK) -> str:
    """Cyclone DDS's configuration (XML) for a participant that talks to ROS 2 peers on ``address``
    only (127.0.0.1 unless told otherwise): no multicast, unicast discovery, Fast DDS's types matched."""
    return (
        "<CycloneDDS><Domain Id='any'>"
        f"<General><Interfaces><NetworkInterface address='{address}'/></Interfaces>"
        "<AllowMulticast>false</AllowMulticast></General>"
        "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
        f"<MaxAutoParticipantIndex>{MAX_PARTICIPANTS}</MaxAutoParticipantIndex>"
        f"<Peers><Peer address='{address}'/></Peers></Discovery>"
        "<Compatibility><IgnoreTypeInformation>1.15</IgnoreTypeInformation></Compatibility>"
        "</Domain></CycloneDDS>"
    )


def participant(domain_id: int, address: str = LOOPBACK) -> DomainParticipant:
    """A participant in ROS 2 domain ``domain_id`` that rclpy's graph sees (USER_DATA ``enclave=/;``),
    configured by :func:`cyclone_config`.  One configuration per process: the first call sets it."""
    os.environ["CYCLONEDDS_URI"] = cyclone_config(address)  # read by Cyclone when the domain is first made
    return DomainParticipant(domain_id, qos=Qos(Policy.Userdata(b"enclave=/;")))


def rclpy_environment(domain_id: int = 0) -> dict[str, str]:
    """What an rclpy process needs in its environment to meet turtlectl's participant on loopback."""
    return {
        "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST",
        ROS_DOMAIN_ENV: str(domain_id),
        "RMW_IMPLEMENTATION": "rmw_fastrtps_cpp",
    }
