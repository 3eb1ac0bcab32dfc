"""The Python layer's overhead on Example 3.2: wall time of reading the scene file, solving
and producing the history, against `tsm-contact solve FILE --json OUT` (a process that does the
same and writes the history), median of 10 runs each, in one process on one machine.

    python examples/python/overhead.py [--bin target/release/tsm-contact] [--runs 10]
"""

import argparse
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import tsm_contact as tc

ROOT = Path(__file__).resolve().parents[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=str(ROOT / "target" / "release" / "tsm-contact"))
    ap.add_argument("--scene", default=str(ROOT / "assets" / "scenes" / "example_3_2.ron"))
    ap.add_argument("--runs", type=int, default=10)
    args = ap.parse_args()
    out = Path(tempfile.mkdtemp()) / "h.json"

    def cli():
        t = time.perf_counter()
        subprocess.run([args.bin, "solve", args.scene, "--json", str(out)], check=True, capture_output=True)
        return time.perf_counter() - t

    def python(save):
        t = time.perf_counter()
        h = tc.solve(tc.Scene.from_file(args.scene))
        if save:
            h.save(out)
        return time.perf_counter() - t

    for f in (cli, lambda: python(False), lambda: python(True)):
        f()  # warm the file cache and the allocator
    rows = [
        ("tsm-contact solve --json (process)", [cli() for _ in range(args.runs)]),
        ("Python: Scene.from_file + solve", [python(False) for _ in range(args.runs)]),
        ("Python: Scene.from_file + solve + History.save", [python(True) for _ in range(args.runs)]),
    ]
    base = statistics.median(rows[0][1])
    print(f"{Path(args.scene).name}, median of {args.runs} runs")
    for name, times in rows:
        m = statistics.median(times)
        print(f"{name:50} {m * 1e3:8.1f} ms  ({(m / base - 1) * 100:+.1f} % against the CLI)")


if __name__ == "__main__":
    main()
