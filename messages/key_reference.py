"""Who publishes each key of the wire contract, when, and how to use it: what code cannot say
about the keys, in one place (each field's unit, range and meaning: messages.reference).
Read by ``turtlectl interface`` and by docs/gen_interfaces.py (docs/interfaces.md);
tests/unit/docs/test_gen_interfaces.py fails when a key has no entry here, or an entry names
one that no longer exists.  Pure data: no zenoh.
"""

from __future__ import annotations

from turtlectl.messages import keys

# key -> (kind, payload, from -> to, when, how to use it)
KEYS: dict[str, tuple[str, str, str, str, str]] = {
    keys.CMD_VEL: (
        "topic",
        "Twist",
        "navigator -> sim",
        "with each pose, only while a goal runs",
        "subscribe; publish to drive by hand (the sim stops 1 s (cmd_timeout) after the last one)",
    ),
    keys.POSE: ("topic", "Pose", "sim -> anyone", "62.5 Hz (every 16 ms simulation step)", "subscribe"),
    keys.STATUS: ("topic", "TurtleStatus", "status_monitor -> anyone", "10 Hz", "subscribe"),
    keys.OBSTACLES: ("topic", "LaserScan", "obstacle_detector -> navigator, anyone", "5 Hz", "subscribe"),
    keys.FEEDBACK: (
        "topic",
        "NavigateToFeedback",
        "navigator -> anyone (observers)",
        "10 Hz, only while a goal runs",
        "subscribe",
    ),
    keys.NAVIGATE_TO: (
        "service",
        "NavigateToRequest -> NavigateToFeedback replies, then one NavigateToResponse",
        "client -> navigator",
        "per goal; feedback at feedback_rate (10 Hz)",
        "get with ConsolidationMode.NONE (the default consolidation delivers only the response, at the end)",
    ),
    keys.CANCEL: (
        "service",
        "Cancel -> Ack",
        "client -> navigator",
        "on request",
        "get; Ack ok=false when no goal is running",
    ),
    keys.TELEPORT: (
        "service",
        "TeleportAbsolute -> Ack",
        "client -> sim",
        "on request",
        "get; an ErrorReply (reply.err) for an impossible pose",
    ),
    keys.MOVING: (
        "service",
        "Moving -> Ack from each server",
        "sim -> navigator (whatever drives the turtle)",
        "before a teleport or reset moves the turtle",
        "the simulator moves the turtle once every server has answered (each turtle's, <turtle>/moving; a reset asks **/moving)",
    ),
    keys.RESET: (
        "service",
        "Reset -> Ack from each server",
        "client -> sim (pose; turtle1 and the turtles of its params back at their spawns, every other turtle removed), every status_monitor (battery)",
        "on request",
        "get with QueryTarget.ALL and ConsolidationMode.NONE for both Acks (the default consolidation returns one)",
    ),
    keys.SPAWN: (
        "service",
        "SpawnRequest -> SpawnResponse",
        "client -> sim",
        "on request",
        "get; an ErrorReply (reply.err) for a name taken or invalid, or a place outside the world, inside an obstacle or on a turtle; the answer comes once the new turtle's first pose is out",
    ),
    keys.KILL: (
        "service",
        "Kill -> Ack",
        "client -> sim",
        "on request",
        "get; an ErrorReply (reply.err) naming the turtles for an unknown name; the turtle's keys go with it",
    ),
    keys.TURTLES: ("topic", "Turtles", "sim -> anyone (obstacle_detector)", "15.6 Hz (every 4th step)", "subscribe"),
    keys.CLOCK: (
        "topic",
        "Clock",
        "sim -> nodes with use_sim_time",
        "62.5 Hz x real_time_factor (every step)",
        "subscribe; a node started with use_sim_time runs its timers, timeouts and stamps on it",
    ),
    keys.pose_key("<turtle>"): (
        "topic",
        "Pose",
        "sim -> anyone",
        "62.5 Hz, for each spawned turtle (turtle1's is turtle1/pose)",
        "subscribe",
    ),
    keys.cmd_vel_key("<turtle>"): (
        "topic",
        "Twist",
        "anyone -> sim",
        "as sent",
        "publish to drive a spawned turtle (turtle1's is turtle1/cmd_vel)",
    ),
    keys.teleport_key("<turtle>"): (
        "service",
        "TeleportAbsolute -> Ack",
        "client -> sim",
        "on request",
        "get; as turtle1/teleport_absolute (only turtle1's cancels a running goal)",
    ),
    keys.WORLD_KEY: (
        "queryable",
        "JSON (application/json): World",
        "sim -> anyone (turtlectl view)",
        "on request",
        "get; fixed for the sim's lifetime",
    ),
    keys.params_key("<node>"): (
        "queryable",
        "JSON (application/json): the node's parameters",
        "each node -> anyone",
        "on request",
        "get; the parameters the node runs with",
    ),
    keys.param_describe_key("<node>"): (
        "queryable",
        "JSON (application/json): ParamDescription, the node's parameters described (type, unit, range, default, meaning, whether each can change at run time and why not, value now)",
        "each node (any kind) -> anyone",
        "on request",
        "get; `turtlectl param describe` and `param set` work from it alone",
    ),
    keys.param_set_key("<node>"): (
        "service",
        "SetParameter -> Ack",
        "client -> each node",
        "on request",
        "get; an ErrorReply (reply.err) for an unknown parameter, an invalid value or one that cannot change at run time; `turtlectl param set` validates as the launch file does first",
    ),
    keys.PARAMETER_EVENTS: (
        "topic",
        "ParameterEvent",
        "each node -> anyone",
        "each time a parameter changes at run time",
        "subscribe (`turtlectl echo turtlectl/parameter_events`)",
    ),
    keys.node_key("<node>"): (
        "queryable",
        "JSON (application/json): NodeDetails (name, pid, host, start_ns, kind, log_level, errors, last_error)",
        "each node -> anyone",
        "on request",
        "get; `turtlectl/nodes/*` for every node",
    ),
    keys.log_level_key("<node>"): (
        "service",
        "SetLogLevel -> Ack",
        "client -> each node",
        "on request",
        "get; an ErrorReply for an unknown level",
    ),
    keys.log_key("<node>"): (
        "topic, queryable",
        "Log",
        "each node -> anyone (turtlectl log, record)",
        "each record the node logs at its log level, once its session is open; a get: its last 200 records",
        f"subscribe on `{keys.LOG_KEYS}` for every node's (`<node>`: its name, `/` written `.`: turtle2.navigator); "
        f"get `{keys.LOG_KEYS}` (QueryTarget.ALL, ConsolidationMode.NONE) for each node's recent ones, a Log reply each, oldest first",
    ),
    f"{keys.NODE_TOKEN_PREFIX}/<name>/<pid>/<host>/<start_ns>": (
        "liveliness token",
        "-",
        "each node -> anyone",
        "while the node runs",
        f"liveliness get or subscribe on `{keys.NODE_TOKEN_PREFIX}/**`",
    ),
    f"{keys.ENTITY_TOKEN_PREFIX}/<node>/<pid>/<role>/<Type>/<key>": (
        "liveliness token",
        "-",
        "each node -> anyone (turtlectl list)",
        "while the entity exists",
        f"liveliness get on `{keys.ENTITY_TOKEN_PREFIX}/**`; role is pub, sub or srv; Type the message type's full name with a dot for its slash (turtlectl.Pose, capstone_msgs.TurtleStatus; a service's request type; JSON for the JSON queryables); key may contain /",
    ),
    f"{keys.CLIENT_NODE_TOKEN_PREFIX}/<name>/<pid>/<host>/<start_ns>/<tool>": (
        "liveliness token",
        "-",
        "each client (a turtlectl tool, a script's turtlectl.Client) -> anyone (turtlectl list, node list)",
        "while the client's session is open",
        "<name> is <tool>-<pid> (teleop-4242), <tool> the command (teleop, goto, echo, record, plot, ...) or python; "
        "a client of another language may declare one to be listed; optional",
    ),
    f"{keys.CLIENT_ENTITY_TOKEN_PREFIX}/<name>/<pid>/<role>/<Type>/<key>": (
        "liveliness token",
        "-",
        "each client -> anyone (turtlectl list, topic info; teleop finds who drives a turtle)",
        "while the client's publisher or subscriber exists",
        f"as `{keys.ENTITY_TOKEN_PREFIX}/...`, role pub or sub; never counted as a node's (claims); optional",
    ),
    f"{keys.CLIENT_TOKEN_PREFIX}/<id>": (
        "liveliness token",
        "-",
        "a navigate_to caller -> navigator",
        "while the caller waits for its goal",
        "declare it before the request, put <id> in NavigateToRequest.client; optional",
    ),
    f"{keys.DOMAIN_TOKEN_PREFIX}/<domain>": (
        "liveliness token",
        "-",
        "a supervisor run with --domain -> anyone",
        "while the supervisor runs",
        "liveliness get on `@turtlectl/domain/*` from a session without namespace",
    ),
}
