"""cli.system.supervisor.elsewhere: the nodes a supervisor did not start, said once as they are
first seen, leave and come back (name, pid, host); a stale token's removal says nothing."""

from turtlectl.cli.system.supervisor.elsewhere import Elsewhere


def test_a_node_of_another_host_is_said_when_seen_when_it_leaves_and_when_it_is_back():
    nodes = Elsewhere()
    said = [
        nodes.seen(True, "turtle2/navigator", 41, "hostb"),
        nodes.seen(True, "turtle2/navigator", 41, "hostb"),  # the same token again: nothing
        nodes.seen(False, "turtle2/navigator", 41, "hostb"),
        nodes.seen(True, "turtle2/navigator", 57, "hostb"),  # respawned there
    ]
    assert said == [
        "turtle2/navigator runs elsewhere (pid 41 on hostb; not started here)",
        None,
        "turtle2/navigator left (pid 41 on hostb; not started here): its topics and services are gone until it is back",
        "turtle2/navigator is back (pid 57 on hostb; not started here)",
    ]


def test_the_removal_of_a_process_already_replaced_says_nothing():
    nodes = Elsewhere()
    nodes.seen(True, "status_monitor", 10, "")
    nodes.seen(True, "status_monitor", 11, "")  # a new process before the old token went
    assert nodes.seen(False, "status_monitor", 10, "") is None
    assert nodes.seen(False, "status_monitor", 11, "") == (
        "status_monitor left (pid 11; not started here): its topics and services are gone until it is back"
    )
