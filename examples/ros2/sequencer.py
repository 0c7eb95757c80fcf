"""A small ROS 2 lifecycle node, written the way a ROS 2 user writes one (not for the bench).

/sequencer computes number sequences on request:
- action ~/fibonacci (test_msgs/action/Fibonacci): the first `order` Fibonacci numbers, one per
  step, each step sent as feedback;
- action ~/countdown (test_msgs/action/Fibonacci): `order` numbers counting down from `order`, one per step;
- service ~/reset (std_srvs/srv/Trigger): forgets how many sequences were computed;
- service ~/calibrate (std_srvs/srv/Trigger): measures the step time again;
- service ~/status (std_srvs/srv/Trigger): says how many sequences were computed.

It is managed (rclpy.lifecycle): its servers exist from the start and work only while it is
active (activate lets it work, deactivate stops it). README.md lists the protections it lacks on purpose.

    python3 examples/ros2/sequencer.py   # in a shell where ROS 2 is sourced
"""
import threading
import time

import rclpy
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_srvs.srv import Trigger
from test_msgs.action import Fibonacci

STEP_S = 0.1  # seconds per number of a sequence
MAX_ORDER = 50


class Sequencer(LifecycleNode):
    def __init__(self):
        super().__init__("sequencer")
        self.active = False
        self.computed = 0
        self.lock = threading.Lock()
        group = ReentrantCallbackGroup()
        ActionServer(self, Fibonacci, "~/fibonacci", self.fibonacci, goal_callback=self.accept_goal,
                     cancel_callback=self.accept_cancel, callback_group=group)
        # countdown was added later, copied from the server above without its goal check
        ActionServer(self, Fibonacci, "~/countdown", self.countdown, cancel_callback=self.accept_cancel,
                     callback_group=group)
        self.create_service(Trigger, "~/reset", self.reset, callback_group=group)
        self.create_service(Trigger, "~/calibrate", self.calibrate, callback_group=group)
        self.create_service(Trigger, "~/status", self.status, callback_group=group)

    # -- lifecycle ---------------------------------------------------------------------------
    def on_configure(self, state):
        self.computed = 0
        self.get_logger().info("configured")
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.active = True
        return super().on_activate(state)

    def on_deactivate(self, state):
        self.active = False
        return super().on_deactivate(state)

    def on_cleanup(self, state):
        self.computed = 0
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state):
        self.active = False
        return TransitionCallbackReturn.SUCCESS

    # -- actions -----------------------------------------------------------------------------
    def accept_goal(self, goal):
        if not self.active or not 0 <= goal.order <= MAX_ORDER:
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def accept_cancel(self, goal_handle):
        return CancelResponse.ACCEPT

    def fibonacci(self, goal_handle):
        sequence = [0, 1]
        return self.steps(goal_handle, sequence, lambda: sequence[-1] + sequence[-2])

    def countdown(self, goal_handle):
        sequence = [goal_handle.request.order]
        return self.steps(goal_handle, sequence, lambda: sequence[-1] - 1)

    def steps(self, goal_handle, sequence, following):
        feedback, order = Fibonacci.Feedback(), goal_handle.request.order
        while len(sequence) < order:
            if goal_handle.is_cancel_requested:
                goal_handle.canceled()
                return Fibonacci.Result(sequence=sequence)
            sequence.append(following())
            feedback.sequence = sequence
            goal_handle.publish_feedback(feedback)
            time.sleep(STEP_S)
        goal_handle.succeed()
        with self.lock:
            self.computed += 1
        return Fibonacci.Result(sequence=sequence[:max(order, 0)])

    # -- services ----------------------------------------------------------------------------
    def reset(self, request, response):
        response.success = self.active
        if self.active:
            with self.lock:
                self.computed = 0
        response.message = "reset" if self.active else "not active"
        return response

    def calibrate(self, request, response):
        # forgot to check self.active: it calibrates while inactive too
        time.sleep(STEP_S)
        response.success, response.message = True, f"step {STEP_S} s"
        return response

    def status(self, request, response):
        response.success = self.active
        response.message = f"{self.computed} sequences" if self.active else "not active"
        return response


def main():
    rclpy.init()
    node = Sequencer()
    executor = MultiThreadedExecutor()
    executor.add_node(node)
    try:
        executor.spin()
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
