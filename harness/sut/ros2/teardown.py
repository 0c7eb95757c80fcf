"""How a bench ROS 2 process (rclpy) ends leaving as little of Fast DDS's shared memory as it can.

Under ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST rmw_fastrtps gives every participant the shared-memory
transport, whose files (/dev/shm/fastrtps_* on Jazzy, fastdds_* on Kilted: a segment, its ports,
their lock files and semaphores) are removed when the participant is deleted, that is once the
process's nodes, their action servers and clients included, are destroyed and its context shut
down. The bench's processes end with os._exit (rclpy's C++ destructors can abort when an executor
thread is still inside rcl), so they call `release` first: measured, a node that os._exit()s
without it leaves its segment, its ports and their semaphores. A process killed outright (and, on
Jazzy, now and then a released one) leaves them anyway: environment.sweep_dead_segments removes
those once their owner is gone.
"""
from __future__ import annotations

import contextlib

import rclpy


def release(nodes, executor=None, timeout_s: float = 0.5) -> None:
    """Stops the executor (if any), destroys the nodes with their waitables, and shuts down and
    destroys the default context."""
    if executor is not None:
        executor.shutdown(timeout_sec=timeout_s)
    for node in nodes:
        with contextlib.suppress(Exception):  # destroyed already, or its context shut down first
            for waitable in list(node.waitables):  # action servers and clients: not destroyed with the node
                waitable.destroy()
            node.destroy_node()
    rclpy.try_shutdown()
    rclpy.utilities.get_default_context().destroy()
