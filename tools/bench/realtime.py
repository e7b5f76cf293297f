#!/usr/bin/env python3
"""How fast the simulator runs paper 000's experiment. A benchmark, not a test.

Runs build/host/sim/motorsim on sim/scenarios/paper000_experiment.toml,
pinned to one CPU (taskset) when possible, and reports:

  * realtime_factor: the simulator's own figure, read from its metrics JSON
    (--metrics-out), median of --runs runs;
  * the wall time of a metrics-only run (--metrics-out without --out: no
    CSV, no PNG), of a whole run writing CSV + PNG (--out DIR), and of a
    whole run with --no-plot (CSV only) when motorsim has that flag; medians
    of --runs runs;
  * with --variants N: N seeds as metrics-only runs, --jobs J at a time,
    total wall time and time per variant (a user running a thousand variants
    should wait seconds, not minutes). With pinning, job slot k runs on the
    k-th CPU this process may use from the chosen one on (round robin), so
    each run still has one core.

Prints a small table, then one JSON line (also written to --json-out FILE).
Standard library only. Exit codes: 0 ok, 1 a motorsim run failed or its
metrics lack realtime_factor, 2 usage error (bad arguments, missing binary
or scenario).
"""
from __future__ import annotations

import argparse
import json
import os
import queue
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))  # the toolbox, tools/lib
from lib import motorsim  # noqa: E402
DEFAULT_BINARY = ROOT / "build" / "host" / "sim" / "motorsim"
DEFAULT_SCENARIO = ROOT / "sim" / "scenarios" / "paper000_experiment.toml"
PROG = "realtime.py"


class BenchError(Exception):
    """A failure with a message for the user and an exit code."""

    def __init__(self, message: str, code: int = 1):
        super().__init__(message)
        self.code = code


def positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}")
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
    return value


def non_negative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}")
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {value}")
    return value


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(
        prog=PROG,
        description="Benchmark motorsim on paper 000's experiment: realtime factor "
        "(median of --runs runs, pinned to one CPU) and wall times.",
    )
    p.add_argument("--binary", type=Path, default=DEFAULT_BINARY,
                   help="motorsim executable (default: build/host/sim/motorsim)")
    p.add_argument("--scenario", type=Path, default=DEFAULT_SCENARIO,
                   help="scenario TOML (default: sim/scenarios/paper000_experiment.toml)")
    p.add_argument("--runs", type=positive_int, default=5,
                   help="runs per measurement, the median is reported (default: 5)")
    p.add_argument("--variants", type=non_negative_int, default=0, metavar="N",
                   help="also run N seeds (metrics only) and report the total wall time")
    p.add_argument("--jobs", type=positive_int, default=1, metavar="J",
                   help="--variants runs at a time, each pinned to its own CPU when "
                   "pinning (default: 1)")
    p.add_argument("--seed-base", type=non_negative_int, default=1,
                   help="first seed of --variants (default: 1)")
    p.add_argument("--no-full", action="store_true",
                   help="skip the whole-run (--out: CSV + PNG) timings")
    pin = p.add_mutually_exclusive_group()
    pin.add_argument("--cpu", type=non_negative_int,
                     help="CPU to pin to (default: the first one this process may use)")
    pin.add_argument("--no-pin", action="store_true", help="do not pin to one CPU")
    p.add_argument("--timeout", type=positive_int, default=600,
                   help="seconds before one motorsim run counts as failed (default: 600)")
    p.add_argument("--json-out", type=Path, help="also write the JSON line to this file")
    p.add_argument("--keep", type=Path, metavar="DIR",
                   help="keep the runs' outputs in DIR (default: a temporary directory)")
    return p.parse_args(argv)


def check_inputs(args: argparse.Namespace) -> None:
    # Absolute, so that "motorsim" in the current directory is not looked up in PATH.
    args.binary = Path(os.path.abspath(args.binary))
    args.scenario = Path(os.path.abspath(args.scenario))
    binary = args.binary
    if not binary.is_file():
        raise BenchError(
            f"motorsim binary not found: {binary}\n"
            "  build it first: cmake --preset host && cmake --build --preset host\n"
            "  (or ./scripts/run_paper000.sh), or pass --binary PATH", 2)
    if not os.access(binary, os.X_OK):
        raise BenchError(f"motorsim binary is not executable: {binary}", 2)
    if not args.scenario.is_file():
        raise BenchError(f"scenario not found: {args.scenario}", 2)


def allowed_cpus() -> list[int]:
    try:
        return sorted(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return [0]


def pin_prefix(args: argparse.Namespace) -> tuple[list[str], int | None, str]:
    """Command prefix that pins to one CPU, the CPU, and a note for the table."""
    if args.no_pin:
        return [], None, "not pinned (--no-pin)"
    taskset = shutil.which("taskset")
    if taskset is None:
        return [], None, "not pinned (no taskset)"
    cpu = args.cpu if args.cpu is not None else allowed_cpus()[0]
    probe = subprocess.run([taskset, "-c", str(cpu), "true"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if probe.returncode != 0:
        if args.cpu is not None:
            raise BenchError(f"cannot pin to CPU {cpu}: {probe.stderr.strip()}", 2)
        return [], None, f"not pinned (taskset -c {cpu} failed)"
    return [taskset, "-c", str(cpu)], cpu, f"pinned to CPU {cpu}"


def find_key(obj, key: str):
    """First value of key anywhere in a nested JSON object, else None."""
    if isinstance(obj, dict):
        if key in obj:
            return obj[key]
        children = obj.values()
    elif isinstance(obj, list):
        children = obj
    else:
        return None
    for child in children:
        found = find_key(child, key)
        if found is not None:
            return found
    return None


def slot_prefixes(prefix: list[str], cpu: int | None, jobs: int) -> list[list[str]]:
    """One command prefix per job slot: slot k pinned to the k-th allowed CPU
    from cpu on (round robin); unpinned if prefix is."""
    if not prefix or cpu is None or jobs == 1:
        return [prefix] * jobs
    cpus = allowed_cpus()
    if cpu not in cpus:
        cpus = sorted(set(cpus) | {cpu})
    start = cpus.index(cpu)
    return [prefix[:-1] + [str(cpus[(start + k) % len(cpus)])] for k in range(jobs)]


class Runner:
    def __init__(self, args: argparse.Namespace, prefix: list[str], workdir: Path):
        self.args = args
        self.prefix = prefix
        self.workdir = workdir
        self.count = 0
        self._lock = threading.Lock()

    def run(self, extra: list[str], prefix: list[str] | None = None, seed: int | None = None,
            metrics: bool = False):
        """Runs motorsim once (tools/lib/motorsim.py) with extra arguments;
        returns the wall time of the process in s, and with metrics=True
        (a metrics-only run) the metrics too. Thread-safe (the variants run
        from a thread pool)."""
        prefix = self.prefix if prefix is None else prefix
        r = motorsim.run(self.args.binary, self.args.scenario, raw=not metrics, extra=extra, prefix=prefix,
                         seed=seed, timeout=self.args.timeout, ok=None)
        if r.status is None:
            raise BenchError(f"motorsim {r.stderr}: {' '.join(r.cmd)}")
        if r.status != 0:
            tail = "\n".join(r.stderr.strip().splitlines()[-10:])
            raise BenchError(f"motorsim failed (exit {r.status}): {' '.join(r.cmd)}\n{tail}")
        if metrics and r.metrics is None:
            raise BenchError(f"motorsim wrote no metrics (--metrics-out), or not JSON: {' '.join(r.cmd)}")
        with self._lock:
            self.count += 1
        return (r.wall_s, r.metrics) if metrics else r.wall_s

    def metrics_run(self, tag: str, seed: int | None = None,
                    prefix: list[str] | None = None) -> tuple[float, dict]:
        """A metrics-only run: --metrics-out without --out (no CSV, no PNG)."""
        return self.run([], prefix, seed=seed, metrics=True)


def supports_flag(binary: Path, flag: str) -> bool:
    try:
        proc = subprocess.run([str(binary), "--help"], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return flag in proc.stdout


def stats(values: list[float]) -> dict:
    return {"median": round(statistics.median(values), 6), "min": min(values),
            "max": max(values)}


def rel(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def bench(args: argparse.Namespace, workdir: Path) -> dict:
    check_inputs(args)
    prefix, cpu, pin_note = pin_prefix(args)
    runner = Runner(args, prefix, workdir)
    result: dict = {
        "bench": "realtime",
        "binary": rel(args.binary),
        "scenario": rel(args.scenario),
        "runs": args.runs,
        "pinned_cpu": cpu,
    }
    rows: list[tuple[str, str, str, str]] = []

    def fmt_s(v: float) -> str:
        return f"{v:.3f} s"

    # 1. realtime factor, as motorsim measures it, and the metrics-only wall time.
    rfs, walls = [], []
    for i in range(args.runs):
        wall, metrics = runner.metrics_run(f"rt{i}")
        rf = find_key(metrics, "realtime_factor")
        if not isinstance(rf, (int, float)) or isinstance(rf, bool):
            raise BenchError(f"no numeric realtime_factor in motorsim's metrics JSON "
                             f"({workdir / f'metrics_rt{i}.json'})")
        rfs.append(round(float(rf), 6))
        walls.append(wall)
    s = stats(rfs)
    rows.append(("realtime_factor (motorsim metrics)", f"{s['median']:.1f}x",
                 f"{s['min']:.1f}x", f"{s['max']:.1f}x"))
    result["realtime_factor_median"] = s["median"]
    result["realtime_factor_runs"] = rfs
    s = stats(walls)
    rows.append(("wall: metrics only", fmt_s(s["median"]), fmt_s(s["min"]), fmt_s(s["max"])))
    result["wall_metrics_only_s_median"] = s["median"]

    # 2. whole runs: CSV + PNG, and CSV only when motorsim has --no-plot.
    result["wall_full_s_median"] = None
    result["wall_full_no_plot_s_median"] = None
    if not args.no_full:
        variants = [("wall: --out (CSV + PNG)", "wall_full_s_median", [])]
        if supports_flag(args.binary, "--no-plot"):
            variants.append(("wall: --out --no-plot (CSV)", "wall_full_no_plot_s_median",
                             ["--no-plot"]))
        else:
            rows.append(("wall: --out --no-plot (CSV)", "n/a", "", ""))
        for label, key, flags in variants:
            walls = []
            for i in range(args.runs):
                out = workdir / f"{key}_{i}"
                walls.append(runner.run(["--out", str(out)] + flags))
            s = stats(walls)
            rows.append((label, fmt_s(s["median"]), fmt_s(s["min"]), fmt_s(s["max"])))
            result[key] = s["median"]

    # 3. many variants, metrics only, --jobs at a time.
    result["variants"] = args.variants
    result["variants_jobs"] = args.jobs
    result["variants_total_s"] = None
    result["variants_per_variant_s"] = None
    result["variants_run_wall_s_median"] = None
    variants_note = ""
    if args.variants:
        prefixes = slot_prefixes(prefix, cpu, args.jobs)
        slots: queue.Queue = queue.Queue()
        for k in range(args.jobs):
            slots.put(k)

        def variant(seed: int) -> float:
            slot = slots.get()
            try:
                return runner.metrics_run(f"seed{seed}", seed=seed, prefix=prefixes[slot])[0]
            finally:
                slots.put(slot)

        seeds = range(args.seed_base, args.seed_base + args.variants)
        t0 = time.perf_counter()
        if args.jobs == 1:
            walls = [variant(s) for s in seeds]
        else:
            pool = ThreadPoolExecutor(max_workers=args.jobs)
            try:
                walls = list(pool.map(variant, seeds))
            finally:  # on a failure, start no more runs
                pool.shutdown(wait=True, cancel_futures=True)
        total = time.perf_counter() - t0
        result["variants_total_s"] = round(total, 6)
        result["variants_per_variant_s"] = round(total / args.variants, 6)
        result["variants_run_wall_s_median"] = round(statistics.median(walls), 6)
        pinned = sorted({p[-1] for p in prefixes if p})
        variants_note = (f"pinned to CPU {', '.join(pinned)}" if pinned else "not pinned")

    print(f"motorsim benchmark: {result['binary']} --scenario {result['scenario']}")
    print(f"{pin_note}, {args.runs} run(s) per measurement, {runner.count} motorsim runs in all")
    header = ("measurement", "median", "min", "max")
    widths = [max(len(r[c]) for r in rows + [header]) for c in range(4)]
    for r in [header] + rows:
        print(f"  {r[0]:<{widths[0]}}  {r[1]:>{widths[1]}}  {r[2]:>{widths[2]}}  {r[3]:>{widths[3]}}"
              .rstrip())
    if args.variants:
        total = result["variants_total_s"]
        print(f"variants: {args.variants} seeds (metrics only), {args.jobs} at a time "
              f"({variants_note}): {total:.3f} s in all, {1e3 * total / args.variants:.1f} ms per "
              f"variant, {1e3 * result['variants_run_wall_s_median']:.1f} ms per run (median wall)")
    return result


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        if args.keep is not None:
            args.keep.mkdir(parents=True, exist_ok=True)
            result = bench(args, args.keep)
        else:
            with tempfile.TemporaryDirectory(prefix="mc_bench_") as tmp:
                result = bench(args, Path(tmp))
    except BenchError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return e.code
    line = json.dumps(result, sort_keys=True)
    print(line)
    if args.json_out is not None:
        args.json_out.write_text(line + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
