"""A spec names a type by its full name or by a short one: the interface checks compare it with
the full name the graph says (a user's capstone_msgs/TurtleStatus is not turtlectl's)."""

from __future__ import annotations

from turtlectl.cli.verify.checks import _declared
from turtlectl.messages.naming import names as same_type

ROLES = ("type", "from", "published by")


def test_a_short_name_in_a_spec_is_any_packages_type_of_that_name():
    assert same_type("LaserScan", "turtlectl/LaserScan")
    assert same_type("TurtleStatus", "capstone_msgs/TurtleStatus")


def test_a_full_name_in_a_spec_is_that_type_only():
    assert same_type("capstone_msgs/TurtleStatus", "capstone_msgs/TurtleStatus")
    assert not same_type("turtlectl/TurtleStatus", "capstone_msgs/TurtleStatus")
    assert not same_type("Pose", "turtlectl/Twist")


def test_a_topic_of_a_built_in_type_named_short_in_the_spec_holds():
    found = ("turtlectl/LaserScan", ["obstacle_detector"])
    _, measured, problems = _declared("LaserScan", "obstacle_detector", found, ROLES, "absent")
    assert problems == [] and measured == "turtlectl/LaserScan from obstacle_detector"
    _, _, problems = _declared("turtlectl/TurtleStatus", "", ("capstone_msgs/TurtleStatus", ["m"]), ROLES, "absent")
    assert problems == ["its type is capstone_msgs/TurtleStatus"]
