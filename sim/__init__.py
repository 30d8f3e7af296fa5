"""The turtle simulator: pure kinematics (`kinematics`, `world`) and its process (`node`)."""
