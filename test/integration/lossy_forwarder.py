"""A user-space link with delay and loss between two interfaces of one namespace (this kernel has
no sch_netem): every Ethernet frame read on one side is written to the other after DELAY ± JITTER
seconds, or dropped with probability LOSS. Run inside the namespace:
``python lossy_forwarder.py IF_A IF_B DELAY JITTER LOSS``; it prints "up" once both sides are open.
"""
from __future__ import annotations

import heapq
import random
import socket
import sys
import threading
import time

ETH_P_ALL = 0x0003
PACKET_OUTGOING = 4


def main() -> None:
    a, b, delay, jitter, loss = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:6])
    socks = {}
    for name in (a, b):
        s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETH_P_ALL))
        s.bind((name, 0))
        socks[name] = s
    queue: list = []
    cond = threading.Condition()
    seq = 0

    def read(src: str, dst: str) -> None:
        nonlocal seq
        sock = socks[src]
        while True:
            frame, address = sock.recvfrom(65535)
            if address[2] == PACKET_OUTGOING or random.random() < loss:
                continue  # our own writes, or lost
            due = time.monotonic() + max(0.0, random.uniform(delay - jitter, delay + jitter))
            with cond:
                seq += 1
                heapq.heappush(queue, (due, seq, dst, frame))
                cond.notify()

    def write() -> None:
        while True:
            with cond:
                while not queue or queue[0][0] > time.monotonic():
                    cond.wait(None if not queue else queue[0][0] - time.monotonic())
                _, _, dst, frame = heapq.heappop(queue)
            try:
                socks[dst].send(frame)
            except OSError:
                pass

    for src, dst in ((a, b), (b, a)):
        threading.Thread(target=read, args=(src, dst), daemon=True).start()
    print("up", flush=True)
    write()


if __name__ == "__main__":
    main()
