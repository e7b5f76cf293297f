#!/usr/bin/env python3
"""Where the control step's instructions go, per call site, on the emulated core.

Builds the PIL image of one numeric type with debug info (same -O level),
runs it under qemu-system-arm with one instruction per translation block and
exec logging, maps every executed PC through addr2line's inline chain, and
prints instructions PER PERIOD grouped by (mc_* operation, firmware source
line) and by operation. Use it to see which lines of firmware/ cost what:

  tools/bench/pil_profile.py --type fixed --samples 1000
  tools/bench/pil_profile.py --type float --by op

Instructions outside the drive's step (the harness, the inits) are left out. The log is
about 60 bytes per executed instruction: keep --samples to a few thousand.
"""
import argparse
import collections
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import crossbuild as cb  # noqa: E402
import pil  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--type", choices=["float", "fixed"], default="fixed")
    ap.add_argument("--samples", type=int, default=1000)
    ap.add_argument("--scenario", default=os.path.join(cb.ROOT, "sim", "scenarios", "paper000_ideal.toml"))
    ap.add_argument("--gen", default=None, help="mc_pil_gen of a host build of this type")
    ap.add_argument("--build-root", default=os.path.join(cb.ROOT, "build", "pil-profile"))
    ap.add_argument("--by", choices=["line", "op", "function"], default="line")
    ap.add_argument("--top", type=int, default=60)
    ap.add_argument("--estimator", default=None, help="mc_pil_gen --estimator (a drive measured per estimator)")
    ap.add_argument("--drive", default="paper000", help="the drive the image is built for (its scenario: --scenario)")
    args = ap.parse_args()
    miss = cb.missing_tools()
    if miss:
        print("SKIP: needs " + ", ".join(miss), file=sys.stderr)
        return cb.SKIP
    preset, machine, _ = cb.PRESETS[args.type]
    gen = pil.host_generator(args.type, args.gen)
    os.makedirs(args.build_root, exist_ok=True)
    vec = os.path.join(args.build_root, "pil_vectors_%s.c" % args.type)
    cb.run([gen] + (["--estimator", args.estimator] if args.estimator else []) + [args.scenario, vec, str(args.samples)])
    bdir = os.path.join(args.build_root, preset)
    cb.cross_build(preset, bdir, {"MC_PIL_VECTORS": vec, "MC_DRIVE": args.drive, "CMAKE_C_FLAGS_RELEASE": "-O3 -DNDEBUG -g -fno-ipa-icf"},
                   targets=["mc_pil"])
    elf = os.path.join(bdir, "hal", "backends", "mcu", "mc_pil.elf")
    log = os.path.join(args.build_root, "exec_%s.log" % args.type)
    cmd = ["qemu-system-arm", "-M", machine, "-nographic", "-monitor", "none", "-serial", "none",
           "-semihosting-config", "enable=on,target=native", "-icount", "shift=8", "-singlestep",
           "-d", "exec,nochain", "-D", log, "-kernel", elf]
    cb.log("+", " ".join(cmd))
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    cnt = collections.Counter()
    pat = re.compile(r"\[[0-9a-f]+/([0-9a-f]+)/")
    with open(log) as f:
        for line in f:
            m = pat.search(line)
            if m:
                cnt[int(m.group(1), 16)] += 1
    os.remove(log)
    pcs = sorted(cnt)
    out = subprocess.run(["arm-none-eabi-addr2line", "-a", "-f", "-i", "-e", elf] + ["0x%x" % p for p in pcs],
                         stdout=subprocess.PIPE, text=True).stdout.splitlines()
    chain, cur, i = {}, None, 0
    while i < len(out):
        if out[i].startswith("0x"):
            cur = int(out[i], 16)
            chain[cur] = []
            i += 1
            continue
        loc = out[i + 1] if i + 1 < len(out) else "?"
        chain[cur].append((out[i], os.path.basename(loc.split(" ")[0])))
        i += 2
    harness = {"main", "paint_stack", "stack_used", "mcu_put_u32", "mcu_put_i32", "mcu_puts", "mcu_put_kv", "mcu_put_hex32",
               "semihost", "mcu_systick_now", "mcu_systick_elapsed", "from_bits", "to_bits", "Reset_Handler",
               "memcpy", "memset"}
    agg = collections.Counter()
    total = 0
    for pc, c in cnt.items():
        ch = chain.get(pc, [])
        if not ch or ch[-1][0] in harness or any(f.endswith("_init") for f, _ in ch[-1:]):
            continue
        total += c
        ops = [f for f, _ in ch if f.startswith("mc_")]
        op = ops[-1] if ops else "(firmware code)"
        fw = [(f, loc) for f, loc in ch if "mc_num" not in loc and "frame_fg" not in loc]
        if args.by == "op":
            key = (op,)
        elif args.by == "function":
            key = (fw[-1][0] if fw else ch[-1][0],)
        else:
            key = (op, fw[0][1] if fw else "?")
        agg[key] += c
    n = max(1, args.samples)
    print("%d periods, %.1f instructions per period in %s's step and below (%s, %s)"
          % (n, total / n, args.drive, args.type, machine))
    for key, c in agg.most_common(args.top):
        print("%8.1f  %s" % (c / n, "  ".join(key)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
