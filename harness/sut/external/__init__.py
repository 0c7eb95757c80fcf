"""External SUTs over untimely/1: the wire format, the stdio/TCP channel, the wall-clock runner, SUT definitions."""
