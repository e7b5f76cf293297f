#!/usr/bin/env python3
"""Output handling of motorsim like a careful Unix tool (issue 9), checked
end to end:

  1. --metrics-out to a symlink: the link stays, its target gets the JSON;
  2. --metrics-out to a FIFO read by another process: the reader gets the
     whole JSON and the FIFO is still a FIFO (not replaced by a file);
     2b. --metrics-out /dev/stdout with stdout a pipe (a magic link of
     /proc whose target names no path): the JSON goes down the pipe;
  3. SIGINT while the CSV is being written: the process ends by the signal
     and leaves neither the CSV nor its temporary file;
  4. SIGINT during the run: nothing is written;
  5. an empty --out or --metrics-out is an error (exit 2, one line naming
     the flag), and nothing is written.

usage: check_output_handling.py MOTORSIM SCENARIO_DIR
Exit 0 if all hold, 1 otherwise.
"""
from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path


def fail(msg: str) -> None:
    print("FAIL:", msg)
    sys.exit(1)


def main() -> int:
    motorsim, scdir = sys.argv[1], Path(sys.argv[2]).resolve()
    good = scdir / "bad_scenarios" / "good.toml"
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        # 1. symlink
        (d / "link.json").symlink_to("target.json")
        r = subprocess.run([motorsim, "--scenario", str(good), "--metrics-out", str(d / "link.json"), "--quiet"])
        if r.returncode != 0 or not (d / "link.json").is_symlink():
            fail(f"symlink: rc {r.returncode}, link replaced: {not (d / 'link.json').is_symlink()}")
        json.loads((d / "target.json").read_text())
        print("ok   symlink followed, link kept")
        # 2. FIFO
        fifo = d / "fifo"
        os.mkfifo(fifo)
        got = {}
        def reader():
            with open(fifo) as f:
                got["text"] = f.read()
        t = threading.Thread(target=reader)
        t.start()
        r = subprocess.run([motorsim, "--scenario", str(good), "--metrics-out", str(fifo), "--quiet"])
        t.join(timeout=30)
        if r.returncode != 0 or "text" not in got:
            fail(f"fifo: rc {r.returncode}, reader got {'text' in got}")
        m = json.loads(got["text"])
        if "fault" not in m or not fifo.is_fifo():
            fail("fifo: JSON incomplete or the FIFO was replaced")
        print("ok   FIFO written in place, reader got the whole JSON")
        # 2b. /dev/stdout into a pipe
        r = subprocess.run([motorsim, "--scenario", str(good), "--metrics-out", "/dev/stdout", "--quiet"],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            m = json.loads(r.stdout)
        except ValueError:
            m = {}
        if r.returncode != 0 or "fault" not in m:
            fail(f"/dev/stdout into a pipe: rc {r.returncode}, stderr {r.stderr.strip()!r}, JSON complete: {'fault' in m}")
        print("ok   /dev/stdout into a pipe: the whole JSON came through it")
        # 3. SIGINT during the CSV write: a 100 s run writes 1e6 rows (about 200 MB)
        long = d / "long.toml"
        text = (scdir.parent.parent / "sim" / "scenarios" / "paper000_experiment.toml").read_text()
        text = re.sub(r"(?m)^duration_s = .*$", "duration_s = 100.0", text, count=1)
        text = text.replace('file = "../motors/', f'file = "{scdir.parent.parent}/sim/motors/')
        long.write_text(text)
        out = d / "out3"
        p = subprocess.Popen([motorsim, "--scenario", str(long), "--out", str(out), "--no-plot", "--quiet",
                              "--no-expect"], stderr=subprocess.DEVNULL)
        tmp = out / ".long.csv.tmp"
        t0 = time.time()
        while not tmp.exists() and p.poll() is None and time.time() - t0 < 120:
            time.sleep(0.002)
        if not tmp.exists():
            p.kill()
            fail("SIGINT test: the CSV's temporary file never appeared (run too fast to catch?)")
        p.send_signal(signal.SIGINT)
        rc = p.wait(timeout=60)
        left = sorted(x.name for x in out.iterdir()) if out.exists() else []
        if rc != -signal.SIGINT or any(n.endswith(".tmp") or n == "long.csv" for n in left):
            fail(f"SIGINT during the CSV write: rc {rc}, left {left}")
        print(f"ok   SIGINT during the CSV write: ended by the signal, left {left}")
        # 4. SIGINT during the run (1,000 s without a CSV: seconds of loop)
        longer = d / "longer.toml"
        longer.write_text(re.sub(r"(?m)^duration_s = .*$", "duration_s = 1000.0", text, count=1))
        out4 = d / "out4"
        p = subprocess.Popen([motorsim, "--scenario", str(longer), "--out", str(out4), "--no-csv", "--quiet",
                              "--no-expect"], stderr=subprocess.DEVNULL)
        time.sleep(0.3)
        p.send_signal(signal.SIGINT)
        rc = p.wait(timeout=60)
        if rc != -signal.SIGINT or out4.exists():
            fail(f"SIGINT during the run: rc {rc}, output dir exists: {out4.exists()}")
        print("ok   SIGINT during the run: nothing written")
        # 5. empty paths
        for flag in ("--out", "--metrics-out"):
            r = subprocess.run([motorsim, "--scenario", str(good), flag, "", "--quiet"], cwd=d,
                               capture_output=True, text=True)
            if r.returncode != 2 or f"{flag}: empty path" not in r.stderr or (d / "out").exists():
                fail(f"{flag} '': rc {r.returncode}, stderr {r.stderr.strip()!r}")
        print("ok   empty --out / --metrics-out refused")
    return 0


if __name__ == "__main__":
    sys.exit(main())
