"""What the ROS 1 adapter (harness/sut/ros/) and the ROS 2 one (harness/sut/ros2/) share, and the bag
readers (harness/sut/bags/) with them (docs/architecture.md): the mapping file and its routes, the
bridge from requests to goals and the reply rules, the launcher's side of `untimely/1` on stdio, and
the Dala nodes' common arguments. Nothing here imports a ROS client library: it runs under the
bench's interpreter as under either distro's.
"""
