#!/usr/bin/env python3
"""The emulated DAC/ADC board (issue 13; motorsim --backend board-emulated,
sim/model/board_emulation.h, hal/backends/board/board_chain.h):

  * paper000_experiment and paper001_benchmark through the board (its
    default [board]: 16-bit +-10 V converters, sensor offsets of 2 % of full
    scale, 1 % gain errors, 1 mV of noise) exit 0: every [expect] threshold
    of the scenario met, no fault;
  * the calibration found every offset within one A/D step;
  * a sensor offset beyond board.offset_max_V refuses to start: exit 1,
    the phase and the value named, nothing written;
  * bad [board] configuration (an unknown channel, a gain of 0, a D/A range
    that cannot reach the supply, two signals on one channel, an unknown
    key) is refused with exit 2 naming the key, nothing written.

usage: check_board.py MOTORSIM SCENARIOS_DIR
"""
import json
import os
import subprocess
import sys
import tempfile

fails = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        fails.append(what)


def run(motorsim, scenario, out):
    r = subprocess.run([motorsim, "--scenario", scenario, "--backend", "board-emulated", "--metrics-out", out,
                        "--quiet"], capture_output=True, text=True)
    return r.returncode, r.stderr


def main(motorsim, scenarios):
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("paper000_experiment", "paper001_benchmark"):
            out = os.path.join(tmp, name + ".json")
            rc, err = run(motorsim, os.path.join(scenarios, name + ".toml"), out)
            check(rc == 0, f"{name} through the emulated board: exit {rc} (0: every [expect] met) {err.strip()[-300:]}")
            if os.path.exists(out):
                m = json.load(open(out))
                check(m["board_offset_error_max_V"] <= m["board_adc_step_V"],
                      f"{name}: offsets calibrated within {m['board_offset_error_max_V']:.3g} V, one A/D step is "
                      f"{m['board_adc_step_V']:.3g} V")
        base = open(os.path.join(scenarios, "paper000_experiment.toml")).read().replace(
            '"../motors/', '"' + os.path.join(os.path.abspath(scenarios), "..", "motors") + "/")
        cases = [
            ("offset beyond range", "sensor_offset_V = [0.2, 0.7]", 1, "board.offset_max_V: phase b's current sensor"),
            ("unknown channel", "current_channels = [0, 9]", 2, "board.current_channels: channel 9 of phase b"),
            ("gain of 0", "sensor_V_per_A = 0.0", 2, "board.sensor_V_per_A: must be > 0"),
            ("D/A range below the supply", "amplifier_V_per_V = 2.0", 2, "board.dac_range_V: the D/A range 10 V"),
            ("two signals on one channel", "vbus_channel = 1", 2, "board.vbus_channel: A/D channel 1 already carries"),
            ("output channel twice", "voltage_channels = [3, 3]", 2, "board.voltage_channels: D/A channel 3 carries two"),
            ("unknown key", "gain_V = 1.0", 2, "board.gain_V: unknown key"),
        ]
        for what, line, want_rc, want_msg in cases:
            sc = os.path.join(tmp, "bad.toml")
            with open(sc, "w") as f:
                f.write(base + "\n[board]\n" + line + "\n")
            outdir = os.path.join(tmp, "out_" + what.replace(" ", "_"))
            r = subprocess.run([motorsim, "--scenario", sc, "--backend", "board-emulated", "--out", outdir],
                               capture_output=True, text=True)
            check(r.returncode == want_rc and want_msg in r.stderr and not os.path.exists(outdir),
                  f"{what}: exit {r.returncode} ({want_rc}), nothing written, stderr: {r.stderr.strip()[-200:]}")
    print(f"check_board: {'FAILED' if fails else 'all checks passed'}")
    return 1 if fails else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1], sys.argv[2]))
