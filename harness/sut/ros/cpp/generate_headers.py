"""The C++ headers of untimely_msgs/Request for the C++ node, generated from Request.action.

Debian ships gencpp but neither catkin nor the .msg files of std_msgs and actionlib_msgs; the
seven messages of the action and the text of their dependencies come from messages.py (the same
text the Python side builds its classes from, so the MD5 sums agree), written as .msg files into
OUT/msg, and gencpp writes OUT/include/untimely_msgs/*.h. Run by `make ros-cpp` under /usr/bin/python3.

    python3 -m harness.sut.ros.cpp.generate_headers OUT
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from harness.sut.ros.messages import GENERIC_DEFINITION, action_sections, dependencies
from harness.sut.roscommon.routes import GENERIC_TYPE

GEN_CPP = "/usr/lib/gencpp/gen_cpp.py"
TEMPLATES = "/usr/share/gencpp"


def main(out: Path) -> None:
    package = GENERIC_TYPE.split("/")[0]
    own = action_sections(GENERIC_TYPE, GENERIC_DEFINITION.read_text())
    files = {f"{package}/{name}": text for name, text in own.items()}
    files.update(dependencies(package, own.values()))
    for full_type, text in files.items():
        path = out / "msg" / f"{full_type}.msg"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    search = [arg for p in sorted({t.split("/")[0] for t in files}) for arg in ("-I", f"{p}:{out / 'msg' / p}")]
    for name in own:
        subprocess.run([sys.executable, GEN_CPP, str(out / "msg" / package / f"{name}.msg"), "-p", package,
                        "-o", str(out / "include" / package), "-e", TEMPLATES, *search], check=True)


if __name__ == "__main__":
    main(Path(sys.argv[1]))
