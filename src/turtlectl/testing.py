"""Testing your own system, as ``launch_testing`` does for ROS 2 and dora's ``MockNode`` for
its nodes (docs/how-to/test-your-system.md):

* ``LaunchedSystem(launch_file, args=())``: the real ``turtlectl launch`` on a free port,
  ready when every node is, failed at once with the node's output when one dies while
  starting, always stopped (its process group killed).  ``.client()`` is a ``turtlectl.Client``.
* the pytest plugin (installed with turtlectl: a ``pytest11`` entry point) gives every test
  the fixtures ``turtlectl_system`` (a Client of the system your launch file starts: the
  ``turtlectl_launch`` marker's file, else the ini option ``turtlectl_launch``, else
  ``launch.toml`` in the rootdir) and ``turtlectl_launch`` (a factory for more systems).
* ``FakeNode(NodeClass, params)``: your node class without Zenoh: deliver messages and
  requests, advance a fake clock so timers fire, read what it published and answered;
  ``send_goal`` gives a goal server a goal (a ``FakeGoal``: its feedback, result, cancel).
* ``unstamped(msg)``: a published message with its ``stamp`` and ``seq`` (filled in by the
  publisher) at 0, to compare with one built by hand: ``unstamped(m) == Twist(linear=1.0)``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from turtlectl import _lazy

if TYPE_CHECKING:
    from turtlectl.cli.system.launched import LaunchedSystem, StartFailed
    from turtlectl.runtime.fake import FakeGoal, FakeNode, unstamped

__all__ = ["FakeGoal", "FakeNode", "LaunchedSystem", "StartFailed", "unstamped"]

_HOME = {
    "FakeGoal": "turtlectl.runtime.fake",
    "FakeNode": "turtlectl.runtime.fake",
    "LaunchedSystem": "turtlectl.cli.system.launched",
    "StartFailed": "turtlectl.cli.system.launched",
    "unstamped": "turtlectl.runtime.fake",
}


__getattr__ = _lazy(__name__, _HOME)
