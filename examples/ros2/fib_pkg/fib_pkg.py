#!/usr/bin/env python3
"""fib_pkg: a node as a package generator's Python template writes it (not for the bench).

- action ~/fibonacci (fib_pkg_interfaces/action/Fibonacci): the first `order` Fibonacci numbers,
  one a second, each step sent as feedback;
- service ~/set_enabled (std_srvs/srv/SetBool): enables or disables the node.

Its defect is the template's: the action's `async` execute callback sleeps with `time.sleep`
under `rclpy.spin`'s single-threaded executor, so while a goal runs nothing else is served: a
cancel is answered only once the goal has ended, a service call waits for the goal.

    python3 fib_pkg.py   # in a shell where ROS 2 and fib_pkg_interfaces are sourced
"""
import time

import rclpy
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.node import Node
from std_srvs.srv import SetBool

from fib_pkg_interfaces.action import Fibonacci


class FibPkg(Node):

    def __init__(self):
        super().__init__("fib_pkg")
        self.declare_parameter("period", 1.0)
        self.enabled = True
        self.action_server = ActionServer(self, Fibonacci, "~/fibonacci", self.execute_callback,
                                          goal_callback=self.goal_callback, cancel_callback=self.cancel_callback)
        self.service = self.create_service(SetBool, "~/set_enabled", self.set_enabled_callback)
        self.get_logger().info("fib_pkg is ready")

    def goal_callback(self, goal_request):
        self.get_logger().info(f"received goal: order={goal_request.order}")
        return GoalResponse.ACCEPT if self.enabled else GoalResponse.REJECT

    def cancel_callback(self, goal_handle):
        self.get_logger().info("received cancel request")
        return CancelResponse.ACCEPT

    async def execute_callback(self, goal_handle):
        self.get_logger().info("executing goal")
        period = self.get_parameter("period").value
        feedback = Fibonacci.Feedback()
        feedback.partial_sequence = [0, 1]
        for i in range(1, goal_handle.request.order):
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                self.get_logger().info("goal canceled")
                return Fibonacci.Result()
            feedback.partial_sequence.append(feedback.partial_sequence[i] + feedback.partial_sequence[i - 1])
            goal_handle.publish_feedback(feedback)
            time.sleep(period)
        goal_handle.succeed()
        result = Fibonacci.Result()
        result.sequence = feedback.partial_sequence
        return result

    def set_enabled_callback(self, request, response):
        self.enabled = request.data
        response.success = True
        response.message = "enabled" if request.data else "disabled"
        return response


def main(args=None):
    rclpy.init(args=args)
    node = FibPkg()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
