"""map_markers' CPU per tick on a map of 10,000 regions (on demand, not in the suite).

    python test/benchmarks/bench_map_markers.py [regions]

Peers in the same run, on the same map (a grid of square regions) and the same controller state:

- *before*: what every tick did until the static map was split off — build the shapes of every region
  (outline, triangulated fill, label), a marker for each and serialize the whole array;
- *after*: what a tick does now (``MarkerBuilder.state_array``: DELETEALL, the highlighted regions,
  the controller's text, serialized); the static map is built and serialized once at start-up
  (reported too).

CPU time (``time.process_time``) per tick, medians; figures go to docs/BENCHMARKS.md by hand.
"""
from __future__ import annotations

import io
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

import genpy

from ltl_stack.ros.markers import MarkerBuilder, StateView
from ltl_stack.runtime.propositions.regions import RegionMap

CONFIG = {"draw_regions": True, "frame_id": "map", "region_suffix": "_rc", "label": "", "text_row": 0}


def grid_map(count: int) -> RegionMap:
    side = int(count ** 0.5 + 0.999)
    items = [{"name": f"r{i}", "type": "poly", "position": [0, 0],
              "points": [[i % side, i // side], [i % side + 1, i // side], [i % side + 1, i // side + 1],
                         [i % side, i // side + 1]]} for i in range(count)]
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "grid.regions"
        path.write_text("Regions: # JSON\n" + json.dumps(items) + "\n")
        return RegionMap.load(path)


def cpu(work, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.process_time()
        work()
        times.append(time.process_time() - start)
    return statistics.median(times)


def serialized(array) -> int:
    buffer = io.BytesIO()
    array.serialize(buffer)
    return buffer.tell()


def main(count: int = 10_000) -> None:
    start = time.process_time()
    regions = grid_map(count)
    load = time.process_time() - start
    view = StateView(12, 1, "normal", {"r17_rc": True, "person": False}, {"r18": True, "camera": True})
    stamp = genpy.Time(0)

    def before() -> None:  # every tick rebuilt every region's shapes and markers, and sent them all
        everything = MarkerBuilder(regions, CONFIG)
        serialized(everything.static_array(stamp))
        serialized(everything.state_array(view, None, stamp))

    start = time.process_time()
    builder = MarkerBuilder(regions, CONFIG)
    static_bytes = serialized(builder.static_array(stamp))
    once = time.process_time() - start
    after = cpu(lambda: serialized(builder.state_array(view, None, stamp)), 50)
    old = cpu(before, 3)
    tick_bytes = serialized(builder.state_array(view, None, stamp))
    print(f"map of {count} regions: read and validated in {load:.2f} s CPU")
    print(f"static map, once at start-up: {once:.2f} s CPU, {static_bytes / 1e6:.1f} MB")
    print(f"per tick before: {old * 1000:.0f} ms CPU (median of 3); after: {after * 1000:.2f} ms CPU "
          f"(median of 50), {tick_bytes} bytes; ratio {old / after:.0f}x")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10_000)
