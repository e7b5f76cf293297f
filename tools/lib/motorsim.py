"""Run motorsim and read what it writes: the one place in tools/ that builds
its command line.

Every script that runs the simulator (the docs' table generators, the
benchmarks, the Monte Carlo sweep, the baseline) calls this module instead of
its own subprocess call, so a new flag, a new output or a better error
message is written once.

    import sys; from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/
    from lib import motorsim

    ms = motorsim.find(build="build/host")           # or binary=PATH
    r = motorsim.run(ms, motorsim.SCENARIOS / "paper000_experiment.toml", seed=3, expect=False)
    r.metrics["theta_track_max_rad"]

run() writes the metrics into a temporary directory (--metrics-out: no CSV,
no per-sample log, the cheapest run) unless csv=True (--out DIR --no-plot:
the CSV is read too), and raises MotorsimError naming the scenario, the
arguments, the exit status and motorsim's message when the status is not
one of `ok` (default: only 0). A scenario may be given as text (a variant
of a shipped one): it is written into a temporary file first, in `text_dir`
when its relative paths (the motor file) need the shipped folder.

Standard library only.
"""
from __future__ import annotations

import csv
import json
import os
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Sequence

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "sim" / "scenarios"
MOTORS = ROOT / "sim" / "motors"
DEFAULT_BUILD = ROOT / "build" / "host"

# motorsim's exit statuses (README, "Exit status and fault codes"; docs/motorsim.md)
OK, RUN_FAILED, BAD_INPUT, FAULT, EXPECT_MISSED, DIVERGED = 0, 1, 2, 3, 4, 5
# the statuses after which every output is still written: a result, not a
# failure of the tool
RESULTS = (OK, FAULT, EXPECT_MISSED, DIVERGED)


class MotorsimError(RuntimeError):
    """motorsim is missing, did not run, or ended with a status the caller
    does not accept; the message names the scenario and the status."""


@dataclass
class Run:
    """One motorsim run: its exit status (None: it did not run or timed
    out), its stderr, its metrics (None if it wrote none), and with csv=True
    the CSV log's rows (dicts of strings) and header; with out=DIR the
    CSV log's path."""
    cmd: list[str]
    scenario: str
    status: int | None
    stderr: str
    metrics: dict | None
    rows: list[dict] | None = None
    columns: list[str] | None = field(default=None)
    csv: Path | None = None
    wall_s: float | None = None  # wall time of the motorsim process alone


def find(build: str | os.PathLike | None = None, binary: str | os.PathLike | None = None) -> Path:
    """The motorsim binary: `binary` if given, else BUILD/sim/motorsim
    (default build/host). Raises MotorsimError saying how to build it."""
    path = Path(binary) if binary is not None else Path(build or DEFAULT_BUILD).resolve() / "sim" / "motorsim"
    if not path.is_file():
        raise MotorsimError(f"{path}: no motorsim there; build it: cmake --preset host && "
                            "cmake --build --preset host --target motorsim")
    return path


def command(binary: str | os.PathLike, scenario: str | os.PathLike, *, seed: int | None = None,
            estimator: str | None = None, theta0_rad: str | float | None = None,
            compute_delay_samples: float | None = None, expect: bool = True, quiet: bool = True,
            metrics_out: str | os.PathLike | None = None, out: str | os.PathLike | None = None,
            plot: bool = False, extra: Sequence[str] = ()) -> list[str]:
    """motorsim's argument vector, in one fixed order. theta0_rad given as a
    string is passed as written (the caller's own formatting)."""
    cmd = [str(binary), "--scenario", str(scenario)]
    if estimator is not None:
        cmd += ["--estimator", estimator]
    if theta0_rad is not None:
        cmd += ["--theta0-rad", theta0_rad if isinstance(theta0_rad, str) else repr(float(theta0_rad))]
    if compute_delay_samples is not None:
        cmd += ["--compute-delay-samples", f"{compute_delay_samples:g}"]
    if seed is not None:
        cmd += ["--seed", str(int(seed))]
    if out is not None:
        cmd += ["--out", str(out)]
        if not plot:
            cmd.append("--no-plot")
    if metrics_out is not None:
        cmd += ["--metrics-out", str(metrics_out)]
    if quiet:
        cmd.append("--quiet")
    if not expect:
        cmd.append("--no-expect")
    return cmd + [str(x) for x in extra]


def describe(scenario: str | os.PathLike, name: str | None = None, **flags) -> str:
    """'NAME (--seed 3 --estimator flux)': the scenario and the flags that
    made this run differ from a plain one, for error messages."""
    bits = [f"--{k.replace('_', '-')} {v}" for k, v in flags.items() if v is not None and v is not False]
    return (name or Path(scenario).name) + (f" ({' '.join(bits)})" if bits else "")


def run(binary: str | os.PathLike, scenario: str | os.PathLike | None = None, *, text: str | None = None,
        name: str | None = None, text_dir: str | os.PathLike | None = None, seed: int | None = None,
        estimator: str | None = None, theta0_rad: str | float | None = None,
        compute_delay_samples: float | None = None, expect: bool = True, csv_log: bool = False,
        out: str | os.PathLike | None = None, raw: bool = False, extra: Sequence[str] = (), prefix: Sequence[str] = (), ok: Iterable[int] | None = (OK,),
        timeout: float | None = None) -> Run:
    """Runs one scenario and reads its outputs.

    scenario     a scenario file; or text: its TOML text, written to NAME.toml
                 (default: the stem of `scenario`, else 'scenario') in a
                 temporary directory, or as a hidden temporary file in
                 text_dir (for relative paths such as the motor file's)
    seed, estimator, theta0_rad, compute_delay_samples
                 motorsim's flags of those names (None: not given)
    expect       False: --no-expect (the scenario's [expect] is not judged)
    csv_log      True: a full run into a temporary --out (no PNG), and the
                 CSV log is read into Run.rows; else metrics only
    out          a full run (CSV, metrics, no PNG) into this directory, which
                 stays: Run.csv is the log's path (its rows are not read)
    extra        further motorsim arguments; prefix: a command to run it
                 under (e.g. taskset -c 0)
    raw          True: add no output or --quiet flag of its own (the caller
                 passes them in extra and reads the files; Run.metrics None)
    ok           the statuses to accept; any other, a timeout, or no metrics
                 raises MotorsimError. None: never raise (Run.status None when
                 it did not run, Run.metrics None when it wrote none)
    """
    if scenario is None and text is None:
        raise ValueError("motorsim.run: give a scenario file or its text")
    ok = None if ok is None else tuple(ok)
    stem = name or (Path(scenario).stem if scenario is not None else "scenario")
    with tempfile.TemporaryDirectory(prefix="motorsim_") as work:
        work_p = Path(work)
        hidden = None
        try:
            if text is not None:
                if text_dir is not None:
                    hidden = tempfile.NamedTemporaryFile("w", suffix=".toml", dir=text_dir, prefix=f".{stem}_",
                                                         delete=False)
                    with hidden:
                        hidden.write(text)
                    path = Path(hidden.name)
                    stem_out = path.stem
                else:
                    path = work_p / f"{stem}.toml"
                    path.write_text(text)
                    stem_out = stem
            else:
                path = Path(scenario)
                stem_out = path.stem
            label = describe(path if text is None else f"{stem}.toml (a variant)", None, seed=seed, estimator=estimator,
                             theta0_rad=theta0_rad, compute_delay_samples=compute_delay_samples)
            if raw:
                mpath = work_p / "no-metrics-read"
                cmd = command(binary, path, seed=seed, estimator=estimator, theta0_rad=theta0_rad,
                              compute_delay_samples=compute_delay_samples, expect=expect, quiet=False,
                              extra=extra)
            elif csv_log or out is not None:
                outdir = Path(out) if out is not None else work_p / "out"
                mpath = outdir / f"{stem_out}_metrics.json"
                cmd = command(binary, path, seed=seed, estimator=estimator, theta0_rad=theta0_rad,
                              compute_delay_samples=compute_delay_samples, expect=expect, out=outdir,
                              extra=extra)
            else:
                mpath = work_p / "metrics.json"
                cmd = command(binary, path, seed=seed, estimator=estimator, theta0_rad=theta0_rad,
                              compute_delay_samples=compute_delay_samples, expect=expect, metrics_out=mpath,
                              extra=extra)
            cmd = [str(p) for p in prefix] + cmd
            t0 = time.perf_counter()
            try:
                proc = subprocess.run(cmd, stdout=subprocess.DEVNULL if raw else subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True, timeout=timeout)
                status, stderr = proc.returncode, proc.stderr
            except subprocess.TimeoutExpired:
                status, stderr = None, f"timed out after {timeout:g} s"
            except OSError as e:
                status, stderr = None, f"cannot run {binary}: {e}"
            wall_s = time.perf_counter() - t0
            metrics = None
            if not raw and mpath.exists():
                try:
                    metrics = json.loads(mpath.read_text())
                except ValueError as e:
                    if ok is not None:
                        raise MotorsimError(f"motorsim on {label}: unreadable metrics {mpath.name}: {e}") from None
            rows = columns = None
            csv_path = outdir / f"{stem_out}.csv" if out is not None else None
            if csv_log and out is None and status is not None and (outdir / f"{stem_out}.csv").exists():
                with open(outdir / f"{stem_out}.csv", newline="") as f:
                    reader = csv.DictReader(f)
                    rows = list(reader)
                    columns = list(reader.fieldnames or [])
        finally:
            if hidden is not None:
                Path(hidden.name).unlink(missing_ok=True)
    if ok is not None:
        msg = stderr.strip()
        if status not in ok:
            what = "did not finish" if status is None else f"exit status {status}"
            raise MotorsimError(f"motorsim on {label}: {what}" + (f": {msg}" if msg else ""))
        if metrics is None and not raw:
            raise MotorsimError(f"motorsim on {label}: exit status {status} but no metrics written"
                                + (f": {msg}" if msg else ""))
    return Run(cmd=cmd, scenario=str(path), status=status, stderr=stderr, metrics=metrics, rows=rows, columns=columns, csv=csv_path,
               wall_s=wall_s)


def metrics(binary: str | os.PathLike, scenario: str | os.PathLike | None = None, **kw) -> dict:
    """run(...).metrics: the metrics JSON of one run."""
    return run(binary, scenario, **kw).metrics


def with_absolute_motor(text: str, base: Path = SCENARIOS) -> str:
    """A shipped scenario's text with its relative motor path ('../motors/')
    made absolute, so the variant can be written anywhere."""
    return text.replace('file = "../motors/', f'file = "{base.parent}/motors/')


def version(binary: str | os.PathLike) -> str:
    """`motorsim --version`'s output (it names the numeric type: 'fixed
    point' or 'float'). Raises MotorsimError when it fails."""
    try:
        p = subprocess.run([str(binary), "--version"], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise MotorsimError(f"{binary} --version: {e}") from None
    if p.returncode != 0:
        raise MotorsimError(f"{binary} --version: exit status {p.returncode}: {p.stderr.strip()}")
    return p.stdout
