#!/usr/bin/env python3
"""Monte Carlo sweep: runs a motorsim scenario N times with the plant's
parameters drawn from stated spreads while the drive keeps its nominal model.

    .venv/bin/python tools/sweep.py --scenario FILE --runs N --spread-pct P
        [--spread R=20,L=20,K=20] [--j-range 0.5,2] [--dead-time-pct D] [--jobs J] [--seed S]
        [--keep DIR] [--plot FILE.png [--plot-axes R,J]] [--dask ADDRESS]

What one run is
  A variant of the scenario: [motor] overrides that hold the drawn plant
  values, and a [drive_model] table that holds what the drive is designed
  for, which stays the scenario's nominal model: each key of the scenario's
  own [drive_model] if it has one, else the plant value of the scenario as
  written (the motor file plus the scenario's [motor] overrides). For the
  shipped scenarios that is the motor file's values. Everything else of the
  scenario is kept (including [design] identify_rl and [expect]). Each run
  also has its own noise seed (--seed of motorsim).

  motorsim runs it metrics-only (--metrics-out without --out) and judges it
  against the scenario's [expect] table (no --no-expect): exit 0 is a pass;
  3 (the drive latched a fault), 4 (a metric missed its [expect] bound) and
  5 (the plant diverged) are fails, with the reason motorsim printed; any
  other exit status (1, 2, a signal, a time-out) is an error of the tool.

The distributions (factor = plant value / nominal value, independent per run
and per parameter)
  R  R_ohm                                  uniform in [1 - p/100, 1 + p/100]
  L  L_H (stepper2); L_d_H and L_q_H (pmsm3, one factor for both: the
     saliency ratio is kept)                uniform in [1 - p/100, 1 + p/100]
  K  K_Nm_per_A (stepper2); Phi_Wb (pmsm3)  uniform in [1 - p/100, 1 + p/100]
  J  J_kgm2                                 uniform in [1 - p/100, 1 + p/100],
                                            or with --j-range LO,HI
                                            log-uniform in [LO, HI]:
                                            exp(U(ln LO, ln HI)), so x2 is as
                                            likely as x0.5
  D  [inverter] dead_time_s (the board's; with --dead-time-pct D only: a
     scenario with an [inverter])          uniform in [1 - D/100, 1 + D/100];
     the drive's compensation keeps the nominal dead time
     ([inverter] compensation_dead_time_s)
  p is --spread-pct (default 0: a seed-only sweep), or the parameter's own
  percentage from --spread NAME=PCT,... (which overrides --spread-pct for the
  names it gives). 0 <= p < 100.

  Draws come from Python's random.Random(--seed), run by run in index order:
  for each run one random() each for R, L, K, J (in this order, also for a
  zero spread, so changing one spread does not reshuffle the others) and
  then its noise seed, randrange(2**31); with --dead-time-pct its D comes
  from a stream of its own (random.Random("dead_time/SEED")), so the other
  draws stay those of a sweep without it. The same --seed and spreads give
  the same variants and seeds, so the same per-run results, whatever --jobs
  or --dask.

Output
  stdout: one JSON object: runs, passed, failed, errors, pass_rate (passed /
  runs), pass_rate_ci95 (Wilson interval), fail_reasons (count per outcome:
  fault, expect, diverged), expect_misses (count per [expect] metric), the
  spreads, the nominal plant and drive model, the seed, wall_time_s, the
  main metric (theta_track_max_rad for a position scenario, speed_err_rms_rpm
  for a [speed] scenario, or --metric) with its statistics, `worst` (the
  --worst runs with the worst main metric), `failures` (every failed run),
  `error_runs` (every run that was an error of the tool), each with its factors,
  plant values, noise seed, outcome, reason and `replay`: the exact motorsim
  command that replays it; with --per-run also `per_run` (every run).
  The variant scenarios of the worst cases, failures and errors are written
  into --keep DIR (default: a new temporary directory, named on stderr) so
  that the replay commands work; a replay writes CSV + PNG beside them.
  stderr: a progress bar, then a human summary.

Parallelism
  Locally, --jobs motorsim processes at once (default: every core).
  With --dask ADDRESS the runs are submitted to an existing Dask distributed
  scheduler (dask.distributed.Client(ADDRESS), client.map, as_completed);
  each task runs motorsim on a worker, which must see the same filesystem as
  this process: the motorsim binary and the motor file are used by their
  absolute paths here (the variant itself is sent with the task).

Exit status: 0 the sweep ran (whatever its pass rate), 1 some runs were
errors of the tool (the JSON is still written), 2 bad command line or input
(nothing run), 3 the pass rate is below --min-pass-pct.
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import io
import json
import math
import os
import random
import re
import shlex
import statistics
import sys
import tempfile
import time
import tomllib
from pathlib import Path

TOOLS = Path(__file__).resolve().parent
sys.path.insert(0, str(TOOLS))  # the toolbox, tools/lib
from lib import motorsim  # noqa: E402

ROOT = TOOLS.parent
DEFAULT_BINARY = ROOT / "build" / "host" / "sim" / "motorsim"

PARAMS = ("R", "L", "K", "J")
# The plant keys each drawn factor scales, by motor type.
PARAM_KEYS = {
    "stepper2": {"R": ("R_ohm",), "L": ("L_H",), "K": ("K_Nm_per_A",), "J": ("J_kgm2",)},
    "pmsm3": {"R": ("R_ohm",), "L": ("L_d_H", "L_q_H"), "K": ("Phi_Wb",), "J": ("J_kgm2",)},
}
# The keys a [drive_model] table takes, by motor type (sim/scenarios/README.md).
MODEL_KEYS = {
    "stepper2": ("L_H", "R_ohm", "K_Nm_per_A", "J_kgm2", "fv_Nms_per_rad", "n_p"),
    "pmsm3": ("L_d_H", "L_q_H", "R_ohm", "Phi_Wb", "J_kgm2", "fv_Nms_per_rad", "n_p"),
}
OUTCOMES = {0: "pass", 3: "fault", 4: "expect", 5: "diverged"}
IGNORED_METRICS = ("wall_time_s", "realtime_factor")  # wall-clock figures: differ run to run


class UsageError(Exception):
    pass


# ------------------------------------------------------------ spreads ----
class Spread:
    """The distribution of one parameter's factor."""

    def __init__(self, param: str, kind: str, lo: float, hi: float, pct: float | None = None):
        self.param, self.kind, self.lo, self.hi, self.pct = param, kind, lo, hi, pct

    def factor(self, u: float) -> float:
        """The factor for u uniform in [0, 1)."""
        if self.kind == "log-uniform":
            return math.exp(math.log(self.lo) + (math.log(self.hi) - math.log(self.lo)) * u)
        return self.lo + (self.hi - self.lo) * u

    def describe(self) -> str:
        if self.kind == "log-uniform":
            return f"{self.param} x{self.lo:g}-{self.hi:g} log-uniform"
        return f"{self.param} ±{self.pct:g} %"

    def to_json(self, keys: tuple[str, ...]) -> dict:
        d = {"keys": list(keys), "dist": self.kind, "lo": self.lo, "hi": self.hi}
        if self.pct is not None:
            d["pct"] = self.pct
        return d


def uniform_pct(param: str, pct: float) -> Spread:
    if not (0.0 <= pct < 100.0) or not math.isfinite(pct):
        raise UsageError(f"{param}: the spread must be in [0, 100) % (got {pct:g})")
    return Spread(param, "uniform", 1.0 - pct / 100.0, 1.0 + pct / 100.0, pct)


def parse_spreads(spread_pct: float, spread: str | None, j_range: str | None) -> dict[str, Spread]:
    out = {p: uniform_pct(p, spread_pct) for p in PARAMS}
    if spread:
        for item in spread.split(","):
            name, sep, value = item.partition("=")
            name = name.strip().upper()
            if not sep or name not in PARAMS:
                raise UsageError(f"--spread: expected NAME=PCT with NAME one of {','.join(PARAMS)} (got '{item}')")
            try:
                pct = float(value)
            except ValueError:
                raise UsageError(f"--spread: {name}: not a number: '{value}'") from None
            out[name] = uniform_pct(name, pct)
    if j_range:
        try:
            lo, hi = (float(x) for x in j_range.split(","))
        except ValueError:
            raise UsageError(f"--j-range: expected LO,HI (got '{j_range}')") from None
        if not (0.0 < lo <= hi) or not math.isfinite(hi):
            raise UsageError(f"--j-range: need 0 < LO <= HI (got {lo:g},{hi:g})")
        out["J"] = Spread("J", "log-uniform", lo, hi)
    return out


def draw_runs(n: int, seed: int, spreads: dict[str, Spread], dead_time_pct: float = 0.0) -> list[dict]:
    """Factors and noise seed of each run (see the docstring for the order)."""
    rng = random.Random(seed)
    rng_d = random.Random(f"dead_time/{seed}")  # a stream of its own: the other draws as without it
    runs = []
    for i in range(n):
        factors = {p: spreads[p].factor(rng.random()) for p in PARAMS}
        runs.append({"index": i, "factors": factors, "seed": rng.randrange(1 << 31)})
        if dead_time_pct > 0.0:
            runs[-1]["factors"]["D"] = 1.0 + dead_time_pct / 100.0 * (2.0 * rng_d.random() - 1.0)
    return runs


# ----------------------------------------------------------- variants ----
class Base:
    """The scenario, its motor, the nominal plant and the drive model."""

    def __init__(self, scenario: Path):
        try:
            self.sc = tomllib.loads(scenario.read_text())
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
            raise UsageError(f"{scenario}: {e}") from None
        self.path = scenario.resolve()
        motor_ref = self.sc.get("motor", {}).get("file")
        if not isinstance(motor_ref, str):
            raise UsageError(f"{scenario}: motor.file: missing")
        self.motor_file = (scenario.parent / motor_ref).resolve()
        try:
            motor = tomllib.loads(self.motor_file.read_text())
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
            raise UsageError(f"{self.motor_file}: {e}") from None
        self.type = motor.get("type")
        if self.type not in PARAM_KEYS:
            raise UsageError(f"{self.motor_file}: type: expected one of {', '.join(PARAM_KEYS)} (got {self.type!r})")
        overrides = self.sc["motor"]
        # The scenario's plant as written, then what its drive is designed for.
        self.plant = {k: overrides.get(k, motor.get(k)) for k in MODEL_KEYS[self.type]}
        missing = [k for k, v in self.plant.items() if v is None and k != "fv_Nms_per_rad"]
        if missing:
            raise UsageError(f"{self.motor_file}: missing {', '.join(missing)}")
        self.plant = {k: v for k, v in self.plant.items() if v is not None}
        self.drive_model = dict(self.plant)
        self.drive_model.update(self.sc.get("drive_model", {}))
        self.speed = "speed" in self.sc
        self.expect = self.sc.get("expect", {})
        # [inverter]: its file's path made absolute (the variants are
        # written elsewhere) and the board's nominal dead time
        self.dead_time_s = None
        inv = self.sc.get("inverter")
        if isinstance(inv, dict):
            inv_vals = {}
            if isinstance(inv.get("file"), str):
                inv_file = (scenario.parent / inv["file"]).resolve()
                self.sc["inverter"]["file"] = str(inv_file)
                try:
                    inv_vals = tomllib.loads(inv_file.read_text())
                except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
                    raise UsageError(f"{inv_file}: {e}") from None
            inv_vals.update(inv)
            self.dead_time_s = float(inv_vals.get("dead_time_s", 0.0))

    def variant(self, run: dict, name: str) -> str:
        """The TOML text of one run's scenario."""
        sc = json.loads(json.dumps(self.sc))  # deep copy
        sc["motor"]["file"] = str(self.motor_file)
        sc["drive_model"] = dict(self.drive_model)  # the drive keeps the nominal model
        for p in PARAMS:
            for key in PARAM_KEYS[self.type][p]:
                sc["motor"][key] = self.plant[key] * run["factors"][p]  # the plant differs
        sc.setdefault("run", {})["seed"] = run["seed"]
        if "D" in run["factors"]:  # the board's dead time differs, the drive's compensation keeps the nominal
            sc["inverter"]["dead_time_s"] = self.dead_time_s * run["factors"]["D"]
            sc["inverter"].setdefault("compensation_dead_time_s", self.dead_time_s)
        facs = ", ".join(f"{p} x{run['factors'][p]:.4f}" for p in PARAMS if p in run["factors"])
        if "D" in run["factors"]:
            facs += f", dead time x{run['factors']['D']:.4f}"
        sc["description"] = f"tools/sweep.py {name} of {self.path.name}: plant {facs}; drive nominal"
        import tomli_w  # the venv has it (tools/requirements.txt)
        header = (f"# {name} of a Monte Carlo sweep (tools/sweep.py) over {self.path}\n"
                  f"# plant factors {facs}, noise seed {run['seed']}; [drive_model] is the nominal model\n")
        return header + tomli_w.dumps(sc)


# ------------------------------------------------------------- a run ----
def run_variant(binary: str, name: str, toml_text: str, seed: int, timeout_s: float | None,
                tools_dir: str = str(TOOLS)) -> dict:
    """One motorsim run of one variant, metrics only (tools/lib/motorsim.py,
    which the worker imports from tools_dir: it may run on a Dask worker,
    which must see this filesystem). Returns motorsim's exit status (None: it
    did not run or timed out), its stderr and its metrics (None when it
    wrote none)."""
    import sys as _sys

    if tools_dir not in _sys.path:
        _sys.path.insert(0, tools_dir)
    from lib import motorsim as _motorsim

    r = _motorsim.run(binary, text=toml_text, name=name, seed=seed, timeout=timeout_s, ok=None)
    return {"status": r.status, "stderr": r.stderr.replace(r.scenario, name + ".toml"), "metrics": r.metrics}


def reason_of(status: int | None, stderr: str) -> str:
    lines = [ln.strip() for ln in stderr.splitlines() if ln.strip()]
    # "motorsim: FAILED: <scenario path>: expect.x: ..." -> "expect.x: ..."
    failed = [re.sub(r"^\S+\.toml: ", "", ln.removeprefix("motorsim: FAILED: "))
              for ln in lines if ln.startswith("motorsim: FAILED")]
    if status == 0:
        return ""
    if failed:
        return "; ".join(failed)
    return lines[-1] if lines else f"motorsim exit status {status} and no message"


# ---------------------------------------------------------- executors ----
class Progress:
    """A text bar on stderr: redrawn in place on a terminal (10 Hz at most),
    one line per 10 % otherwise."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.enabled = total, enabled and total > 0
        self.tty = sys.stderr.isatty()
        self.t0 = time.monotonic()
        self.last_draw = 0.0
        self.last_decile = -1

    def update(self, done: int, fails: int, errors: int) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        el = now - self.t0
        frac = done / self.total
        if self.tty:
            if done < self.total and now - self.last_draw < 0.1:
                return
            self.last_draw = now
        else:
            decile = int(10 * frac)
            if decile == self.last_decile:
                return
            self.last_decile = decile
        width = 30
        fill = int(width * frac)
        eta = el / frac * (1 - frac) if frac > 0 else 0.0
        line = (f"sweep [{'#' * fill}{'.' * (width - fill)}] {done}/{self.total} "
                f"fail {fails} err {errors} {el:.1f} s, eta {eta:.0f} s")
        if self.tty:
            sys.stderr.write("\r" + line + ("\n" if done >= self.total else ""))
        else:
            sys.stderr.write(line + "\n")
        sys.stderr.flush()


def execute_local(tasks: list[tuple], jobs: int, on_done) -> None:
    with cf.ThreadPoolExecutor(jobs) as pool:
        futs = {pool.submit(run_variant, *t[1:]): t[0] for t in tasks}
        try:
            for fut in cf.as_completed(futs):
                on_done(futs[fut], fut.result())
        except BaseException:
            for f in futs:
                f.cancel()
            raise


def execute_dask(tasks: list[tuple], address: str, on_done) -> int:
    """Runs the tasks on the Dask scheduler at address; returns the number of
    worker threads it had."""
    try:
        from dask.distributed import Client, as_completed
    except ImportError:
        raise UsageError("--dask needs dask[distributed] (run scripts/setup.sh, use .venv/bin/python)") from None
    module = sys.modules.get(__name__)
    if __name__ != "__main__" and module is not None:
        # Imported (e.g. by a test): ship run_variant by value, so a worker
        # that cannot import this module can still run it.
        import cloudpickle
        cloudpickle.register_pickle_by_value(module)
    try:
        client = Client(address, timeout="20s")
    except (OSError, TimeoutError, ValueError) as e:
        raise UsageError(f"--dask {address}: cannot connect to the scheduler: {e}") from None
    try:
        threads = sum(client.nthreads().values())
        idx, rest = [t[0] for t in tasks], list(zip(*[t[1:] for t in tasks]))
        futures = client.map(run_variant, *rest, pure=False)
        by_key = {f.key: i for f, i in zip(futures, idx)}
        try:
            for fut in as_completed(futures):
                on_done(by_key[fut.key], fut.result())
        except BaseException:
            client.cancel(futures)
            raise
    finally:
        client.close()
    return threads


# ------------------------------------------------------------ results ----
def wilson(k: int, n: int, z: float = 1.959964) -> list[float]:
    if n == 0:
        return [0.0, 1.0]
    p = k / n
    den = 1 + z * z / n
    c = (p + z * z / (2 * n)) / den
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return [max(0.0, c - h), min(1.0, c + h)]


def main_metric(base: Base, override: str | None) -> tuple[str, bool]:
    """(name, higher_is_worse)."""
    name = override or ("speed_err_rms_rpm" if base.speed else "theta_track_max_rad")
    bound = base.expect.get(name, {})
    higher_worse = not (isinstance(bound, dict) and "min" in bound and "max" not in bound)
    return name, higher_worse


def plot(path: Path, records: list[dict], axes: list[tuple[str, str]], spreads: dict[str, Spread],
         title: str, metric: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FixedFormatter, FixedLocator, NullFormatter

    n = len(axes)
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axs = plt.subplots(rows, cols, figsize=(6.4 if n == 1 else 4.0 * cols + 1.0, 4.8 if n == 1 else 3.6 * rows + 0.6),
                            squeeze=False, layout="constrained")
    styles = {"fault": ("^", "black", "fault (exit 3)"), "expect": ("x", "red", "[expect] missed (exit 4)"),
              "diverged": ("s", "magenta", "diverged (exit 5)"), "error": ("D", "orange", "tool error")}
    passes = [r for r in records if r["outcome"] == "pass"]
    vals = [r["metric"] for r in passes if r["metric"] is not None]
    sc = None
    for k, (a, b) in enumerate(axes):
        ax = axs[k // cols][k % cols]
        if passes:
            sc = ax.scatter([r["factors"][a] for r in passes], [r["factors"][b] for r in passes],
                            c=[r["metric"] if r["metric"] is not None else float("nan") for r in passes],
                            s=9, cmap="viridis", vmin=min(vals) if vals else None, vmax=max(vals) if vals else None,
                            linewidths=0, label=f"pass ({len(passes)})")
        for outcome, (marker, color, label) in styles.items():
            sel = [r for r in records if r["outcome"] == outcome]
            if sel:
                ax.scatter([r["factors"][a] for r in sel], [r["factors"][b] for r in sel], s=28, marker=marker,
                           c=color, linewidths=1.2, label=f"{label} ({len(sel)})")
        for p, axis in ((a, ax.xaxis), (b, ax.yaxis)):
            if spreads[p].kind == "log-uniform":
                (ax.set_xscale if axis is ax.xaxis else ax.set_yscale)("log")
                lo, hi = math.log2(spreads[p].lo), math.log2(spreads[p].hi)
                ticks = sorted({round(2 ** (lo + (hi - lo) * k / 4), 2) for k in range(5)})
                axis.set_major_locator(FixedLocator(ticks))
                axis.set_major_formatter(FixedFormatter([f"{t:g}" for t in ticks]))
                axis.set_minor_formatter(NullFormatter())
        ax.set_xlabel(f"{a} factor (plant / drive model)")
        ax.set_ylabel(f"{b} factor (plant / drive model)")
        ax.grid(True, alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7, loc="upper left", framealpha=0.85)
    for k in range(n, rows * cols):
        axs[k // cols][k % cols].set_visible(False)
    if sc is not None:
        fig.colorbar(sc, ax=axs.ravel().tolist(), label=f"{metric} of the passes", shrink=0.9, pad=0.02)
    fig.suptitle(title, fontsize=9)
    # A palette PNG (256 colours, no dither): a third of the RGB file's size,
    # small enough to commit, and the picture looks the same.
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    plt.close(fig)
    from PIL import Image  # a dependency of matplotlib
    Image.open(buf).convert("RGB").quantize(256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE) \
        .save(path, format="png", optimize=True)


# --------------------------------------------------------------- main ----
def parse_args(argv: list[str] | None) -> argparse.Namespace:
    doc = __doc__ or ""
    ap = argparse.ArgumentParser(
        prog="sweep.py", formatter_class=argparse.RawDescriptionHelpFormatter,
        description=doc.split("\n\n", 1)[0],
        epilog=doc[doc.index("What one run is"):] if "What one run is" in doc else None)
    ap.add_argument("--scenario", required=True, type=Path, help="the motorsim scenario (TOML)")
    ap.add_argument("--runs", required=True, type=int, help="number of runs N")
    ap.add_argument("--spread-pct", type=float, default=0.0, metavar="P",
                    help="R, L, K (Phi for pmsm3) and J factors uniform in [1-P/100, 1+P/100] (default 0)")
    ap.add_argument("--spread", metavar="NAME=PCT,...",
                    help="per-parameter uniform ±PCT %%, NAME in R, L, K, J; overrides --spread-pct for those")
    ap.add_argument("--j-range", metavar="LO,HI",
                    help="J factor log-uniform in [LO, HI] (exp of a uniform draw in [ln LO, ln HI]); "
                         "overrides the other J spreads")
    ap.add_argument("--dead-time-pct", type=float, default=0.0, metavar="D",
                    help="the board's dead time ([inverter] dead_time_s) uniform in [1-D/100, 1+D/100]; the drive's "
                         "compensation keeps the nominal (default 0: as written)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="motorsim runs at once, locally (default: os.cpu_count() = %(default)s)")
    ap.add_argument("--seed", type=int, default=1,
                    help="seed of the draws of the factors and of each run's noise seed (default 1)")
    ap.add_argument("--dask", metavar="ADDRESS",
                    help="submit the runs to this Dask distributed scheduler (e.g. tcp://host:8786) instead of "
                         "the local pool; the workers must share this filesystem (binary and motor file are used "
                         "by their absolute paths)")
    ap.add_argument("--keep", type=Path, metavar="DIR",
                    help="write the variants of the worst cases, failures and errors here, for their replay "
                         "commands (default: a new temporary directory, named on stderr)")
    ap.add_argument("--plot", type=Path, metavar="FILE.png", help="scatter of pass/fail over a parameter plane")
    ap.add_argument("--plot-axes", default="R,J", metavar="A,B",
                    help="the plane: two of R, L, K, J, x then y (default R,J); several planes joined by '/' "
                         "(e.g. K,J/R,L), or 'all' for the six")
    ap.add_argument("--metric", help="main metric of the worst cases (default theta_track_max_rad, or "
                                     "speed_err_rms_rpm for a [speed] scenario)")
    ap.add_argument("--worst", type=int, default=5, metavar="K", help="worst cases listed (default 5)")
    ap.add_argument("--per-run", action="store_true", help="add every run to the JSON (key per_run)")
    ap.add_argument("--binary", type=Path, default=DEFAULT_BINARY, help="motorsim (default %(default)s)")
    ap.add_argument("--timeout", type=float, default=300.0, metavar="S",
                    help="time limit of one run in seconds (default 300; beyond: an error)")
    ap.add_argument("--min-pass-pct", type=float, metavar="X", help="exit 3 if the pass rate is below X %%")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    return ap.parse_args(argv)


def run_sweep(args: argparse.Namespace) -> tuple[dict, int]:
    if args.runs < 1:
        raise UsageError("--runs must be >= 1")
    if args.jobs < 1:
        raise UsageError("--jobs must be >= 1")
    if args.worst < 0:
        raise UsageError("--worst must be >= 0")
    spreads = parse_spreads(args.spread_pct, args.spread, args.j_range)
    if args.plot_axes.strip().lower() == "all":
        axes = [(a, b) for i, a in enumerate(PARAMS) for b in PARAMS[i + 1:]]
    else:
        axes = []
        for plane in args.plot_axes.split("/"):
            pair = [x.strip().upper() for x in plane.split(",")]
            if len(pair) != 2 or pair[0] == pair[1] or any(p not in PARAMS for p in pair):
                raise UsageError(f"--plot-axes: expected A,B (two different of {','.join(PARAMS)}), several "
                                 f"joined by '/', or 'all' (got '{args.plot_axes}')")
            axes.append((pair[0], pair[1]))
    binary = args.binary.resolve()
    if not (binary.is_file() and os.access(binary, os.X_OK)):
        raise UsageError(f"{args.binary}: no motorsim there; build it: cmake --preset host && "
                         "cmake --build --preset host")
    base = Base(args.scenario)
    if not (0.0 <= args.dead_time_pct < 100.0):
        raise UsageError(f"--dead-time-pct: must be in [0, 100) (got {args.dead_time_pct:g})")
    if args.dead_time_pct > 0.0 and base.dead_time_s is None:
        raise UsageError(f"--dead-time-pct: {args.scenario} has no [inverter] table")
    metric, higher_worse = main_metric(base, args.metric)
    keep = args.keep
    if keep is None:
        keep = Path(tempfile.mkdtemp(prefix="sweep_keep_"))
    keep = keep.resolve()
    keep.mkdir(parents=True, exist_ok=True)
    print(f"sweep: variants of the worst cases and failures go to {keep}", file=sys.stderr)

    runs = draw_runs(args.runs, args.seed, spreads, args.dead_time_pct)
    width = max(4, len(str(args.runs - 1)))
    names = [f"run_{r['index']:0{width}d}" for r in runs]
    texts = [base.variant(r, n) for r, n in zip(runs, names)]
    tasks = [(r["index"], str(binary), n, t, r["seed"], args.timeout) for r, n, t in zip(runs, names, texts)]

    results: dict[int, dict] = {}
    prog = Progress(args.runs, not args.no_progress)
    counts = {"fail": 0, "err": 0}

    def on_done(i: int, res: dict) -> None:
        outcome = OUTCOMES.get(res["status"], "error")
        results[i] = dict(res, outcome=outcome)
        if outcome == "error":
            counts["err"] += 1
        elif outcome != "pass":
            counts["fail"] += 1
        prog.update(len(results), counts["fail"], counts["err"])

    t0 = time.monotonic()
    threads = args.jobs
    if args.dask:
        threads = execute_dask(tasks, args.dask, on_done)
    else:
        execute_local(tasks, args.jobs, on_done)
    wall = time.monotonic() - t0

    # ---- records --------------------------------------------------------
    expect_names = list(base.expect)
    records = []
    for r, name in zip(runs, names):
        res = results[r["index"]]
        m = res["metrics"] or {}
        val = m.get(metric)
        rec = {
            "index": r["index"], "name": name, "seed": r["seed"],
            "factors": {p: round(f, 6) for p, f in r["factors"].items()},
            "plant": {k: base.plant[k] * r["factors"][p] for p in PARAMS for k in PARAM_KEYS[base.type][p]},
            "status": res["status"], "outcome": res["outcome"], "reason": reason_of(res["status"], res["stderr"]),
            "metric": val if isinstance(val, (int, float)) and math.isfinite(val) else None,
            "fault": m.get("fault"),
            "expect_metrics": {k: m.get(k) for k in expect_names},
            "metrics": {k: v for k, v in m.items() if k not in IGNORED_METRICS},
        }
        records.append(rec)

    passed = sum(r["outcome"] == "pass" for r in records)
    failures = [r for r in records if r["outcome"] in ("fault", "expect", "diverged")]
    errors = [r for r in records if r["outcome"] == "error"]
    fail_reasons = {o: sum(r["outcome"] == o for r in failures) for o in ("fault", "expect", "diverged")}
    expect_misses: dict[str, int] = {}
    for r in failures:
        for key in set(re.findall(r"expect\.(\w+):", r["reason"])):
            expect_misses[key] = expect_misses.get(key, 0) + 1
    finite = [r for r in records if r["metric"] is not None]
    finite.sort(key=lambda r: r["metric"], reverse=higher_worse)
    worst = finite[:args.worst]

    def public(r: dict) -> dict:
        path = keep / f"{r['name']}.toml"
        replay = shlex.join(motorsim.command(binary, path, seed=r["seed"], out=keep / r["name"], plot=True,
                                             quiet=False))
        d = {k: v for k, v in r.items() if k not in ("metrics", "name")}
        d.update(scenario=str(path), replay=replay)
        return d

    kept = {r["index"] for r in worst + failures + errors}
    for i in sorted(kept):
        (keep / f"{names[i]}.toml").write_text(texts[i])
    vals = sorted(r["metric"] for r in finite)

    def q(p: float) -> float | None:
        return vals[min(len(vals) - 1, int(p * len(vals)))] if vals else None

    summary = {
        "tool": "sweep", "scenario": str(base.path), "binary": str(binary), "motor_type": base.type,
        "runs": args.runs, "passed": passed, "failed": len(failures), "errors": len(errors),
        "pass_rate": passed / args.runs, "pass_rate_ci95": wilson(passed, args.runs),
        "fail_reasons": fail_reasons, "expect_misses": expect_misses,
        "spreads": {p: spreads[p].to_json(PARAM_KEYS[base.type][p]) for p in PARAMS},
        "nominal_plant": base.plant, "drive_model": base.drive_model,
        "dead_time_pct": args.dead_time_pct, "nominal_dead_time_s": base.dead_time_s,
        "seed": args.seed, "backend": "dask" if args.dask else "local", "dask": args.dask,
        "jobs": threads, "wall_time_s": round(wall, 3), "runs_per_s": round(args.runs / wall, 2) if wall > 0 else None,
        "metric": metric, "metric_worse": "higher" if higher_worse else "lower",
        "metric_stats": {"min": vals[0] if vals else None, "median": statistics.median(vals) if vals else None,
                         "p95": q(0.95), "p99": q(0.99), "max": vals[-1] if vals else None,
                         "expect": base.expect.get(metric)},
        "worst": [public(r) for r in worst], "failures": [public(r) for r in failures],
        "error_runs": [public(r) for r in errors],
        "keep_dir": str(keep), "plot": str(args.plot) if args.plot else None,
    }
    if args.per_run:
        summary["per_run"] = [{k: v for k, v in r.items() if k != "name"} for r in records]

    # ---- plot and human summary ----------------------------------------
    spread_txt = ", ".join(spreads[p].describe() for p in PARAMS)
    if args.plot:
        title = (f"{base.path.name}: {args.runs} runs, {spread_txt}, seed {args.seed}\n"
                 f"passed {passed}/{args.runs} = {100 * passed / args.runs:.1f} %")
        plot(args.plot, records, axes, spreads, title, metric)
    err = sys.stderr
    where = f"dask {args.dask} ({threads} threads)" if args.dask else f"{threads} jobs"
    print(f"sweep: {base.path.name}, {args.runs} runs ({spread_txt}; seed {args.seed}), {where}, {wall:.1f} s",
          file=err)
    lo, hi = summary["pass_rate_ci95"]
    reasons = ", ".join(f"{k} {v}" for k, v in fail_reasons.items() if v) or "none"
    print(f"sweep: passed {passed}/{args.runs} = {100 * passed / args.runs:.1f} % "
          f"(95 % CI {100 * lo:.1f}-{100 * hi:.1f} %); failed: {reasons}; errors: {len(errors)}", file=err)
    if expect_misses:
        print("sweep: [expect] misses: " + ", ".join(f"{k} {v}" for k, v in sorted(expect_misses.items())), file=err)
    if vals:
        st = summary["metric_stats"]
        print(f"sweep: {metric}: median {st['median']:.4g}, p95 {st['p95']:.4g}, max {st['max']:.4g}"
              + (f" ([expect] {st['expect']})" if st["expect"] else ""), file=err)

    def line(r: dict) -> str:
        f = " ".join(f"{p} x{r['factors'][p]:.3f}" for p in PARAMS)
        m = f"{r['metric']:.4g}" if r["metric"] is not None else "n/a"
        return f"  {r['name']} {f} seed {r['seed']}: {r['outcome']}, {metric} {m}" + (
            f": {r['reason']}" if r["reason"] else "")

    for label, lst in (("worst", worst), ("failures", failures[:10]), ("errors", errors[:10])):
        if lst:
            more = {"failures": len(failures), "errors": len(errors)}.get(label, len(lst)) - len(lst)
            print(f"sweep: {label}" + (f" (first 10 of {len(lst) + more})" if more > 0 else "") + ":", file=err)
            for r in lst:
                print(line(r), file=err)
    shown = (failures[:1] or errors[:1] or worst[:1])
    if shown:
        print(f"sweep: replay, e.g.: {public(shown[0])['replay']}", file=err)
    if args.plot:
        print(f"sweep: wrote {args.plot}", file=err)

    status = 0
    if errors:
        status = 1
    elif args.min_pass_pct is not None and 100.0 * passed / args.runs < args.min_pass_pct:
        print(f"sweep: pass rate {100 * passed / args.runs:.1f} % below --min-pass-pct {args.min_pass_pct:g}",
              file=err)
        status = 3
    return summary, status


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        summary, status = run_sweep(args)
    except UsageError as e:
        print(f"sweep.py: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("sweep.py: interrupted", file=sys.stderr)
        return 130
    json.dump(summary, sys.stdout, indent=1)
    sys.stdout.write("\n")
    return status


if __name__ == "__main__":
    sys.exit(main())
