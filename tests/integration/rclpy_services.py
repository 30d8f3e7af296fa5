"""A real rclpy node serving std_srvs services, run with the rclpy wheels' venv (.venv-ros2):
"the student's rclpy server" that ``turtlectl ros2 call`` talks to over DDS.

Serves /set_flag (SetBool: success = data, message "flag <data>"), /trigger (Trigger: success,
message "triggered <n>") and /reset (Empty), prints READY once they exist, and runs until its stdin
closes.  Each request it answers is printed as one line ("set_flag True", "trigger", "reset").
"""

import sys
import threading

import rclpy
from rclpy.node import Node
from std_srvs.srv import Empty, SetBool, Trigger


def main() -> None:
    rclpy.init()
    node = Node("rclpy_services")
    triggered = [0]

    def set_flag(request, response):
        response.success = request.data
        response.message = f"flag {request.data}"
        print("set_flag", request.data, flush=True)
        return response

    def trigger(request, response):
        triggered[0] += 1
        response.success = True
        response.message = f"triggered {triggered[0]}"
        print("trigger", flush=True)
        return response

    def reset(request, response):
        print("reset", flush=True)
        return response

    node.create_service(SetBool, "/set_flag", set_flag)
    node.create_service(Trigger, "/trigger", trigger)
    node.create_service(Empty, "/reset", reset)
    closed = threading.Event()
    threading.Thread(target=lambda: (sys.stdin.read(), closed.set()), daemon=True).start()
    print("READY", flush=True)
    while not closed.is_set():
        rclpy.spin_once(node, timeout_sec=0.1)
    node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
