"""cli.tools.topics: what a silent topic says."""

from turtlectl.cli.tools.topics import silence_text
from turtlectl.messages.keys import (
    EntityInfo,
    NodeInfo,
    entity_token,
    node_token,
)
from turtlectl.runtime.client.graph import build_graph


def _graph_with(*entities: EntityInfo, nodes: bool = True):
    keys = [entity_token(e) for e in entities]
    if nodes:
        keys.append(node_token(NodeInfo(name="navigator", pid=2)))
    return build_graph(keys, now_ns=0)


def test_silence_says_when_a_topic_is_published():
    feedback_pub = EntityInfo(
        node="navigator", pid=2, role="pub", type_name="NavigateToFeedback", key="navigate_to/feedback"
    )
    graph = _graph_with(feedback_pub)
    text = silence_text("navigate_to/feedback", graph, lambda: "")
    assert "navigator publishes it only while a goal runs" in text and "launch" not in text
    assert "navigator publishes it only while a goal runs" in silence_text("navigate_to/*", graph, lambda: "")
    status_pub = EntityInfo(node="status_monitor", pid=3, role="pub", type_name="TurtleStatus", key="robot/status")
    assert "for 3 s although status_monitor publishes it" in silence_text(
        "robot/status", _graph_with(status_pub), lambda: ""
    )
    assert "no running node publishes it" in silence_text("nosuch", graph, lambda: "")
    nothing = silence_text("robot/status", build_graph([], 0), lambda: "; systems run in domain lab1")
    assert "no turtlectl node runs on this router" in nothing and nothing.endswith("; systems run in domain lab1")
    assert "no turtlectl node runs in domain lab2" in silence_text(
        "robot/status", build_graph([], 0), lambda: "", "lab2"
    )


def test_silence_outside_a_domain_points_into_the_domain_that_publishes():
    keys = [
        "lab1/" + node_token(NodeInfo(name="status_monitor", pid=3)),
        "lab1/"
        + entity_token(
            EntityInfo(node="status_monitor", pid=3, role="pub", type_name="TurtleStatus", key="robot/status")
        ),
    ]
    text = silence_text("robot/status", build_graph(keys, 0), lambda: "")
    assert (
        text
        == "nothing published on robot/status here: it is published in domain lab1: add it before the command, `turtlectl --domain lab1 ...` (or use lab1/robot/status)"
    )


def test_silence_on_parameter_events_says_they_come_only_when_a_parameter_changes():
    """An idle parameter_events topic is not called "may be stalled"."""
    events = EntityInfo(node="sim", pid=4, role="pub", type_name="ParameterEvent", key="turtlectl/parameter_events")
    text = silence_text("turtlectl/parameter_events", _graph_with(events), lambda: "")
    assert text == (
        "nothing published on turtlectl/parameter_events yet: sim publishes it only when a parameter changes "
        "(`turtlectl param set NODE NAME VALUE`)"
    )


def test_a_stream_that_stopped_after_flowing_gets_the_same_reasons_without_yet():
    """The hint comes when nothing ever arrived and also when a stream stops."""
    feedback_pub = EntityInfo(
        node="navigator", pid=2, role="pub", type_name="NavigateToFeedback", key="navigate_to/feedback"
    )
    text = silence_text("navigate_to/feedback", _graph_with(feedback_pub), lambda: "", flowed=True)
    assert text == (
        "nothing published on navigate_to/feedback for 3 s: navigator publishes it only while a goal runs "
        "(start one with `turtlectl goto X Y THETA`)"
    )
    gone = silence_text("robot/status", build_graph([], 0), lambda: "", flowed=True)
    assert gone.startswith("nothing published on robot/status for 3 s: no turtlectl node runs on this router")
    assert "yet" not in silence_text("nosuch", _graph_with(), lambda: "", flowed=True)


def test_silence_of_a_publisher_does_not_call_it_stalled_only():
    """A filter node publishes only when it gets commands; silence is not a stall."""
    pub = EntityInfo(node="turtle2/limiter", pid=3, role="pub", type_name="Twist", key="turtle2/cmd_vel")
    text = silence_text("turtle2/cmd_vel", _graph_with(pub), lambda: "")
    assert text.endswith(
        "although turtle2/limiter publishes it: it may be idle (it publishes only when it has something to say) "
        "or stalled (see its log)"
    ), text
