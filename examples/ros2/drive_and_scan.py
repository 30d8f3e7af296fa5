"""A student's ROS 2 node, in plain rclpy: it drives turtlectl's turtle and reads its laser scan.

Nothing of turtlectl is imported: with turtlectl's system running and its ROS 2 bridge on
(``turtlectl ros2 bridge``, or ``run = "ros2_bridge"`` in the launch file), this is an ordinary ROS 2
node talking to ``/turtle1/cmd_vel``, ``/obstacles`` and ``/turtle1/odom``.

    pip install ros-rclpy ros-geometry-msgs ros-sensor-msgs ros-nav-msgs ros-rmw-fastrtps-cpp
    ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST python drive_and_scan.py --seconds 10

It drives forward, and turns left while something is nearer than ``--clearance`` m ahead (the beams
within 20 degrees of straight ahead); once a second it prints where the odometry says it is and the
nearest range ahead.
"""

import argparse
import math

import rclpy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.node import Node
from sensor_msgs.msg import LaserScan

AHEAD = math.radians(20)  # rad: the beams that count as "ahead", either side of straight on


class DriveAndScan(Node):
    def __init__(self, clearance: float, speed: float):
        super().__init__("drive_and_scan")
        self.clearance, self.speed = clearance, speed
        self.nearest = math.inf  # m: the nearest range ahead in the last scan
        self.scans = 0
        self.position = None
        self.cmd = self.create_publisher(Twist, "/turtle1/cmd_vel", 10)
        self.create_subscription(LaserScan, "/obstacles", self.on_scan, 10)
        self.create_subscription(Odometry, "/turtle1/odom", self.on_odom, 10)
        self.create_timer(0.1, self.drive)
        self.create_timer(1.0, self.report)

    def on_scan(self, scan: LaserScan) -> None:
        ahead = [
            r
            for i, r in enumerate(scan.ranges)
            if abs(scan.angle_min + i * scan.angle_increment) <= AHEAD and scan.range_min <= r
        ]
        self.nearest = min(ahead, default=math.inf)
        self.scans += 1

    def on_odom(self, odom: Odometry) -> None:
        p = odom.pose.pose.position
        self.position = (p.x, p.y)

    def drive(self) -> None:
        cmd = Twist()
        if self.nearest < self.clearance:
            cmd.angular.z = 1.5  # rad/s: turn left until the way ahead is clear
        else:
            cmd.linear.x = self.speed  # m/s
        self.cmd.publish(cmd)

    def report(self) -> None:
        where = "no odometry yet" if self.position is None else f"at ({self.position[0]:.2f}, {self.position[1]:.2f})"
        print(f"{where}, nearest ahead {self.nearest:.2f} m, {self.scans} scans", flush=True)

    def stop(self) -> None:
        self.cmd.publish(Twist())  # stand still when leaving


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=30.0, help="how long to drive (s)")
    parser.add_argument("--clearance", type=float, default=1.0, help="turn while something is nearer ahead (m)")
    parser.add_argument("--speed", type=float, default=0.8, help="forward speed (m/s)")
    args = parser.parse_args()
    rclpy.init()
    node = DriveAndScan(args.clearance, args.speed)
    end = node.get_clock().now().nanoseconds + int(args.seconds * 1e9)
    try:
        while rclpy.ok() and node.get_clock().now().nanoseconds < end:
            rclpy.spin_once(node, timeout_sec=0.1)
    except KeyboardInterrupt:
        pass
    finally:
        node.stop()
        node.report()
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
