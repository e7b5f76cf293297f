#!/usr/bin/env python3
"""Processor-in-the-loop cost of the drives' control step on emulated Cortex-M.

For each numeric type (float on Cortex-M4F / mps2-an386, fixed point Q14.17
on Cortex-M3 / mps2-an385) and each drive of --drive (drives of the
registry, firmware/drives/registry.c):
  1. the HOST build of that type (preset host / host-fixed) runs the drive's
     scenario (drive + software plant, closed loop) and records, per period,
     the sample the drive got and the command it returned
     (mc_pil_gen, tools/bench/pil_gen.cpp) into a C file with the drive's
     configuration;
  2. the cross preset (cortex-m4f / cortex-m3-fixed) builds the firmware
     library and the bare-metal image mc_pil (hal/backends/mcu/pil_image.c,
     cmake -DMC_DRIVE=<drive>) with those vectors;
  3. qemu-system-arm runs the image with -icount: every <drive>_drive_step()
     is timed with SysTick and its outputs are compared BIT FOR BIT with the
     host's.

What this script knows of a drive comes from its facts file,
firmware/drives/<drive>/tools.toml (tools/lib/drive_facts.py): its
benchmark scenario (the default of --scenario), the numeric types its
design runs in, the prefix of its keys, the estimators measured one by one
(mc_pil_gen --estimator, whatever the scenario says), further images built
beside mc_pil, its probe's columns and its cost targets. The keys of one run
are <head><estimator>_<m4f_float|m3_fixed>_..., where <head> is "" for
the drive measured by default (paper 000's: m4f_float_instr_mean ...), the
drive's short name (p001_flux_m4f_float_...) or its name
(paper002_m4f_float_...): the whole step (instr_*, over all periods),
closed_loop_instr_* / open_loop_instr_* (periods that start and end in that
state), the CAN node's step, bit-exactness, sizes, stack. A drive with a
probe (tools/bench/pil_probes/<drive>_probe.c, linked into its image) has
its parts timed too: paper 001's, with the FLUX estimator, in every period
that starts and ends in closed loop, times the parts of the step on copies
of their states, replayed with the step's own inputs and checked bit for bit
against the drive's states afterwards: flux_observer_step (12)-(14),
speed_load_observer_step (I&I, (15)-(16)), ida_pbc_step (11, inline in the
step) and the two dq rotations (inline), each called through a noipa
wrapper that takes its arguments in one struct, minus an empty wrapper timed
in the same period (the same pointer + bl sequence): a part's count is its
body plus loading its arguments (and the bl for the library calls), as in
the step. Keys part_<flux_observer|ii|ida_pbc|frames>_instr_*,
part_fo_ida_instr_* (flux observer + IDA-PBC per period) and
part_fo_ida_frames_instr_* (+ the rotations).

Instruction counts: qemu's mps2 SysTick runs at the 25 MHz core clock (40 ns
a tick); with -icount shift=S an instruction lasts 2^S ns of virtual time.
With shift=0 a tick is 40 instructions, too coarse for one step; the default
shift=8 makes an instruction 6.4 ticks, so round(ticks * 40 / 2^S) is the
exact, repeatable instruction count (checked against straight-line nop
sequences when this was written). The count of an empty timed region
(the SysTick read itself) is subtracted. --shift 0 is accepted and gives the
40-instruction-resolution numbers.

Writes JSON to stdout; progress goes to stderr. --check exits 1 when an
image fails to run or an output differs from the host build (the ctest);
--check-targets also when a cost target of the drive's facts (paper 000:
float M4F mean <= 1000 and max <= 1200, fixed M3 mean <= 1500; paper 001:
flux observer + IDA-PBC on M4F float mean <= 600; paper 002: its step on
M4F float mean <= 2500) is missed; misses are always listed under
"target_misses". Exit 77 (ctest skip) when the arm toolchain or qemu is not
installed.

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
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # tools/: the toolbox
import crossbuild as cb  # noqa: E402
from lib import drive_facts  # noqa: E402

PREFIX = {"float": "m4f_float", "fixed": "m3_fixed"}


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


def parse_ci_stack(build_dir, root_fn):
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
    # the commands and the drive's signals after each step (pil_image.c)
    res[p + "_bit_exact_vs_host"] = (info.get("mismatches") == "0" and info.get("signal_mismatches") == "0"
                                     and ok_run)
    res[p + "_mismatches"] = int(info.get("mismatches", "-1"))
    res[p + "_signals"] = int(info.get("signals", "-1"))
    res[p + "_signal_mismatches"] = int(info.get("signal_mismatches", "-1"))
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
    # the image without the vectors: the rows of pil_rows and the signals'
    # hash of each period counted separately
    vec_bytes = n * (vectors_row_words(vec) + 1) * 4
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


def run_drive(facts, typ, est, args):
    """One run of drive facts.name on type typ (with estimator est, or the
    scenario's when None): keys <head>[<est>_]<m4f_float|m3_fixed>_*, with its
    further images' sizes and its probe's parts."""
    drive = facts.name
    preset, machine, _ = cb.PRESETS[typ]
    run, bdir, elf, vec = run_image(drive, typ, args, getattr(args, "scenario_" + drive),
                                    "pil_vectors_%s%s_%s.c" % (drive, "_" + est if est else "", typ),
                                    gen_extra=["--estimator", est] if est else [],
                                    extra_targets=facts.pil.images)
    p = run_prefix(facts, est, typ)
    res, instr, to_instr, calib = common_keys(p, run, args, bdir, elf, vec, drive, machine)
    for img in facts.pil.images:
        sz = cb.size_of([os.path.join(bdir, "hal", "backends", "mcu", img + ".elf")])
        what = img[len("mc_"):]
        res["%s_%s_image_flash_bytes" % (p, what)] = sz["text"] + sz["data"]
        res["%s_%s_image_ram_bytes" % (p, what)] = sz["data"] + sz["bss"]
    if facts.pil.probe is not None:
        res.update(probe_keys(facts.pil.probe, p, run, instr, to_instr, calib))
    return res


def run_prefix(facts, est, typ):
    """The prefix of one run's keys: <head>[<est>_]<m4f_float|m3_fixed>."""
    return facts.head() + (est + "_" if est else "") + PREFIX[typ]


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


def probe_keys(probe, p, run, instr, to_instr, calib):
    """The keys of a drive's probe (tools/bench/pil_probes/<drive>_probe.c):
    its lines P <period> <column>..., each part's count its column minus the
    first empty column after it (an empty call timed alike), the sums of its
    facts, the whole step in those periods and the rest, the call overhead
    subtracted (the first empty column), the mismatches of its replay."""
    parts, info = run["parts"], run["info"]
    n = int(info.get("n", "0"))
    res = {}
    if parts:
        count = {name: [to_instr(r[c]) - to_instr(r[e]) for r in parts] for name, c, e in probe.parts()}
        res[p + "_part_periods"] = len(parts)
        for name, _, _ in probe.parts():
            res.update(instr_stats(p + "_part_" + name, count[name]))
        for name, of in probe.sums.items():
            res.update(instr_stats(p + "_part_" + name, [sum(v) for v in zip(*(count[x] for x in of))]))
        if len(instr) == n:
            whole = [instr[r[0]] for r in parts]
            res.update(instr_stats(p + "_part_whole_step", whole))
            res[p + "_part_rest_instr_mean"] = round(
                (sum(whole) - sum(sum(v) for v in count.values())) / len(parts), 1)
        first = probe.first_empty()
        res[p + "_part_call_overhead_subtracted"] = round(sum(to_instr(r[first]) for r in parts) / len(parts) - calib,
                                                          1)
    res[p + "_part_mismatches"] = int(info.get("part_mismatches", "-1"))
    if parts:
        res[p + "_part_outputs_checked"] = int(info.get("part_outputs_checked", "0"))
    return res


def markdown_table(path, facts):
    """The cost table of drive facts.name (its keys without an estimator:
    the default drive's, m4f_float_... and m3_fixed_...) in a --results
    file, markdown on stdout."""
    try:
        with open(path) as f:
            r = json.load(f)
    except (OSError, ValueError) as e:
        print("pil.py: %s: %s" % (path, e), file=sys.stderr)
        return 2
    h, drive = facts.head(), facts.name
    cols = [(h + "m4f_float", "Cortex-M4F, float"), (h + "m3_fixed", "Cortex-M3, fixed point Q14.17")]
    if any(p + "_instr_mean" not in r for p, _ in cols):
        print("pil.py: %s: no results of the %s drive of both types (run pil.py --drive %s --results FILE)"
              % (path, drive, drive), file=sys.stderr)
        return 2
    tg = r.get("targets", {})

    def row(name, fmt, target=""):
        print("| %s | %s | %s | %s |" % (name, fmt(cols[0][0]), fmt(cols[1][0]), target))

    def n(x):
        return "{:,}".format(int(round(x)))

    def kb(x):
        return "%.1f KB" % (x / 1000.0)

    print("| | %s | %s | target |" % (cols[0][1], cols[1][1]))
    print("| --- | --- | --- | --- |")
    row("instructions per step, mean / max", lambda p: "%s / %s" % (n(r[p + "_instr_mean"]), n(r[p + "_instr_max"])),
        "mean ≤ %s (M4F), ≤ %s (M3); max ≤ %s (M4F)" % (n(tg.get(cols[0][0] + "_instr_mean", 0)),
                                                        n(tg.get(cols[1][0] + "_instr_mean", 0)),
                                                        n(tg.get(cols[0][0] + "_instr_max", 0))))
    row("the CAN node's step after it, mean / max",
        lambda p: "%s / %s" % (n(r[p + "_can_instr_mean"]), n(r[p + "_can_instr_max"])))
    row("firmware library flash, static RAM", lambda p: "%s, %d" % (kb(r[p + "_lib_flash_bytes"]),
                                                                    r[p + "_lib_ram_static_bytes"]))
    row("PIL image flash without the recorded vectors", lambda p: kb(r[p + "_pil_image_flash_bytes_without_vectors"]))
    row("`%s_drive_t` (all state)" % drive, lambda p: "%s B" % n(r[p + "_drive_state_ram_bytes"]))
    row("stack of `%s_drive_step`, static / measured" % drive,
        lambda p: "%d / %d B" % (r[p + "_step_stack_bytes_static"], r[p + "_step_stack_measured_bytes"]))
    row("periods, bit-exact with the host build",
        lambda p: "%s, %s" % (n(r[p + "_periods"]), "yes" if r.get(p + "_bit_exact_vs_host") else "NO"))
    print()
    lto = all(r.get(p + "_lto") for p, _ in cols)
    print("%s, %s, GCC %s, -O3%s; `%s`. Targets missed: %s."
          % (r.get(h + "scenario", "?"), r.get("date", "?"), r.get("gcc", "?"),
             " -flto (MC_LTO)" if lto else "", os.path.relpath(os.path.abspath(path), cb.ROOT),
             "; ".join(r.get("target_misses", [])) or "none"))
    return 0


def main():
    try:
        facts = drive_facts.load_all()
    except drive_facts.FactsError as e:
        print("pil.py: %s" % e, file=sys.stderr)
        return 2
    default = drive_facts.default_drive(facts)
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--types", default="float,fixed",
                    help="comma list of float,fixed (a drive runs those of its types, tools.toml)")
    ap.add_argument("--drive", default=default,
                    help="comma list of drives of the registry (firmware/drives/registry.c): %s (default %s: "
                         "the one whose keys carry no prefix)" % (", ".join(facts), default))
    ap.add_argument("--step-call", choices=["direct", "interface"], default="direct",
                    help="how the image calls the timed step (CMake MC_PIL_STEP_CALL): direct, the drive's "
                         "<name>_drive_step as drive_ops_t.step calls it (default), or interface, drive_step()")
    ap.add_argument("--estimators", "--estimator", default=None,
                    help="comma list of estimators, for the drives measured per estimator (default: each one's "
                         "pil.estimators of its tools.toml: %s)"
                         % "; ".join("%s %s" % (n, ",".join(f.pil.estimators)) for n, f in facts.items()
                                     if f.pil.estimators))
    ap.add_argument("--scenario", default=None,
                    help="scenario of the (one) drive of --drive (default: its benchmark, scenario of "
                         "firmware/drives/<drive>/tools.toml: %s)"
                         % ", ".join("%s %s" % (n, os.path.relpath(f.scenario, cb.ROOT)) for n, f in facts.items()))
    ap.add_argument("--max-samples", type=int, default=0, help="record at most N periods (0 = whole scenario)")
    ap.add_argument("--gen-float", default=None, help="mc_pil_gen of a float host build (default: build/host)")
    ap.add_argument("--gen-fixed", default=None, help="mc_pil_gen of a fixed host build (default: build/host-fixed)")
    ap.add_argument("--build-root", default=os.path.join(cb.ROOT, "build", "pil"))
    ap.add_argument("--shift", type=int, default=8, help="qemu -icount shift (default 8: exact counts)")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 when an image does not run to the end or an output differs from the host build")
    ap.add_argument("--check-targets", action="store_true",
                    help="also exit 1 when a cost target of the drive (pil.targets of its tools.toml) is missed")
    ap.add_argument("--results", default=None, help="also write the JSON to this file")
    ap.add_argument("--markdown", metavar="RESULTS.json", default=None,
                    help="run nothing: print the cost table of --drive (default %s) of a results file "
                         "(docs/benchmarks.md and docs/fixed_point.md embed it)" % default)
    args = ap.parse_args()
    drives = [d.strip() for d in (args.drive or "").split(",") if d.strip()]
    if not drives or any(d not in facts for d in drives):
        ap.error("--drive: comma list of drives of the registry: %s" % ", ".join(facts))
    if args.markdown:
        if len(drives) > 1:
            ap.error("--markdown: give one --drive with it")
        return markdown_table(args.markdown, facts[drives[0]])
    args.build_root = os.path.abspath(args.build_root)
    ests = {}  # drive -> the estimators measured one by one ([None]: the scenario's)
    for d in drives:
        ests[d] = list(facts[d].pil.estimators) or [None]
        if args.estimators is not None and facts[d].pil.estimators:
            ests[d] = [e.strip() for e in args.estimators.split(",") if e.strip()]
            if not ests[d] or any(e not in facts[d].estimators for e in ests[d]):
                ap.error("--estimators: comma list of %s (the %s drive's)" % (", ".join(facts[d].estimators), d))
    if args.scenario and len(drives) > 1:
        ap.error("--scenario: give one --drive with it")
    for d in drives:
        setattr(args, "scenario_" + d, os.path.abspath(args.scenario) if args.scenario else str(facts[d].scenario))
    miss = cb.missing_tools()
    if miss:
        print("SKIP: PIL needs %s (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm)"
              % ", ".join(miss), file=sys.stderr)
        return cb.SKIP
    types = [t.strip() for t in args.types.split(",") if t.strip()]
    out = {}
    for d in drives:
        h = facts[d].head()
        out[h + "scenario"] = os.path.relpath(getattr(args, "scenario_" + d), cb.ROOT)
        if facts[d].pil.estimators:
            # measured per estimator: these results are compared across
            # commits, the drive changing under them: say which tree
            out[h + "estimators"] = ests[d]
            out[h + "max_samples"] = args.max_samples or None
            try:
                head = subprocess.run(["git", "-C", cb.ROOT, "rev-parse", "--short", "HEAD"], stdout=subprocess.PIPE,
                                      stderr=subprocess.DEVNULL, text=True).stdout.strip()
                dirty = subprocess.run(["git", "-C", cb.ROOT, "status", "--porcelain", "--untracked-files=no"],
                                       stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout.strip()
                out[h + "git_head"] = head + ("-dirty" if dirty else "") if head else None
            except OSError:
                pass
    out.update({"date": datetime.date.today().isoformat(),
                "instr_counting": "SysTick ticks * 40 ns / 2^shift ns, minus the empty-region count"})
    targets = {}
    for d in drives:
        for (e, t), lims in facts[d].pil.targets.items():
            targets.update({"%s_%s" % (run_prefix(facts[d], e, t), k): lim for k, lim in lims.items()})
    out["targets"] = targets
    try:
        out["gcc"] = subprocess.run(["arm-none-eabi-gcc", "-dumpversion"], stdout=subprocess.PIPE,
                                    text=True).stdout.strip()
    except OSError:
        pass
    failures, misses = [], []
    for d in drives:
        f = facts[d]
        for e in ests[d]:
            for t in types:
                if t not in f.types:
                    cb.log("%s: no %s run (its design is %s only)" % (d, t, "/".join(f.types)))
                    continue
                r = run_drive(f, t, e, args)
                out.update(r)
                p = run_prefix(f, e, t)
                what = " ".join([d] + ([e] if e else []) + [t])
                if not r.get(p + "_image_ok"):
                    failures.append("%s: image did not run to PIL PASS" % what)
                if r.get(p + "_mismatches", -1) != 0:
                    failures.append("%s: %s outputs differ from the host build" % (what, r.get(p + "_mismatches")))
                if f.pil.probe is not None and r.get(p + "_part_mismatches", -1) != 0:
                    failures.append("%s: %s replayed parts differ from the drive's states"
                                    % (what, r.get(p + "_part_mismatches")))
                for k, lim in f.targets_of(e, t).items():
                    v = r.get("%s_%s" % (p, k))
                    if v is None:
                        misses.append("%s: %s not measured" % (what, k))
                    elif v > lim:
                        misses.append("%s: %s %s > target %s" % (what, k, v, lim))
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
