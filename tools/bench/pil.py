#!/usr/bin/env python3
"""Processor-in-the-loop cost of the drives' control step on emulated Cortex-M.

For each numeric type (float on Cortex-M4F / mps2-an386, fixed point Q14.17
on Cortex-M3 / mps2-an385):
  1. the HOST build of that type (preset host / host-fixed) runs the paper-000
     scenario (drive + software plant, closed loop) and records, per period,
     the currents the drive got and the voltages it returned
     (mc_pil_gen, tools/bench/pil_gen.cpp) into a C file with the drive config;
  2. the cross preset (cortex-m4f / cortex-m3-fixed) builds the firmware
     library and the bare-metal image mc_pil (hal/backends/mcu/pil_main.c)
     with those vectors;
  3. qemu-system-arm runs the image with -icount: every paper000_drive_step() is timed
     with SysTick and its outputs are compared BIT FOR BIT with the host's.

--drive paper001 (or --drive paper000,paper001) does the same for the
paper-001 speed drive (paper001_drive_step, drives/paper001/paper001_drive.h) on a
[speed] scenario (default sim/scenarios/paper001_benchmark.toml, the 3-phase
PMSM benchmark), once per estimator of --estimators (default
flux,back_emf; mc_pil_gen --estimator sets paper001_config_t.estimator
whatever the scenario says): the host records the three phase currents, the
bus voltage and the three phase voltages per period, the image
(hal/backends/mcu/pil_paper001_main.c, cmake -DMC_PIL_DRIVE=paper001)
replays them and compares the three voltages bit for bit. With the FLUX
estimator, in every period that starts and ends in closed loop, the image
also times the parts of the step on copies of their states, replayed with
the step's own inputs and checked bit for bit against the drive's states
afterwards: flux_observer_step (12)-(14), speed_load_observer_step (I&I,
(15)-(16)), ida_pbc_step (11, inline in the step) and the two dq rotations
(inline), each called through a noipa wrapper that takes its arguments in
one struct, minus an empty wrapper timed in the same period (the same
pointer + bl sequence): a part's count is its body plus loading its
arguments (and the bl for the library calls), as in the step.
Keys p001_<estimator>_<m4f_float|m3_fixed>_...: the whole step (instr_*,
over all periods), closed_loop_instr_* / open_loop_instr_* (periods that
start and end in that state), part_<flux_observer|ii|ida_pbc|frames>_instr_*,
part_fo_ida_instr_* (flux observer + IDA-PBC per period) and
part_fo_ida_frames_instr_* (+ the rotations). Target: flux observer +
IDA-PBC on M4F float, mean <= 600 instructions.

Instruction counts: qemu's mps2 SysTick runs at the 25 MHz core clock (40 ns
a tick); with -icount shift=S an instruction lasts 2^S ns of virtual time.
With shift=0 a tick is 40 instructions, too coarse for one step; the default
shift=8 makes an instruction 6.4 ticks, so round(ticks * 40 / 2^S) is the
exact, repeatable instruction count (checked against straight-line nop
sequences when this was written). The count of an empty timed region
(the SysTick read itself) is subtracted. --shift 0 is accepted and gives the
40-instruction-resolution numbers.

Writes JSON to stdout (keys m4f_float_instr_mean/max/min, m3_fixed_instr_...,
sizes, stack, bit-exactness; p001_... for --drive paper001); progress goes
to stderr. --check exits 1 when an image fails to run or an output differs
from the host build (the ctest); --check-targets also when a cost target
(paper 000: float M4F mean <= 1000 and max <= 1200, fixed M3 mean <= 1500;
paper 001: flux observer + IDA-PBC on M4F float mean <= 600) is missed;
misses are always listed under "target_misses".
Exit 77 (ctest skip) when the arm toolchain or qemu is not installed.

  tools/bench/pil.py                       # paper 000, both types, full scenario
  tools/bench/pil.py --types fixed --max-samples 5000 --check
  tools/bench/pil.py --results tools/bench/results/pil_$(date +%F).json
  tools/bench/pil.py --drive paper001      # paper 001, both estimators, both types
  tools/bench/pil.py --drive paper001 --estimators flux --types float
  tools/bench/pil.py --drive paper001 --results tools/bench/results/pil_paper001_$(date +%F).json
"""
import argparse
import datetime
import glob
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import crossbuild as cb  # noqa: E402

TARGETS = {"float": {"mean": 1000, "max": 1200}, "fixed": {"mean": 1500}}
PREFIX = {"float": "m4f_float", "fixed": "m3_fixed"}
# paper 001: (estimator, type) -> {key suffix: limit}
P001_TARGETS = {("flux", "float"): {"part_fo_ida_instr_mean": 600}}
DEFAULT_SCENARIO = {"paper000": os.path.join(cb.ROOT, "sim", "scenarios", "paper000_ideal.toml"),
                    "paper001": os.path.join(cb.ROOT, "sim", "scenarios", "paper001_benchmark.toml")}
# the other drives' benchmarks (any drive of the registry runs: without an
# entry here, the first scenario of sim/scenarios/ with [drive] kind = it)
DEFAULT_SCENARIO.update({
    "paper002": os.path.join(cb.ROOT, "sim", "scenarios", "paper002_reference.toml"),
    "sensored_foc": os.path.join(cb.ROOT, "sim", "scenarios", "sensored_benchmark.toml")})
# numeric types a drive runs in (default both): paper 002's design and
# scenario are float only (docs/paper002.md)
DRIVE_TYPES = {"paper002": ("float",)}
# (drive, type) -> {key suffix: limit} of the other drives: paper 002's
# budget of issue 14 (EKF + MTPA + current control + SOSMC <= 2,500 on the
# M4F), here on its whole step
DRIVE_TARGETS = {("paper002", "float"): {"instr_mean": 2500}}


def host_generator(typ, given):
    if given:
        return given
    host_preset = cb.PRESETS[typ][2]
    bdir = os.path.join(cb.ROOT, "build", host_preset)
    exe = os.path.join(bdir, "tests", "firmware", "mc_pil_gen")
    cb.log("building %s (preset %s)" % (exe, host_preset))
    cb.run(["cmake", "--preset", host_preset], cwd=cb.ROOT)
    cb.run(["cmake", "--build", bdir, "--target", "mc_pil_gen"], cwd=cb.ROOT)
    return exe


def ci_files(build_dir):
    """The call-graph files of the code the PIL image runs: with link-time
    optimisation (CMake MC_LTO) the link's own, <image>.elf.ltrans*.ci
    beside the image (written by this link: not older than the image),
    else the firmware library's objects'."""
    elf = os.path.join(build_dir, "hal", "backends", "mcu", "mc_pil.elf")
    ltrans = glob.glob(elf + ".ltrans*.ci")
    if ltrans and os.path.exists(elf) and all(os.path.getmtime(f) >= os.path.getmtime(elf) - 5 for f in ltrans):
        return ltrans
    return glob.glob(os.path.join(build_dir, "firmware", "**", "*.ci"), recursive=True)


def parse_ci_stack(build_dir, root_fn="paper000_drive_step"):
    """Worst stack depth from root_fn over the call graph GCC wrote with
    -fcallgraph-info=su (static frame sizes; calls into libgcc/newlib
    helpers that have no .ci entry count as 0 and are listed)."""
    frames, edges, dynamic = {}, {}, set()
    for ci in ci_files(build_dir):
        text = open(ci).read()
        for m in re.finditer(r'node: \{ title: "([^"]+)" label: "([^"]*)"', text):
            title, label = m.group(1), m.group(2)
            name = title.split(":")[-1]
            b = re.search(r"(\d+) bytes \(([a-z,]+)\)", label)
            if b:
                frames[name] = max(frames.get(name, 0), int(b.group(1)))
                if "dynamic" in b.group(2) and "bounded" not in b.group(2):
                    dynamic.add(name)
        for m in re.finditer(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"', text):
            edges.setdefault(m.group(1).split(":")[-1], set()).add(m.group(2).split(":")[-1])
    unknown = set()

    def depth(fn, seen):
        if fn in seen:
            return 0  # recursion: none in the firmware, flagged by the caller
        if fn not in frames:
            unknown.add(fn)
            return 0
        return frames[fn] + max([depth(c, seen | {fn}) for c in edges.get(fn, ())] + [0])

    if root_fn not in frames:
        return None
    worst = depth(root_fn, set())
    path, fn = [root_fn], root_fn
    while edges.get(fn):
        kids = [c for c in edges[fn] if c in frames and c not in path]
        if not kids:
            break
        fn = max(kids, key=lambda c: depth(c, set(path)))
        path.append(fn)
    ext = sorted(u for u in unknown if not u.startswith("mc_"))
    return {"bytes": worst, "path": path, "external_calls_not_counted": ext,
            "dynamic_frames": sorted(dynamic)}


def registry_drives():
    """The drives of firmware/drives/registry.c (each `&<name>_drive_ops`), in its order."""
    with open(os.path.join(cb.ROOT, "firmware", "drives", "registry.c")) as f:
        return re.findall(r"&(\w+)_drive_ops", f.read())


def default_scenario(drive):
    """The drive's benchmark scenario: DEFAULT_SCENARIO's, else the first of
    sim/scenarios/ with [drive] kind = "<drive>"."""
    if drive in DEFAULT_SCENARIO:
        return DEFAULT_SCENARIO[drive]
    for path in sorted(glob.glob(os.path.join(cb.ROOT, "sim", "scenarios", "*.toml"))):
        if re.search(r'^kind\s*=\s*"%s"' % re.escape(drive), open(path).read(), re.M):
            return path
    return None


def vectors_row_words(vec):
    m = re.search(r"pil_row_words = (\d+)u", open(vec).read())
    return int(m.group(1)) if m else 0


def run_image(drive, typ, args, scenario, vec_name, gen_extra=(), extra_targets=()):
    """Records the vectors of drive on the host build of typ, builds the PIL
    image for that drive (cmake -DMC_DRIVE) and runs it under qemu. Returns
    (the image's output parsed, its build folder, its ELF, the vectors file)."""
    preset, machine, _ = cb.PRESETS[typ]
    gen = host_generator(typ, getattr(args, "gen_" + typ))
    os.makedirs(args.build_root, exist_ok=True)
    vec = os.path.join(args.build_root, vec_name)
    cmd = [gen, "--drive", drive] + list(gen_extra) + [scenario, vec]
    if args.max_samples:
        cmd.append(str(args.max_samples))
    cb.run(cmd)
    bdir = os.path.join(args.build_root, preset)
    cb.cross_build(preset, bdir, {"MC_PIL_VECTORS": vec, "MC_QEMU_SHIFT": args.shift, "MC_DRIVE": drive,
                                  "MC_PIL_STEP_CALL": args.step_call},
                   targets=["mc_firmware", "mc_pil"] + list(extra_targets))
    elf = os.path.join(bdir, "hal", "backends", "mcu", "mc_pil.elf")
    rc, out = cb.qemu(machine, elf, args.shift)
    run = {"rc": rc, "out": out, "ticks": [], "can": [], "states": "", "parts": [], "info": {}}
    for line in out.splitlines():
        if line.startswith("T "):
            run["ticks"] += [int(t) for t in line.split()[1:]]
        elif line.startswith("C "):
            run["can"] += [int(t) for t in line.split()[1:]]
        elif line.startswith("S "):
            run["states"] += line[2:].strip()
        elif line.startswith("P "):
            run["parts"].append([int(t) for t in line.split()[1:]])
        elif line.startswith("PIL "):
            for k, v in re.findall(r"(\w+)=(\S+)", line):
                run["info"][k] = v
    return run, bdir, elf, vec


def common_keys(p, run, args, bdir, elf, vec, drive, machine):
    """The keys every drive's run has, prefixed p: the step's instructions
    (all periods, and by supervisor state), the CAN node's, bit-exactness,
    sizes, stack, the qemu line. Returns (keys, instr, to_instr, calib)."""
    info = run["info"]
    scale = cb.TICK_NS / float(2 ** args.shift)
    to_instr = (lambda t: int(round(t * scale))) if args.shift >= 7 else (lambda t: t * scale)
    calib = to_instr(int(info.get("calib", 0)))
    instr = [to_instr(t) - calib for t in run["ticks"]]
    # the CAN node's step after each control step (telemetry at the
    # default rates, the queue drained), timed apart
    can_instr = [to_instr(t) - calib for t in run["can"]]
    n = int(info.get("n", "0"))
    states = run["states"]
    ok_run = (run["rc"] == 0 and "PIL PASS" in run["out"] and len(instr) == n and n > 0 and len(states) == n)
    res = {}
    res.update(instr_stats(p, instr))
    if instr:
        res[p + "_instr_max_at_period"] = instr.index(max(instr))
    if can_instr:
        res[p + "_can_instr_mean"] = round(sum(can_instr) / len(can_instr), 1)
        res[p + "_can_instr_max"] = max(can_instr)
    res[p + "_periods"] = len(instr)
    # by supervisor state: periods that start and end in the same state
    # (state before period i = state after period i-1)
    names = {"1": "open_loop", "2": "closed_loop"}
    if len(states) == len(instr) and instr:
        for code, name in names.items():
            sel = [instr[i] for i in range(len(instr)) if states[i] == code and states[max(i - 1, 0)] == code]
            res.update(instr_stats(p + "_" + name, sel))
            res[p + "_" + name + "_periods"] = len(sel)
        first_closed = states.find("2")
        res[p + "_first_closed_loop_period"] = first_closed if first_closed >= 0 else None
        res[p + "_transition_periods"] = sum(1 for i in range(1, len(states)) if states[i] != states[i - 1])
        res[p + "_final_state"] = {"0": "identify", "1": "open_loop", "2": "closed_loop", "3": "fault"}.get(
            states[-1:], states[-1:])
    res[p + "_bit_exact_vs_host"] = (info.get("mismatches") == "0" and ok_run)
    res[p + "_mismatches"] = int(info.get("mismatches", "-1"))
    res[p + "_image_ok"] = ok_run
    res[p + "_step_call"] = "interface (drive_step)" if info.get("step_via_interface") == "1" else \
        "direct (%s_drive_step)" % drive
    lib = os.path.join(bdir, "firmware", "libmc_firmware.a")
    sz_lib = cb.size_of([lib])
    sz_img = cb.size_of([elf])
    res[p + "_lib_flash_bytes"] = sz_lib["text"] + sz_lib["data"]
    res[p + "_lib_ram_static_bytes"] = sz_lib["data"] + sz_lib["bss"]
    res[p + "_drive_state_ram_bytes"] = int(info["state_bytes"]) if "state_bytes" in info else None
    res[p + "_drive_config_bytes"] = int(info["cfg_bytes"]) if "cfg_bytes" in info else None
    # the image without the vectors: the rows of pil_rows counted separately
    vec_bytes = n * vectors_row_words(vec) * 4
    res[p + "_pil_image_flash_bytes"] = sz_img["text"] + sz_img["data"]
    res[p + "_pil_image_flash_bytes_without_vectors"] = sz_img["text"] + sz_img["data"] - vec_bytes
    res[p + "_pil_image_ram_bytes"] = sz_img["data"] + sz_img["bss"]
    linked = linked_firmware_bytes(os.path.join(bdir, "hal", "backends", "mcu", "mc_pil.map"))
    if linked:
        # the part of the library the drive pulls in
        res[p + "_image_firmware_flash_bytes"] = linked["flash"]
        res[p + "_image_firmware_ram_static_bytes"] = linked["ram"]
    # link-time optimisation (CMake MC_LTO): the link wrote its own call graph
    res[p + "_lto"] = bool(glob.glob(elf + ".ltrans*.ci"))
    stack_and_qemu(res, p, parse_ci_stack(bdir, drive + "_drive_step"), info,
                   "%s -icount shift=%d" % (machine, args.shift))
    if not ok_run:
        cb.log(run["out"][-3000:])
    return res, instr, to_instr, calib


def run_type(typ, args):
    """Paper 000's position drive on type typ (keys m4f_float_* / m3_fixed_*)."""
    preset, machine, _ = cb.PRESETS[typ]
    run, bdir, elf, vec = run_image("paper000", typ, args, args.scenario_paper000, "pil_vectors_%s.c" % typ,
                                    extra_targets=["mc_selftest"])
    p = PREFIX[typ]
    res, _, _, _ = common_keys(p, run, args, bdir, elf, vec, "paper000", machine)
    sz_st = cb.size_of([os.path.join(bdir, "hal", "backends", "mcu", "mc_selftest.elf")])
    res[p + "_selftest_image_flash_bytes"] = sz_st["text"] + sz_st["data"]
    res[p + "_selftest_image_ram_bytes"] = sz_st["data"] + sz_st["bss"]
    return res


def run_generic(drive, typ, args):
    """Any other drive of the registry on type typ (keys <drive>_<m4f_float|m3_fixed>_*)."""
    preset, machine, _ = cb.PRESETS[typ]
    run, bdir, elf, vec = run_image(drive, typ, args, getattr(args, "scenario_" + drive),
                                    "pil_vectors_%s_%s.c" % (drive, typ))
    res, _, _, _ = common_keys("%s_%s" % (drive, PREFIX[typ]), run, args, bdir, elf, vec, drive, machine)
    return res


def stack_and_qemu(res, p, st, info, qemu):
    """The stack keys of one image's results (static from the compiler's
    call graph st, measured from the image's painted stack) and its QEMU line."""
    if st:
        res[p + "_step_stack_bytes_static"] = st["bytes"]
        res[p + "_step_stack_path"] = st["path"]
        res[p + "_step_stack_external_calls"] = st["external_calls_not_counted"]
    if "stack_used" in info:
        res[p + "_run_stack_measured_bytes"] = int(info["stack_used"])
        res[p + "_step_stack_measured_bytes"] = int(info["stack_used"]) - int(info.get("stack_main", 0))
    res[p + "_qemu"] = qemu


def instr_stats(prefix, instr):
    """mean/min/max/p99 of a list of instruction counts, keys prefix_instr_*."""
    res = {}
    if instr:
        res[prefix + "_instr_mean"] = round(sum(instr) / len(instr), 1)
        res[prefix + "_instr_min"] = min(instr)
        res[prefix + "_instr_max"] = max(instr)
        srt = sorted(instr)
        res[prefix + "_instr_p99"] = srt[min(len(srt) - 1, int(0.99 * len(srt)))]
    return res


def linked_firmware_bytes(map_path):
    """Flash (text, rodata, data) and RAM (data, bss) bytes of the
    libmc_firmware.a sections the linker kept in an image (its .map file)."""
    try:
        text = open(map_path).read()
    except OSError:
        return None
    text = text[text.find("Linker script and memory map"):]
    flash = ram = 0
    for m in re.finditer(r"^ (\.text\S*|\.rodata\S*|\.data\S*|\.bss\S*)\s*\n?\s+0x[0-9a-f]+\s+0x([0-9a-f]+)\s+(\S+)",
                         text, re.M):
        sec, size, obj = m.group(1), int(m.group(2), 16), m.group(3)
        if "libmc_firmware.a" not in obj:
            continue
        if not sec.startswith(".bss"):
            flash += size
        if sec.startswith((".data", ".bss")):
            ram += size
    # none with link-time optimisation (CMake MC_LTO): the map names the
    # link's ltrans objects, not the library's, so there is no such split
    return {"flash": flash, "ram": ram} if flash else None


def run_p001(typ, est, args):
    """The paper-001 speed drive with estimator est (flux | back_emf) on type
    typ; its probe (tools/bench/pil_probes/paper001_probe.c) times the parts."""
    preset, machine, _ = cb.PRESETS[typ]
    run, bdir, elf, vec = run_image("paper001", typ, args, args.scenario_paper001,
                                    "pil_vectors_paper001_%s_%s.c" % (est, typ), gen_extra=["--estimator", est])
    p = "p001_%s_%s" % (est, PREFIX[typ])
    res, instr, to_instr, calib = common_keys(p, run, args, bdir, elf, vec, "paper001", machine)
    parts, info = run["parts"], run["info"]
    n = int(info.get("n", "0"))
    if parts:
        # P <period> <flux> <ii> <empty> <ida> <empty> <frames> <empty>: each
        # part's noipa wrapper minus its empty twin (same call sequence)
        flux = [to_instr(r[1]) - to_instr(r[3]) for r in parts]
        ii = [to_instr(r[2]) - to_instr(r[3]) for r in parts]
        ida = [to_instr(r[4]) - to_instr(r[5]) for r in parts]
        frames = [to_instr(r[6]) - to_instr(r[7]) for r in parts]
        res[p + "_part_periods"] = len(parts)
        res.update(instr_stats(p + "_part_flux_observer", flux))
        res.update(instr_stats(p + "_part_ii", ii))
        res.update(instr_stats(p + "_part_ida_pbc", ida))
        res.update(instr_stats(p + "_part_frames", frames))
        res.update(instr_stats(p + "_part_fo_ida", [a + b for a, b in zip(flux, ida)]))
        res.update(instr_stats(p + "_part_fo_ida_frames", [a + b + c for a, b, c in zip(flux, ida, frames)]))
        if len(instr) == n:
            whole = [instr[r[0]] for r in parts]
            res.update(instr_stats(p + "_part_whole_step", whole))
            res[p + "_part_rest_instr_mean"] = round(
                (sum(whole) - sum(flux) - sum(ii) - sum(ida) - sum(frames)) / len(parts), 1)
        res[p + "_part_call_overhead_subtracted"] = round(sum(to_instr(r[3]) for r in parts) / len(parts) - calib, 1)
    res[p + "_part_mismatches"] = int(info.get("part_mismatches", "-1"))
    if parts:
        res[p + "_part_outputs_checked"] = int(info.get("part_outputs_checked", "0"))
    return res


def markdown_table(path):
    """The paper-000 drive's cost table of a --results file, markdown on stdout."""
    try:
        with open(path) as f:
            r = json.load(f)
    except (OSError, ValueError) as e:
        print("pil.py: %s: %s" % (path, e), file=sys.stderr)
        return 2
    cols = [("m4f_float", "Cortex-M4F, float"), ("m3_fixed", "Cortex-M3, fixed point Q14.17")]
    if any(p + "_instr_mean" not in r for p, _ in cols):
        print("pil.py: %s: no paper-000 results of both types (run pil.py --results FILE)" % path, file=sys.stderr)
        return 2
    tg = r.get("targets", {})

    def row(name, fmt, target=""):
        print("| %s | %s | %s | %s |" % (name, fmt("m4f_float"), fmt("m3_fixed"), target))

    def n(x):
        return "{:,}".format(int(round(x)))

    def kb(x):
        return "%.1f KB" % (x / 1000.0)

    print("| | %s | %s | target |" % (cols[0][1], cols[1][1]))
    print("| --- | --- | --- | --- |")
    row("instructions per step, mean / max", lambda p: "%s / %s" % (n(r[p + "_instr_mean"]), n(r[p + "_instr_max"])),
        "mean ≤ %s (M4F), ≤ %s (M3); max ≤ %s (M4F)" % (n(tg.get("m4f_float_instr_mean", 0)),
                                                        n(tg.get("m3_fixed_instr_mean", 0)),
                                                        n(tg.get("m4f_float_instr_max", 0))))
    row("the CAN node's step after it, mean / max",
        lambda p: "%s / %s" % (n(r[p + "_can_instr_mean"]), n(r[p + "_can_instr_max"])))
    row("firmware library flash, static RAM", lambda p: "%s, %d" % (kb(r[p + "_lib_flash_bytes"]),
                                                                    r[p + "_lib_ram_static_bytes"]))
    row("PIL image flash without the recorded vectors", lambda p: kb(r[p + "_pil_image_flash_bytes_without_vectors"]))
    row("`paper000_drive_t` (all state)", lambda p: "%s B" % n(r[p + "_drive_state_ram_bytes"]))
    row("stack of `paper000_drive_step`, static / measured",
        lambda p: "%d / %d B" % (r[p + "_step_stack_bytes_static"], r[p + "_step_stack_measured_bytes"]))
    row("periods, bit-exact with the host build",
        lambda p: "%s, %s" % (n(r[p + "_periods"]), "yes" if r.get(p + "_bit_exact_vs_host") else "NO"))
    print()
    lto = all(r.get(p + "_lto") for p, _ in cols)
    print("%s, %s, GCC %s, -O3%s; `%s`. Targets missed: %s."
          % (r.get("scenario", "?"), r.get("date", "?"), r.get("gcc", "?"),
             " -flto (MC_LTO)" if lto else "", os.path.relpath(os.path.abspath(path), cb.ROOT),
             "; ".join(r.get("target_misses", [])) or "none"))
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--types", default="float,fixed", help="comma list of float,fixed")
    ap.add_argument("--drive", default="paper000",
                    help="comma list of drives of the registry (firmware/drives/registry.c): %s (default "
                         "paper000)" % ", ".join(registry_drives()))
    ap.add_argument("--step-call", choices=["direct", "interface"], default="direct",
                    help="how the image calls the timed step (CMake MC_PIL_STEP_CALL): direct, the drive's "
                         "<name>_drive_step as drive_ops_t.step calls it (default), or interface, drive_step()")
    ap.add_argument("--estimators", "--estimator", default="flux,back_emf",
                    help="paper001 only: comma list of flux, back_emf (default both)")
    ap.add_argument("--scenario", default=None,
                    help="scenario of the (one) drive of --drive (default: sim/scenarios/paper000_ideal.toml, "
                         "paper001_benchmark.toml for paper001, paper002_reference.toml for paper002, "
                         "sensored_benchmark.toml for sensored_foc)")
    ap.add_argument("--max-samples", type=int, default=0, help="record at most N periods (0 = whole scenario)")
    ap.add_argument("--gen-float", default=None, help="mc_pil_gen of a float host build (default: build/host)")
    ap.add_argument("--gen-fixed", default=None, help="mc_pil_gen of a fixed host build (default: build/host-fixed)")
    ap.add_argument("--build-root", default=os.path.join(cb.ROOT, "build", "pil"))
    ap.add_argument("--shift", type=int, default=8, help="qemu -icount shift (default 8: exact counts)")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 when an image does not run to the end or an output differs from the host build")
    ap.add_argument("--check-targets", action="store_true",
                    help="also exit 1 when a cost target is missed (float M4F mean/max, fixed M3 mean; "
                         "paper001: flux observer + IDA-PBC M4F mean)")
    ap.add_argument("--results", default=None, help="also write the JSON to this file")
    ap.add_argument("--markdown", metavar="RESULTS.json", default=None,
                    help="run nothing: print the paper-000 cost table of a results file (docs/benchmarks.md and "
                         "docs/fixed_point.md embed it)")
    args = ap.parse_args()
    if args.markdown:
        return markdown_table(args.markdown)
    args.build_root = os.path.abspath(args.build_root)
    drives = [d.strip() for d in args.drive.split(",") if d.strip()]
    ests = [e.strip() for e in args.estimators.split(",") if e.strip()]
    known = registry_drives()
    if not drives or any(d not in known for d in drives):
        ap.error("--drive: comma list of drives of the registry: %s" % ", ".join(known))
    if not ests or any(e not in ("flux", "back_emf") for e in ests):
        ap.error("--estimators: comma list of flux, back_emf")
    if args.scenario and len(drives) > 1:
        ap.error("--scenario: give one --drive with it")
    for d in drives:
        sc = os.path.abspath(args.scenario) if args.scenario else default_scenario(d)
        if sc is None:
            ap.error("--drive %s: no scenario with [drive] kind = \"%s\" in sim/scenarios/: give --scenario" % (d, d))
        setattr(args, "scenario_" + d, sc)
    miss = cb.missing_tools()
    if miss:
        print("SKIP: PIL needs %s (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm)"
              % ", ".join(miss), file=sys.stderr)
        return cb.SKIP
    types = [t.strip() for t in args.types.split(",") if t.strip()]
    out = {}
    if "paper000" in drives:
        out["scenario"] = os.path.relpath(args.scenario_paper000, cb.ROOT)
    if "paper001" in drives:
        out["p001_scenario"] = os.path.relpath(args.scenario_paper001, cb.ROOT)
        out["p001_estimators"] = ests
        out["p001_max_samples"] = args.max_samples or None
        try:  # the drive changes under these snapshots: say which tree was measured
            head = subprocess.run(["git", "-C", cb.ROOT, "rev-parse", "--short", "HEAD"], stdout=subprocess.PIPE,
                                  stderr=subprocess.DEVNULL, text=True).stdout.strip()
            dirty = subprocess.run(["git", "-C", cb.ROOT, "status", "--porcelain", "--untracked-files=no"],
                                   stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout.strip()
            out["p001_git_head"] = head + ("-dirty" if dirty else "") if head else None
        except OSError:
            pass
    out.update({"date": datetime.date.today().isoformat(),
                "instr_counting": "SysTick ticks * 40 ns / 2^shift ns, minus the empty-region count"})
    targets = {}
    if "paper000" in drives:
        targets.update({"m4f_float_instr_mean": 1000, "m4f_float_instr_max": 1200, "m3_fixed_instr_mean": 1500})
    for (d, t), lims in DRIVE_TARGETS.items():
        if d in drives:
            targets.update({"%s_%s_%s" % (d, PREFIX[t], k): lim for k, lim in lims.items()})
    if "paper001" in drives:
        for (e, t), lims in P001_TARGETS.items():
            for k, lim in lims.items():
                targets["p001_%s_%s_%s" % (e, PREFIX[t], k)] = lim
    out["targets"] = targets
    try:
        out["gcc"] = subprocess.run(["arm-none-eabi-gcc", "-dumpversion"], stdout=subprocess.PIPE,
                                    text=True).stdout.strip()
    except OSError:
        pass
    failures, misses = [], []
    if "paper000" in drives:
        for t in types:
            r = run_type(t, args)
            out.update(r)
            p = PREFIX[t]
            if not r.get(p + "_image_ok"):
                failures.append("%s: image did not run to PIL PASS" % t)
            if r.get(p + "_mismatches", -1) != 0:
                failures.append("%s: %s outputs differ from the host build" % (t, r.get(p + "_mismatches")))
            for k, lim in TARGETS[t].items():
                v = r.get("%s_instr_%s" % (p, k))
                if v is None or v > lim:
                    misses.append("%s: instr %s %s > target %d" % (t, k, v, lim))
    if "paper001" in drives:
        for e in ests:
            for t in types:
                r = run_p001(t, e, args)
                out.update(r)
                p = "p001_%s_%s" % (e, PREFIX[t])
                what = "paper001 %s %s" % (e, t)
                if not r.get(p + "_image_ok"):
                    failures.append("%s: image did not run to PIL PASS" % what)
                if r.get(p + "_mismatches", -1) != 0:
                    failures.append("%s: %s outputs differ from the host build" % (what, r.get(p + "_mismatches")))
                if r.get(p + "_part_mismatches", -1) != 0:
                    failures.append("%s: %s replayed parts differ from the drive's states"
                                    % (what, r.get(p + "_part_mismatches")))
                for k, lim in P001_TARGETS.get((e, t), {}).items():
                    v = r.get("%s_%s" % (p, k))
                    if v is None:
                        misses.append("%s: %s not measured (no closed-loop period recorded)" % (what, k))
                    elif v > lim:
                        misses.append("%s: %s %s > target %d" % (what, k, v, lim))
    for d in drives:
        if d in ("paper000", "paper001"):
            continue
        out[d + "_scenario"] = os.path.relpath(getattr(args, "scenario_" + d), cb.ROOT)
        for t in types:
            if t not in DRIVE_TYPES.get(d, ("float", "fixed")):
                cb.log("%s: no %s run (its design is %s only)" % (d, t, "/".join(DRIVE_TYPES[d])))
                continue
            r = run_generic(d, t, args)
            out.update(r)
            p = "%s_%s" % (d, PREFIX[t])
            what = "%s %s" % (d, t)
            if not r.get(p + "_image_ok"):
                failures.append("%s: image did not run to PIL PASS" % what)
            if r.get(p + "_mismatches", -1) != 0:
                failures.append("%s: %s outputs differ from the host build" % (what, r.get(p + "_mismatches")))
            for k, lim in DRIVE_TARGETS.get((d, t), {}).items():
                v = r.get("%s_%s" % (p, k))
                if v is None or v > lim:
                    misses.append("%s: %s %s > target %d" % (what, k, v, lim))
    out["failures"] = failures
    out["target_misses"] = misses
    text = json.dumps(out, indent=2)
    print(text)
    if args.results:
        os.makedirs(os.path.dirname(os.path.abspath(args.results)), exist_ok=True)
        with open(args.results, "w") as f:
            f.write(text + "\n")
    for f in failures:
        cb.log("PIL FAIL:", f)
    for m in misses:
        cb.log("PIL target missed:", m)
    if args.check and failures:
        return 1
    if args.check_targets and misses:
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
