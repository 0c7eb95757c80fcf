"""ROS 2 (Jazzy, Kilted) from PyPI wheels: each distro's environment, the project's interface
package `untimely_msgs` and its build, and the recorder of a run's bag (docs/ros2.md)."""
