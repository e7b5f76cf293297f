#!/usr/bin/env python3
"""Processor-in-the-loop cost of the drive's control step on emulated Cortex-M.

For each numeric type (float on Cortex-M4F / mps2-an386, fixed point Q14.17
on Cortex-M3 / mps2-an385):
  1. the HOST build of that type (preset host / host-fixed) runs the paper-000
     scenario (drive + software plant, closed loop) and records, per period,
     the currents the drive got and the voltages it returned
     (mc_pil_gen, tools/bench/pil_gen.cpp) into a C file with the drive config;
  2. the cross preset (cortex-m4f / cortex-m3-fixed) builds the firmware
     library and the bare-metal image mc_pil (hal/backends/mcu/pil_main.c)
     with those vectors;
  3. qemu-system-arm runs the image with -icount: every drive_step() is timed
     with SysTick and its outputs are compared BIT FOR BIT with the host's.

Instruction counts: qemu's mps2 SysTick runs at the 25 MHz core clock (40 ns
a tick); with -icount shift=S an instruction lasts 2^S ns of virtual time.
With shift=0 a tick is 40 instructions, too coarse for one step; the default
shift=8 makes an instruction 6.4 ticks, so round(ticks * 40 / 2^S) is the
exact, repeatable instruction count (checked against straight-line nop
sequences when this was written). The count of an empty timed region
(the SysTick read itself) is subtracted. --shift 0 is accepted and gives the
40-instruction-resolution numbers.

Writes JSON to stdout (keys m4f_float_instr_mean/max/min, m3_fixed_instr_...,
sizes, stack, bit-exactness); progress goes to stderr. --check exits 1 when
an image fails to run or an output differs from the host build (the ctest);
--check-targets also when a cost target (float M4F mean <= 1000 and
max <= 1200, fixed M3 mean <= 1500) is missed; misses are always listed
under "target_misses".
Exit 77 (ctest skip) when the arm toolchain or qemu is not installed.

  tools/bench/pil.py                       # both types, full scenario
  tools/bench/pil.py --types fixed --max-samples 5000 --check
  tools/bench/pil.py --results tools/bench/results/pil_$(date +%F).json
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


def parse_ci_stack(build_dir, root_fn="drive_step"):
    """Worst stack depth from root_fn over the call graph GCC wrote with
    -fcallgraph-info=su (static frame sizes; calls into libgcc/newlib
    helpers that have no .ci entry count as 0 and are listed)."""
    frames, edges, dynamic = {}, {}, set()
    for ci in glob.glob(os.path.join(build_dir, "firmware", "**", "*.ci"), recursive=True):
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


def run_type(typ, args):
    preset, machine, _ = cb.PRESETS[typ]
    gen = host_generator(typ, getattr(args, "gen_" + typ))
    os.makedirs(args.build_root, exist_ok=True)
    vec = os.path.join(args.build_root, "pil_vectors_%s.c" % typ)
    cmd = [gen, args.scenario, vec]
    if args.max_samples:
        cmd.append(str(args.max_samples))
    cb.run(cmd)
    bdir = os.path.join(args.build_root, preset)
    cb.cross_build(preset, bdir, {"MC_PIL_VECTORS": vec, "MC_QEMU_SHIFT": args.shift},
                   targets=["mc_firmware", "mc_pil", "mc_selftest"])
    elf = os.path.join(bdir, "hal", "backends", "mcu", "mc_pil.elf")
    rc, out = cb.qemu(machine, elf, args.shift)
    ticks, info = [], {}
    for line in out.splitlines():
        if line.startswith("T "):
            ticks += [int(t) for t in line.split()[1:]]
        elif line.startswith("PIL "):
            for k, v in re.findall(r"(\w+)=(\S+)", line):
                info[k] = v
    scale = cb.TICK_NS / float(2 ** args.shift)
    to_instr = (lambda t: int(round(t * scale))) if args.shift >= 7 else (lambda t: t * scale)
    calib = to_instr(int(info.get("calib", 0)))
    instr = [to_instr(t) - calib for t in ticks]
    n = int(info.get("n", "0"))
    ok_run = (rc == 0 and "PIL PASS" in out and len(instr) == n and n > 0)
    res = {}
    p = PREFIX[typ]
    if instr:
        res[p + "_instr_mean"] = round(sum(instr) / len(instr), 1)
        res[p + "_instr_min"] = min(instr)
        res[p + "_instr_max"] = max(instr)
        res[p + "_instr_max_at_period"] = instr.index(max(instr))
        srt = sorted(instr)
        res[p + "_instr_p99"] = srt[min(len(srt) - 1, int(0.99 * len(srt)))]
    res[p + "_periods"] = len(instr)
    res[p + "_bit_exact_vs_host"] = (info.get("mismatches") == "0" and ok_run)
    res[p + "_mismatches"] = int(info.get("mismatches", "-1"))
    res[p + "_image_ok"] = ok_run
    lib = os.path.join(bdir, "firmware", "libmc_firmware.a")
    sz_lib = cb.size_of([lib])
    sz_img = cb.size_of([elf])
    res[p + "_lib_flash_bytes"] = sz_lib["text"] + sz_lib["data"]
    res[p + "_lib_ram_static_bytes"] = sz_lib["data"] + sz_lib["bss"]
    res[p + "_drive_state_ram_bytes"] = int(info.get("state_bytes", "0").split()[0]) if info.get("state_bytes") else None
    # the image without the vectors: rodata of pil_io counted separately
    vec_bytes = n * 16
    res[p + "_pil_image_flash_bytes"] = sz_img["text"] + sz_img["data"]
    res[p + "_pil_image_flash_bytes_without_vectors"] = sz_img["text"] + sz_img["data"] - vec_bytes
    res[p + "_pil_image_ram_bytes"] = sz_img["data"] + sz_img["bss"]
    sz_st = cb.size_of([os.path.join(bdir, "hal", "backends", "mcu", "mc_selftest.elf")])
    res[p + "_selftest_image_flash_bytes"] = sz_st["text"] + sz_st["data"]
    res[p + "_selftest_image_ram_bytes"] = sz_st["data"] + sz_st["bss"]
    st = parse_ci_stack(bdir)
    if st:
        res[p + "_step_stack_bytes_static"] = st["bytes"]
        res[p + "_step_stack_path"] = st["path"]
        res[p + "_step_stack_external_calls"] = st["external_calls_not_counted"]
    if "stack_used" in info:
        res[p + "_run_stack_measured_bytes"] = int(info["stack_used"])
        res[p + "_step_stack_measured_bytes"] = int(info["stack_used"]) - int(info.get("stack_main", 0))
    res[p + "_qemu"] = "%s -icount shift=%d" % (machine, args.shift)
    if not ok_run:
        cb.log(out[-3000:])
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--types", default="float,fixed", help="comma list of float,fixed")
    ap.add_argument("--scenario", default=os.path.join(cb.ROOT, "sim", "scenarios", "paper000_ideal.toml"))
    ap.add_argument("--max-samples", type=int, default=0, help="record at most N periods (0 = whole scenario)")
    ap.add_argument("--gen-float", default=None, help="mc_pil_gen of a float host build (default: build/host)")
    ap.add_argument("--gen-fixed", default=None, help="mc_pil_gen of a fixed host build (default: build/host-fixed)")
    ap.add_argument("--build-root", default=os.path.join(cb.ROOT, "build", "pil"))
    ap.add_argument("--shift", type=int, default=8, help="qemu -icount shift (default 8: exact counts)")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 when an image does not run to the end or an output differs from the host build")
    ap.add_argument("--check-targets", action="store_true",
                    help="also exit 1 when a cost target is missed (float M4F mean/max, fixed M3 mean)")
    ap.add_argument("--results", default=None, help="also write the JSON to this file")
    args = ap.parse_args()
    args.build_root = os.path.abspath(args.build_root)
    miss = cb.missing_tools()
    if miss:
        print("SKIP: PIL needs %s (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm)"
              % ", ".join(miss), file=sys.stderr)
        return cb.SKIP
    types = [t.strip() for t in args.types.split(",") if t.strip()]
    out = {"scenario": os.path.relpath(args.scenario, cb.ROOT), "date": datetime.date.today().isoformat(),
           "instr_counting": "SysTick ticks * 40 ns / 2^shift ns, minus the empty-region count",
           "targets": {"m4f_float_instr_mean": 1000, "m4f_float_instr_max": 1200, "m3_fixed_instr_mean": 1500}}
    try:
        out["gcc"] = subprocess.run(["arm-none-eabi-gcc", "-dumpversion"], stdout=subprocess.PIPE,
                                    text=True).stdout.strip()
    except OSError:
        pass
    failures, misses = [], []
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
