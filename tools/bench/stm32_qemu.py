#!/usr/bin/env python3
"""One STM32F405 image, a (drive, board) pair with its configuration
variant, under QEMU (-M netduinoplus2), as far as QEMU models the chip
(hal/backends/stm32f405/README.md): the pair is configured as its preset
configures it (MC_DRIVE, MC_BOARD, MC_DRIVE_VARIANT: the configure-time
check of the drive's needs against the board), its flashable image built
and read back (tools/bench/check_stm32_elf.py), and the image's own
start-up, vector table and backend control path run on QEMU's board with
TIM2's interrupt handing it the recorded samples of the drive (PIL vectors
from the host build's mc_pil_gen, on the drive's benchmark scenario with
the estimator of the pair's configuration); the drive's command must equal
the host's bit for bit. Costs, as tools/bench/pil.py counts them (SysTick
under -icount, the empty timed region subtracted): the whole control
interrupt's body (the backend around the step and the CAN-less application
included) and the drive's step alone, in instructions, and as a share of
the control period at 168 MHz (an instruction a cycle: a lower bound of
the share on the chip). What it knows of a drive comes from its facts
file, firmware/drives/<drive>/tools.toml (tools/lib/drive_facts.py): its
benchmark scenario and, with --check-budget, its budget beyond the share of
the period every image keeps ([stm32]).

    tools/bench/stm32_qemu.py [--drive NAME] [--board NAME] [--variant NAME] [--scenario FILE]
                              [--max-samples N] [--shift S] [--build-root DIR] [--check-budget]

JSON on stdout; exit 0 PASS, 1 FAIL (a mismatch, a missed period, no
PASS line, the image not built), 77 no ARM toolchain or qemu-system-arm."""
import argparse
import glob
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # tools/: the toolbox
import crossbuild as cb  # noqa: E402
from lib import drive_facts  # noqa: E402

MACHINE = "netduinoplus2"
# QEMU's netduinoplus2 runs its core clock (and so SysTick) at 168 MHz;
# -icount shift=S makes an instruction 2^S ns: 0.168 * 2^S ticks.
SYSCLK_HZ = 168e6
# the control period of every image: 10 kHz (boards/*.c control_hz)
CONTROL_PERIOD_S = 100e-6
# Every image's interrupt, at its longest, within this share of the
# period in instructions (a cycle each at 168 MHz): the rest is the chip's
# (FPU and load latencies, flash wait states), CAN and the main loop's.
PERIOD_SHARE_MAX = 0.5
# The flashable image's flash at most (issue 44's budget: 128 KiB, the
# first of the F405's 128 KB sectors after the configuration sectors
# would hold the rest)
FLASH_BYTES_MAX = 128 * 1024


def config_estimator(drive, board, variant):
    """The estimator key of the pair's configuration scenario
    (firmware/drives/<drive>/boards/<board>[_<variant>].toml), or None."""
    name = board + ("_" + variant if variant else "")
    path = os.path.join(cb.ROOT, "firmware", "drives", drive, "boards", name + ".toml")
    if not os.path.exists(path):
        return None, path
    m = re.search(r'^estimator\s*=\s*"(\w+)"', open(path).read(), re.M)
    return (m.group(1) if m else None), path


def recorded_estimator(vec):
    """The estimator the vectors were recorded with (mc_pil_gen names it in
    pil_source), or None."""
    m = re.search(r'pil_source\[\] = "[^"]*estimator (\w+)', open(vec).read())
    return m.group(1) if m else None


def run_image(a, facts, board, variant, gen, scenario):
    """Configures, builds and runs the image of (facts.name, board, variant);
    its result (the JSON fields below) with "pass"."""
    drive = facts.name
    image = "_".join([drive, board] + ([variant] if variant else []))
    build_root = a.build_root or os.path.join(cb.ROOT, "build", "stm32_qemu", image)
    if a.build_root and a.all:
        build_root = os.path.join(a.build_root, image)
    os.makedirs(build_root, exist_ok=True)
    estimator, config_toml = config_estimator(drive, board, variant)
    vec = os.path.join(build_root, "pil_vectors_%s.c" % image)
    # the design reference: the defaults with the board's values, as the
    # flashable image of the pair starts (its <board>[_<variant>]_params.c)
    cb.run([gen, "--drive", drive] + (["--estimator", estimator] if estimator else []) +
           ["--board-scenario", config_toml, scenario, vec, str(a.max_samples)])
    bdir = os.path.join(build_root, "stm32f405")
    defs = {"MC_PIL_VECTORS": vec, "MC_DRIVE": drive, "MC_BOARD": board, "MC_DRIVE_VARIANT": variant}
    try:
        cb.cross_build("stm32f405", bdir, defs, targets=["firmware", "stm32_qemu", "stm32_qemu_hse"])
    except RuntimeError as e:
        # the configure-time refusal of a pair, or a build error: printed by cb.run
        return {"image": image, "built": False, "error": str(e), "pass": False}
    # the flashable image of the pair read back: vector table, reset, handlers
    elf_check = subprocess.run([sys.executable, os.path.join(cb.ROOT, "tools", "bench", "check_stm32_elf.py"),
                                os.path.join(bdir, "firmware.elf")], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    elf_ok = elf_check.returncode == 0
    if not elf_ok:
        cb.log(elf_check.stdout)
    elf = os.path.join(bdir, "stm32_qemu.elf")
    # sleep=off: while the core waits for the interrupt (wfi), virtual time
    # jumps to the next timer event instead of following the host's clock,
    # so the 10 kHz interrupt is exactly periodic in instructions
    cmd = ["qemu-system-arm", "-M", MACHINE, "-nographic", "-monitor", "none", "-serial", "none",
           "-semihosting-config", "enable=on,target=native", "-icount", "shift=%d,sleep=off" % a.shift, "-kernel", elf]
    cb.log("+", " ".join(cmd))
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    rc, out = r.returncode, r.stdout
    # the image asking for a crystal QEMU's RCC never reports: fault 1, the
    # bridges off, no control step
    hse = subprocess.run(cmd[:-1] + [os.path.join(bdir, "stm32_qemu_hse.elf")], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True, timeout=600).stdout
    hse_ok = "init failed: HSE crystal did not start fault=1" in hse and "STM32QEMU FAIL" in hse
    isr, step, info = [], [], {}
    for line in out.splitlines():
        if line.startswith("Q "):
            isr += [int(t) for t in line.split()[1:]]
        elif line.startswith("D "):
            step += [int(t) for t in line.split()[1:]]
        elif line.startswith("STM32QEMU "):
            for k, v in re.findall(r"(\w+)=(\S+)", line):
                info[k] = v
    per_instr = SYSCLK_HZ * (2 ** a.shift) * 1e-9
    calib = int(info.get("calib", "0"))

    def stats(ticks, name):
        ins = [(t - calib) / per_instr for t in ticks]  # noqa: B023
        if not ins:
            return {}
        return {name + "_instr_mean": round(sum(ins) / len(ins), 1), name + "_instr_max": round(max(ins)),
                name + "_instr_min": round(min(ins))}

    # the clocks the counts rest on, measured: 1000 nops give the SysTick
    # ticks of an instruction (expected 0.168 * 2^S: SysTick at 168 MHz), and
    # TIM2's interrupt must come every 100 us in those ticks (the board's
    # control_timer_hz is QEMU's timer clock)
    ticks_per_instr = int(info.get("nop1000", "0")) / 1000.0
    nop_ratio = ticks_per_instr / per_instr
    systick_hz = ticks_per_instr / (2 ** a.shift * 1e-9)
    period_us = [int(info.get(k, "0")) / systick_hz * 1e6 if systick_hz else 0.0
                 for k in ("period_min", "period_max")]
    n_periods = int(info.get("period_n", "0"))
    mean_us = (int(info.get("period_sum", "0")) / n_periods / systick_hz * 1e6) if systick_hz and n_periods else 0.0
    # The timer's rate is the mean period (the board's control_timer_hz
    # against QEMU's timer clock), within 0.5 us as every period was before
    # (the SysTick rate it is counted in comes from the 1000 nops, measured
    # 168.375 MHz for 168: 0.2 %); no interrupt may come early (the shortest
    # period within 0.5 us too). One entry's lateness is QEMU's:
    # under host load it delivers an interrupt up to ~1 us late after the
    # previous one's semihosting output (seen 100.94 us once in a loaded CI
    # run), so the longest period is reported, not judged.
    clocks_ok = (abs(nop_ratio - 1.0) < 0.01 and abs(mean_us - 100.0) < 0.5 and abs(period_us[0] - 100.0) < 0.5)
    ok = rc == 0 and "STM32QEMU PASS" in out and clocks_ok and hse_ok and elf_ok
    res = {"image": image, "machine": MACHINE, "icount_shift": a.shift, "scenario": os.path.relpath(scenario, cb.ROOT),
           "drive": drive, "board": board, "variant": variant, "estimator": recorded_estimator(vec) or estimator or "the drive's",
           "board_config": os.path.relpath(config_toml, cb.ROOT), "flash_image_checked": elf_ok,
           "periods": int(info.get("periods", "0")), "steps": int(info.get("steps", "0")),
           "mismatches": int(info.get("mismatches", "-1")), "overruns": int(info.get("overruns", "-1")),
           "systick_hz_measured": round(systick_hz), "control_period_us_min": round(period_us[0], 2),
           "control_period_us_max": round(period_us[1], 2), "control_period_us_mean": round(mean_us, 3),
           "crystal_missing_gives_fault_1": hse_ok,
           "pass": ok}
    # the drive designed on the board from its parameters' defaults
    # (main_qemu.c): its bytes against the host's design of them, its time
    if "design_bytes" in info:
        ticks = int(info.get("design_ticks_hi", "0")) * 2 ** 32 + int(info.get("design_ticks", "0"))
        res.update({"design_on_board_config_bytes": int(info["design_bytes"]),
                    "design_on_board_bytes_differing": int(info.get("design_differ", "-1")),
                    "design_on_board_instr": round(ticks / ticks_per_instr) if ticks_per_instr else None,
                    # the drive's init from it: what the flashable image's
                    # control interrupt runs when it takes a configuration
                    "design_on_board_init_instr": round(int(info.get("design_init_ticks", "0")) / ticks_per_instr)
                    if ticks_per_instr else None})
    res.update(stats(isr, "isr"))
    res.update(stats(step, "drive_step"))
    if "isr_instr_mean" in res and "drive_step_instr_mean" in res:
        res["hal_around_step_instr_mean"] = round(res["isr_instr_mean"] - res["drive_step_instr_mean"], 1)
    period_instr = SYSCLK_HZ * CONTROL_PERIOD_S
    for k in ("isr_instr_mean", "isr_instr_max"):
        if k in res:
            res[k.replace("_instr_", "_period_share_")] = round(res[k] / period_instr, 4)
    sz = cb.size_of([os.path.join(bdir, "stm32_qemu.elf")])
    res["qemu_image_flash_bytes"] = sz["text"] + sz["data"]
    # the flashable image: its flash (code, constants, .data's initial
    # values) and its static RAM (.data, .bss; the stack takes the rest)
    sec = sections(os.path.join(bdir, "firmware.elf"))
    res["firmware_flash_bytes"] = sum(sec.get(k, 0) for k in (".isr_vector", ".text", ".ARM.exidx", ".data"))
    res["firmware_ram_bytes"] = sum(sec.get(k, 0) for k in (".data", ".bss"))
    if a.check_budget:
        # the share of the period every image keeps, and the drive's own
        # ([stm32] of its tools.toml): on the whole interrupt (paper 001's,
        # as before the images were per pair) and on its step (paper 002's:
        # its PIL target on the float M4F, for the images of its own
        # estimator only)
        budget = {"isr_period_share_max": PERIOD_SHARE_MAX, "firmware_flash_bytes": FLASH_BYTES_MAX}
        budget.update({"isr_" + k: lim for k, lim in facts.stm32.isr.items()})
        if not variant:
            budget.update({"drive_step_" + k: lim for k, lim in facts.step_budget().items()})
        res["budget"] = budget
        misses = [k for k, lim in budget.items() if res.get(k, 1e9) > lim]
        res["within_budget"] = not misses
        if misses:
            res["budget_missed"] = misses
        ok = ok and not misses
    if not ok:
        cb.log(out[-3000:])
    res["pass"] = ok
    return res


def sections(elf):
    """{section name: bytes} of an ELF (arm-none-eabi-size -A): the
    flash and the static RAM by section, the stack's reservation apart
    (`size`'s bss counts it)."""
    out = cb.run(["arm-none-eabi-size", "-A", elf])
    sec = {}
    for line in out.splitlines():
        f = line.split()
        if len(f) == 3 and f[0].startswith(".") and f[1].isdigit():
            sec[f[0]] = int(f[1])
    return sec


def images():
    """Every image: (drive, board, variant) of each board configuration
    firmware/drives/<drive>/boards/<board>[_<variant>].toml (as
    tests/firmware/CMakeLists.txt finds them)."""
    out = []
    for path in sorted(glob.glob(os.path.join(cb.ROOT, "firmware", "drives", "*", "boards", "*.toml"))):
        m = re.match(r"([a-z0-9]+)(?:_([a-z0-9_]+))?$", os.path.splitext(os.path.basename(path))[0])
        if m:
            out.append((os.path.basename(os.path.dirname(os.path.dirname(path))), m.group(1), m.group(2) or ""))
    return out


def preset_var(name, key):
    """A cache variable of a configure preset (CMakePresets.json, through its
    inherits), or None."""
    presets = json.load(open(os.path.join(cb.ROOT, "CMakePresets.json")))["configurePresets"]
    byname = {p["name"]: p for p in presets}
    p = byname.get(name)
    while p is not None:
        if key in p.get("cacheVariables", {}):
            return p["cacheVariables"][key]
        p = byname.get(p.get("inherits"))
    return None


def preset_of(drive, board, variant):
    """The configure preset of an image (CMakePresets.json), or None."""
    for p in json.load(open(os.path.join(cb.ROOT, "CMakePresets.json")))["configurePresets"]:
        n = p["name"]
        image = (preset_var(n, "MC_DRIVE"), preset_var(n, "MC_BOARD"), preset_var(n, "MC_DRIVE_VARIANT") or "")
        if preset_var(n, "MC_STM32F405") == "ON" and image == (drive, board, variant):
            return n
    return None


def markdown(results):
    """The cost table of the board README (hal/backends/stm32f405/README.md)."""
    period = SYSCLK_HZ * CONTROL_PERIOD_S
    lines = ["| image (preset) | drive's estimator | periods, bit for bit | drive step: mean / max | "
             "control interrupt: mean / max | share of the 100 us period at 168 MHz: mean / max |",
             "| --- | --- | --- | --- | --- | --- |"]
    for r in results:
        name = "`%s`" % r["image"] + (" (`%s`)" % r["preset"] if r.get("preset") else "")
        lines.append("| %s | %s | %s | %s / %s | %s / %s | %.1f %% / %.1f %% |" % (
            name,
            r.get("estimator"), "%d, %s" % (r.get("periods", 0), "yes" if r.get("mismatches") == 0 else "NO"),
            "{:,.1f}".format(r.get("drive_step_instr_mean", 0)), "{:,}".format(r.get("drive_step_instr_max", 0)),
            "{:,.1f}".format(r.get("isr_instr_mean", 0)), "{:,}".format(r.get("isr_instr_max", 0)),
            100.0 * r.get("isr_instr_mean", 0) / period, 100.0 * r.get("isr_instr_max", 0) / period))
    return "\n".join(lines)


def main():
    try:
        facts = drive_facts.load_all()
    except drive_facts.FactsError as e:
        cb.log("stm32_qemu.py: %s" % e)
        return 2
    # the default image: the stm32f405 preset's (drive, board)
    drive0, board0 = preset_var("stm32f405", "MC_DRIVE"), preset_var("stm32f405", "MC_BOARD")
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--drive", default=drive0,
                    help="a drive of the registry: %s (default %s, the stm32f405 preset's)"
                         % (", ".join(facts), drive0))
    ap.add_argument("--board", default=board0,
                    help="a board of hal/backends/stm32f405/boards/ (default %s, the stm32f405 preset's)" % board0)
    ap.add_argument("--variant", default="",
                    help="a variant of the drive's configuration for the board "
                         "(firmware/drives/<drive>/boards/<board>_<variant>.toml)")
    ap.add_argument("--scenario", default=None,
                    help="default: the drive's benchmark (scenario of firmware/drives/<drive>/tools.toml)")
    ap.add_argument("--max-samples", type=int, default=12000,
                    help="periods replayed (default 12000: 1.2 s, through the start into closed loop)")
    ap.add_argument("--shift", type=int, default=3,
                    help="qemu -icount shift (default 3: 8 ns an instruction, 12500 per 100 us period)")
    ap.add_argument("--build-root", default=None, help="default build/stm32_qemu/<drive>_<board>[_<variant>]")
    ap.add_argument("--check-budget", action="store_true",
                    help="also fail when the interrupt exceeds its budget: at most PERIOD_SHARE_MAX of the period, "
                         "and the drive's PIL targets of the float M4F (pil.py) where it has them")
    ap.add_argument("--gen", help="mc_pil_gen of a host float build (default: build/host's, built if needed)")
    ap.add_argument("--all", action="store_true",
                    help="every image (every board configuration firmware/drives/*/boards/*.toml), one after another")
    ap.add_argument("--markdown", action="store_true",
                    help="the cost table of hal/backends/stm32f405/README.md instead of the JSON")
    a = ap.parse_args()
    if a.drive not in facts:
        ap.error("--drive %s: not a drive of the registry (%s)" % (a.drive, ", ".join(facts)))
    miss = cb.missing_tools()
    if miss:
        cb.log("stm32_qemu: missing " + ", ".join(miss))
        return cb.SKIP
    gen = a.gen or os.path.join(cb.ROOT, "build", "host", "tests", "firmware", "mc_pil_gen")
    if not a.gen:
        cb.run(["cmake", "--preset", "host"], cwd=cb.ROOT)
        cb.run(["cmake", "--build", os.path.dirname(os.path.dirname(os.path.dirname(gen))), "--target", "mc_pil_gen"],
               cwd=cb.ROOT)
    if a.all:
        results = []
        for drive, board, variant in images():
            if drive not in facts:
                cb.log("stm32_qemu.py: firmware/drives/%s/boards/: %s is not a drive of the registry" % (drive, drive))
                return 2
            scenario = a.scenario or str(facts[drive].scenario)
            r = run_image(a, facts[drive], board, variant, gen, scenario)
            r["preset"] = preset_of(drive, board, variant)
            results.append(r)
        ok = all(r["pass"] for r in results)
        print(markdown(results) if a.markdown else json.dumps(results, indent=2))
        return 0 if ok else 1
    scenario = a.scenario or str(facts[a.drive].scenario)
    res = run_image(a, facts[a.drive], a.board, a.variant, gen, scenario)
    res["preset"] = preset_of(a.drive, a.board, a.variant)
    print(markdown([res]) if a.markdown else json.dumps(res, indent=2))
    return 0 if res["pass"] else 1


if __name__ == "__main__":
    sys.exit(main())
