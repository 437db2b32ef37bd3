"""Python overhead against the command line: the same Campbell diagram and cascade run by
the `whirl` binary and by the Python package, each in a process of its own, CPU time (user
+ sys of the process and its threads) and wall time, the median of a few runs.

    .venv/bin/python crates/whirl-py/bench/overhead.py [--runs 3] [--whirl target/debug/whirl]

The binary also draws its plots (PNG and SVG) and writes its CSV files, which the Python
calls do not; the Python process also imports numpy (and the package). Both are listed:
the difference is what a user of each pays for the same numbers.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
MODEL = ROOT / "examples" / "reference_rotor.toml"

JOBS = {
    "campbell": (
        ["campbell", str(MODEL), "--speeds", "0:800Hz:161"],
        f"import whirl; whirl.campbell({str(MODEL)!r}, '0:800Hz:161')",
    ),
    "cascade": (
        # --restart: the binary keeps finished speeds beside --out and would resume them.
        ["cascade", str(MODEL), "--speeds", "100Hz:400Hz:16", "--no-refine", "--max-records", "4", "--restart"],
        f"import whirl; whirl.cascade({str(MODEL)!r}, '100Hz:400Hz:16', no_refine=True, "
        "max_records=4, progress=False)",
    ),
}


def measure(command: list[str]) -> tuple[float, float]:
    """(CPU s, wall s) of one process running `command`."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, cwd=ROOT)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--whirl", default=str(ROOT / "target" / "debug" / "whirl"))
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as out:
        for job, (cli, python) in JOBS.items():
            rows = {}
            for name, command in (
                ("cli", [args.whirl, *cli, "--out", os.path.join(out, job)]),
                ("python", [sys.executable, "-c", python]),
            ):
                runs = [measure(command) for _ in range(args.runs)]
                rows[name] = (statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs))
            (c_cpu, c_wall), (p_cpu, p_wall) = rows["cli"], rows["python"]
            print(
                f"{job:9s} CPU: CLI {c_cpu:6.2f} s, Python {p_cpu:6.2f} s ({100 * (p_cpu / c_cpu - 1):+5.1f} %); "
                f"wall: CLI {c_wall:6.2f} s, Python {p_wall:6.2f} s"
            )
    imports = measure([sys.executable, "-c", "import whirl"])
    print(f"import whirl alone: CPU {imports[0]:.2f} s, wall {imports[1]:.2f} s")
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
