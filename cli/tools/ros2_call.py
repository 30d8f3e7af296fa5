"""``turtlectl ros2 call``'s logic: a ROS 2 service called over DDS (``nodes.ros2_services``), its
answer as text; every failure one ``TurtlectlError`` (no printing here).

Cyclone DDS's Python binding is an optional extra (``turtlectl[ros2]``): it is imported only when a
call runs, and its absence is one line saying how to install it.
"""

from __future__ import annotations

from types import ModuleType
from typing import Any

from turtlectl.runtime.client.errors import BadInput, CannotStart, Unreachable

INSTALL_HINT = "pip install 'turtlectl[ros2]'"


def dds_module(name: str) -> ModuleType:
    """``turtlectl.nodes.<name>`` (a module that imports Cyclone DDS); CannotStart saying how to
    install the extra if Cyclone DDS's Python binding is missing."""
    import importlib

    try:
        return importlib.import_module(f"turtlectl.nodes.{name}")
    except ImportError as exc:
        if (exc.name or "").split(".")[0] != "cyclonedds":
            raise
        raise CannotStart(
            f"ROS 2 needs Cyclone DDS's Python binding, which is not installed ({INSTALL_HINT})"
        ) from None


def call(service: str, ros_type: str, request_text: str, timeout: float) -> dict[str, Any]:
    """Call ROS service ``service`` of type ``ros_type`` with the request ``request_text`` (YAML flow
    mapping or JSON, as ``ros2 service call``); the response's fields.  BadInput for a name, type or
    request that cannot be used (before anything is sent), Unreachable if no server answers within
    ``timeout`` s."""
    from turtlectl.nodes import ros2_requests as rq

    try:
        name = rq.check_service_name(service)
        rq.check_service_type(ros_type)
        request = rq.fit_request(ros_type, rq.parse_request(request_text))
    except ValueError as exc:
        raise BadInput(str(exc)) from None
    services = dds_module("ros2_services")
    dds = dds_module("ros2_dds")
    try:
        domain_id = dds.ros_domain_id()
    except ValueError as exc:
        raise BadInput(str(exc)) from None
    try:
        return services.call(name, ros_type, request, timeout, domain_id)
    except services.NoServer as exc:
        raise Unreachable(f"{exc} (is it served on ROS_DOMAIN_ID {domain_id}, on this host?)") from None
    except services.NoReply as exc:
        raise Unreachable(str(exc)) from None


def response_text(service: str, ros_type: str, response: dict[str, Any]) -> str:
    """The response as a block, as ``turtlectl call`` prints one: ``# <type> response from <service>``,
    one ``field: value`` per line, ``---``."""
    from turtlectl.cli.tools.format import value_text

    lines = [f"# {ros_type} response from {service}"]
    lines += [f"{field}: {value_text(value)}" for field, value in response.items()]
    return "\n".join(lines) + "\n---"
