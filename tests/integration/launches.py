"""Launch files the integration tests share (their fixtures are in conftest.py)."""

CUSTOM = """
[world]
size = 11.088889
obstacles = [
  { x = 5.0, y = 4.5, radius = 0.3 },
  { x = 2.0, y = 6.0, radius = 0.4 },
  { x = 3.0, y = 2.5, radius = 0.5 },
]

[limits]
max_linear_speed = 3.5
max_angular_speed = 8.0

[[node]]
name = "sim"
run = "sim"
required = true
[node.params]
x = 3.0
y = 4.5
theta = 1.0

[[node]]
name = "navigator"
run = "navigator"
[node.params]
blocked_timeout = 1.0
safety_distance = 0.5

[[node]]
name = "status_monitor"
run = "status_monitor"
respawn = true
respawn_delay = 0.2
[node.params]
battery = 80.0

[[node]]
name = "obstacle_detector"
run = "obstacle_detector"
[node.params]
beams = 90
range_max = 2.5
"""
