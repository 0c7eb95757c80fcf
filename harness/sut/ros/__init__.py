"""A ROS 1 system under test behind the `untimely/1` protocol (docs/reference/protocol.md; docs/ros.md).

launcher.py starts a rosmaster and the SUT's node and runs adapter.py on stdio; adapter.py is
generic (it reads the interface from the bench's hello and the mapping file, ros.toml); only
dala_node.py knows the Dala layer. Everything here runs under the system Python that Debian's
ROS packages import under (the `.venv-ros` venv), not the bench's interpreter.
"""
