"""A ROS 2 node written as the rclpy tutorials write one, for the tests of the adapter on nodes
nobody on the project wrote: an action server `count` (its goal runs a while, publishing a feedback,
and honours a cancel) and a std_srvs/SetBool service `set` (success = the request's data), with
no configure_introspection, so its servers publish no introspection on any distro.

    python tests/support/ros2_tutorial_node.py   # under a distro's venv python, in the bench's environment
"""
import time

import rclpy
from rclpy.action import ActionServer, CancelResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.node import Node
from std_srvs.srv import SetBool
from untimely_msgs.action import Request

GOAL_S = 1.5  # how long a goal runs unless cancelled


class Tutorial(Node):
    def __init__(self):
        super().__init__("tutorial")
        self._action_server = ActionServer(self, Request, "count", self.execute_callback,
                                           cancel_callback=lambda goal_handle: CancelResponse.ACCEPT,
                                           callback_group=ReentrantCallbackGroup())
        self.srv = self.create_service(SetBool, "set", self.set_callback)

    def set_callback(self, request, response):
        response.success = request.data
        response.message = "set" if request.data else "not set"
        return response

    def execute_callback(self, goal_handle):
        goal_handle.publish_feedback(Request.Feedback(phase="counting"))
        deadline = time.monotonic() + GOAL_S
        while time.monotonic() < deadline:
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                return Request.Result()
            time.sleep(0.05)
        goal_handle.succeed()
        return Request.Result(code="ok")


def main():
    rclpy.init()
    node = Tutorial()
    try:
        rclpy.spin(node, executor=MultiThreadedExecutor())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
