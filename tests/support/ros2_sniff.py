"""Counts the packets on a network interface until SIGTERM, then prints them as JSON (the ROS 2
confinement test runs it in its network namespace; it needs root for the raw AF_PACKET socket).

    python tests/support/ros2_sniff.py IFACE    # prints "ready" once bound; on SIGTERM {"packets": N, "rtps": M}

RTPS packets (UDP payloads that start with b"RTPS") are DDS's, so ROS 2's, traffic.
"""
import json
import signal
import socket
import sys

ETH_P_ALL, ETH_HEADER, UDP = 0x0003, 14, 17


def rtps(frame: bytes) -> bool:
    """An IPv4 UDP frame whose payload is an RTPS message."""
    if frame[12:14] != b"\x08\x00" or frame[ETH_HEADER + 9] != UDP:
        return False
    payload = ETH_HEADER + (frame[ETH_HEADER] & 0x0F) * 4 + 8
    return frame[payload:payload + 4] == b"RTPS"


def main(interface: str) -> None:
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(True))
    sniffer = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETH_P_ALL))
    sniffer.bind((interface, 0))
    sniffer.settimeout(0.05)
    counts = {"packets": 0, "rtps": 0}
    print("ready", flush=True)
    while not stop:
        try:
            frame = sniffer.recv(65535)
        except (TimeoutError, InterruptedError):
            continue
        counts["packets"] += 1
        counts["rtps"] += rtps(frame)
    print(json.dumps(counts), flush=True)


if __name__ == "__main__":
    main(sys.argv[1])
