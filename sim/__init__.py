"""The turtle simulator: pure kinematics (`kinematics`) and lidar (`lidar`), and the
simulator process (`node`) over `runtime`."""
