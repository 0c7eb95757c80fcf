"""What stands in for or talks to a system under test (docs/architecture.md): the simulated layer
and Dala's behaviour, the executive that plays a script on a SUT, the external-process runner,
the adapters the bench ships (ROS 1, ROS 2, the simulator out of process), SUT definitions, and
the reading of ROS bags into rows."""
