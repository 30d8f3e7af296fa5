"""The node runtime (`runtime`, `session`) and the nodes: navigator, status_monitor, obstacle_detector.

Pure logic lives in `control`, `scan`, `battery`, `goal`, `params`; the node
modules are thin shells that wire keys to it.
"""
