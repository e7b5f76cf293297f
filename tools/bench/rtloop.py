#!/usr/bin/env python3
"""The real-time loop benchmark (issue 13): runs build/host/sim/rtloop, the
paper-000 drive on the emulated DAC/ADC board paced at 10 kHz by the Linux
real-time loop (SCHED_FIFO, locked memory, absolute clock_nanosleep
deadlines; hal/backends/board/rt_loop.h), for N seconds, and writes JSON to
stdout: overruns, jitter_p999_us, jitter_max_us, jitter_mean_us,
step_time_mean_us, step_time_max_us, whether SCHED_FIFO and mlockall were
granted, and the machine (CPU model, cores, kernel).

    tools/bench/rtloop.py [--seconds N] [--rtloop PATH] [--scenario FILE]

Without permission for real-time scheduling the loop says so (stderr) and
runs anyway; sched_fifo is then false. Exit 1 if the loop did not run."""
import argparse
import json
import os
import platform
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def cpu_model():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "?"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--rtloop", default=os.path.join(ROOT, "build", "host", "sim", "rtloop"))
    ap.add_argument("--scenario", default=os.path.join(ROOT, "sim", "scenarios", "paper000_experiment.toml"),
                    help="scenario (default: the README's main job, paper 000's experiment)")
    a = ap.parse_args()
    if not (a.seconds > 0):
        ap.error("--seconds must be > 0")
    if not os.path.exists(a.rtloop):
        print(f"rtloop.py: {a.rtloop} not built (cmake --build --preset host)", file=sys.stderr)
        return 1
    cmd = [a.rtloop, "--seconds", str(a.seconds), "--scenario", a.scenario]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stderr, file=sys.stderr)
        return 1
    res = json.loads(r.stdout)
    res["machine"] = {"cpu": cpu_model(), "cores": os.cpu_count(), "kernel": platform.release()}
    if r.stderr.strip():
        print(r.stderr.strip(), file=sys.stderr)
    print(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
