"""The message classes of `untimely_msgs/Request`, the one generic action every mapped service uses.

Debian ships ROS 1's Python libraries but no catkin workspace to build message packages in, so
the classes are generated when this module is imported, from the definitions below, by genpy's
dynamic generator (the one rosbag uses for types it has no package for). Both ends (the Dala node
and the adapter) generate them from the same text, so their MD5 sums agree on the wire.
The seven messages are what `genaction.py` derives from an .action file.
"""
from __future__ import annotations

import genpy.dynamic
from actionlib_msgs.msg import GoalID, GoalStatus
from std_msgs.msg import Header

PACKAGE = "untimely_msgs"
SEPARATOR = "\n" + "=" * 80 + "\n"

# Request.action: goal / result / feedback.
GOAL = "string service    # the interface's service name, e.g. GotoPosition\nstring args_json  # its arguments, a JSON object of strings\n"
RESULT = "string code       # a reply code of the interface's catalogue, or free text\n"
FEEDBACK = "string phase      # what the activity is doing, e.g. running\n"

DEFINITIONS = {
    "RequestAction": "RequestActionGoal action_goal\nRequestActionResult action_result\nRequestActionFeedback action_feedback\n",
    "RequestActionGoal": "Header header\nactionlib_msgs/GoalID goal_id\nRequestGoal goal\n",
    "RequestActionResult": "Header header\nactionlib_msgs/GoalStatus status\nRequestResult result\n",
    "RequestActionFeedback": "Header header\nactionlib_msgs/GoalStatus status\nRequestFeedback feedback\n",
    "RequestGoal": GOAL,
    "RequestResult": RESULT,
    "RequestFeedback": FEEDBACK,
}


def _own_text(message_class) -> str:
    """A message's own definition, without the dependencies its _full_text appends."""
    return message_class._full_text.split(SEPARATOR)[0]


def _concatenated() -> str:
    """The `gendeps --cat` form genpy.dynamic reads: the core type, then every dependency."""
    sections = [DEFINITIONS["RequestAction"]]
    for name, text in DEFINITIONS.items():
        if name != "RequestAction":
            sections.append(f"MSG: {PACKAGE}/{name}\n{text}")
    for full_name, message_class in (("std_msgs/Header", Header), ("actionlib_msgs/GoalID", GoalID),
                                     ("actionlib_msgs/GoalStatus", GoalStatus)):
        sections.append(f"MSG: {full_name}\n{_own_text(message_class)}")
    return SEPARATOR.join(sections)


_classes = genpy.dynamic.generate_dynamic(f"{PACKAGE}/RequestAction", _concatenated())
RequestAction = _classes[f"{PACKAGE}/RequestAction"]
RequestGoal = _classes[f"{PACKAGE}/RequestGoal"]
RequestResult = _classes[f"{PACKAGE}/RequestResult"]
RequestFeedback = _classes[f"{PACKAGE}/RequestFeedback"]
