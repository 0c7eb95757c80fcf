#!/usr/bin/env python3
"""A lifecycle arm controller, written the way ROS 2 users write one (not for the bench).

/arm (rclpy.lifecycle):
- action ~/move (test_msgs/action/Fibonacci): a trajectory of `order` waypoints, STEP_S each, each
  waypoint sent as feedback; a new move preempts the running one (it ends aborted), a cancel ends
  it canceled, deactivate or cleanup ends it aborted;
- action ~/grip (test_msgs/action/Fibonacci): closes the gripper in `order` steps; rejected while
  the arm moves (the grip interlock);
- service ~/home (std_srvs/srv/Trigger): answers whether the arm is at home;
- lifecycle services ~/change_state, ~/get_state: configure, activate, deactivate, cleanup, shutdown.

Goals are rejected unless the node is active. Four defects, off by default, are switched on by
the environment variable ARM_DEFECTS (a comma-separated list; README.md):
- `deactivate`: deactivating mid-trajectory leaves the goal running (ros2_controllers#1517);
- `cancel`: a cancel is accepted but the goal runs on to SUCCEEDED;
- `parallel`: a new move runs beside the running one (no preemption);
- `grip`: the interlock reads a flag that the motion thread sets only after its first waypoint.

    python3 arm_controller.py   # in a shell where ROS 2 is sourced
"""
import os
import threading
import time

import rclpy
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from std_srvs.srv import Trigger
from test_msgs.action import Fibonacci

STEP_S = 0.2
DEFECTS = {d.strip() for d in os.environ.get("ARM_DEFECTS", "").split(",") if d.strip()}


class Arm(LifecycleNode):
    def __init__(self):
        super().__init__("arm")
        self.active = False
        self.lock = threading.Lock()
        self.moves = []  # goal handles of the moves executing
        self.moving = False  # what the grip interlock reads
        self.stopping = threading.Event()  # deactivate or cleanup: end the running goals
        group = ReentrantCallbackGroup()
        ActionServer(self, Fibonacci, "~/move", self.move, goal_callback=self.accept_goal,
                     handle_accepted_callback=self.preempt, cancel_callback=self.accept_cancel,
                     callback_group=group)
        ActionServer(self, Fibonacci, "~/grip", self.grip, goal_callback=self.accept_grip,
                     cancel_callback=self.accept_cancel, callback_group=group)
        self.create_service(Trigger, "~/home", self.home, callback_group=group)

    # -- lifecycle -----------------------------------------------------------------------------
    def on_configure(self, state):
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state):
        self.stopping.clear()
        self.active = True
        return super().on_activate(state)

    def on_deactivate(self, state):
        self.active = False
        if "deactivate" not in DEFECTS:
            self.stopping.set()
        return super().on_deactivate(state)

    def on_cleanup(self, state):
        self.stopping.set()
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state):
        self.active = False
        self.stopping.set()
        return TransitionCallbackReturn.SUCCESS

    # -- move ----------------------------------------------------------------------------------
    def accept_goal(self, goal):
        return GoalResponse.ACCEPT if self.active and 0 < goal.order <= 50 else GoalResponse.REJECT

    def preempt(self, goal_handle):
        """A new move replaces the running one: the old one is told to stop before the new one runs."""
        with self.lock:
            if "parallel" not in DEFECTS:
                for running in self.moves:
                    running.preempted = True
            goal_handle.preempted = False
            self.moves.append(goal_handle)
            if "grip" not in DEFECTS:
                self.moving = True
        goal_handle.execute()

    def accept_cancel(self, goal_handle):
        return CancelResponse.ACCEPT

    def move(self, goal_handle):
        try:
            while "parallel" not in DEFECTS and self.moves[0] is not goal_handle:
                time.sleep(0.01)  # the preempted move ends first
            sequence = [0, 1]
            for step in range(goal_handle.request.order):
                if getattr(goal_handle, "preempted", False) or self.stopping.is_set():
                    goal_handle.abort()
                    return Fibonacci.Result(sequence=sequence)
                if goal_handle.is_cancel_requested and "cancel" not in DEFECTS:
                    goal_handle.canceled()
                    return Fibonacci.Result(sequence=sequence)
                time.sleep(STEP_S)
                self.moving = True  # the motion thread's own record, set once a waypoint is reached
                sequence.append(sequence[-1] + sequence[-2])
                goal_handle.publish_feedback(Fibonacci.Feedback(sequence=sequence))
            goal_handle.succeed()
            return Fibonacci.Result(sequence=sequence)
        finally:
            with self.lock:
                self.moves.remove(goal_handle)
                self.moving = bool(self.moves)

    # -- grip ----------------------------------------------------------------------------------
    def accept_grip(self, goal):
        return GoalResponse.ACCEPT if self.active and not self.moving and 0 < goal.order <= 10 else GoalResponse.REJECT

    def grip(self, goal_handle):
        for _ in range(goal_handle.request.order):
            time.sleep(STEP_S / 2)
        goal_handle.succeed()
        return Fibonacci.Result(sequence=[goal_handle.request.order])

    def home(self, request, response):
        response.success = not self.moving
        response.message = "at home" if response.success else "moving"
        return response


def main():
    rclpy.init()
    node = Arm()
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
