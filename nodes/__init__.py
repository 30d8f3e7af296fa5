"""The nodes that drive the turtle: navigator, status_monitor, obstacle_detector.

Pure logic lives in `control`, `goal`, `goal_machine` (a goal's lifecycle), `driver` (driving
it), `surroundings`, `planner`, `costmap`, `scan`, `battery` and `params` (no zenoh);
the node modules are thin shells over `runtime` that wire keys to it.  `kinds`
names every node kind a launch file can run.
"""
