#!/usr/bin/env python3
"""The fixed-point firmware contains no floating-point code.

Builds the cortex-m3-fixed preset (firmware library + bare-metal images)
into --build-dir, disassembles the Cortex-M3 object code with
arm-none-eabi-objdump -dr and fails on
  - any call/reference to a soft-float helper: __aeabi_f*, __aeabi_d*
    (AEABI names) or libgcc's generic __*sf*/__*df* routines
    (__addsf3, __floatsidf, __fixdfsi, __extendsfdf2, ...);
  - any FPU instruction (v*.f32/.f64, vmov/vldr/vstr/vpush/vpop,
    vmrs/vmsr, or coprocessor 10/11 access).
Checked: every object of libmc_firmware.a and every .elf image built
(mc_selftest, and mc_pil if it was configured). --selftest first proves the
checker catches float code (a float multiply compiled for the M3 must be
flagged). Exit 0 clean, 1 float found, 77 (ctest skip) without the toolchain.
"""
import argparse
import glob
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import crossbuild as cb  # noqa: E402

SOFTFLOAT = re.compile(
    r"\b(__aeabi_[fd][a-z0-9_]*"
    r"|__(?:add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord|pow[i]?)[sd]f[23]"
    r"|__(?:float|floatun)(?:si|di|ti)[sd]f|__fix(?:uns)?[sd]f(?:si|di|ti)"
    r"|__extendsfdf2|__truncdfsf2)\b")
FPU_INSN = re.compile(
    r"^\s*[0-9a-f]+:\s+(?:[0-9a-f]{4}\s?){1,2}\s+"
    r"(v[a-z0-9]+(?:\.[a-z0-9.]+)?|cdp2?|ldc2?l?|stc2?l?|mcrr?2?|mrrc?2?)\b(.*)$")


def offending_lines(disasm):
    bad = []
    func = "?"
    for line in disasm.splitlines():
        m = re.match(r"^[0-9a-f]+ <([^>]+)>:", line)
        if m:
            func = m.group(1)
            continue
        if SOFTFLOAT.search(line):
            bad.append("%s: soft-float helper: %s" % (func, line.strip()))
            continue
        m = FPU_INSN.match(line)
        if m:
            mnem, rest = m.group(1), m.group(2)
            if mnem.startswith(("mcr", "mrc", "ldc", "stc", "cdp")) and not re.search(r"\b(p10|p11)\b", rest):
                continue
            bad.append("%s: FPU instruction: %s" % (func, line.strip()))
    return bad


def check_file(path):
    out = subprocess.run(["arm-none-eabi-objdump", "-dr", path], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True).stdout
    syms = subprocess.run(["arm-none-eabi-nm", "-A", path], stdout=subprocess.PIPE,
                          stderr=subprocess.DEVNULL, text=True).stdout
    bad = offending_lines(out)
    bad += ["symbol: " + s.strip() for s in syms.splitlines() if SOFTFLOAT.search(s)]
    n_insn = sum(1 for line in out.splitlines() if re.match(r"^\s*[0-9a-f]+:\s", line))
    return bad, n_insn


def selftest():
    """The checker must flag float code compiled for the Cortex-M3."""
    with tempfile.TemporaryDirectory() as d:
        src = os.path.join(d, "f.c")
        with open(src, "w") as f:
            f.write("float g(float a, float b) { return a * b + 1.0f; }\n"
                    "double h(int x) { return (double)x / 3.0; }\n")
        obj = os.path.join(d, "f.o")
        cb.run(["arm-none-eabi-gcc", "-mcpu=cortex-m3", "-mthumb", "-mfloat-abi=soft", "-O2", "-c", src, "-o", obj])
        bad, _ = check_file(obj)
        if not any("__aeabi_fmul" in b for b in bad) or not any("__aeabi_ddiv" in b for b in bad):
            print("nofloat selftest: checker missed soft-float calls:\n" + "\n".join(bad))
            return False
        obj4 = os.path.join(d, "f4.o")
        cb.run(["arm-none-eabi-gcc", "-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard", "-mfpu=fpv4-sp-d16",
                "-O2", "-c", src, "-o", obj4])
        bad, _ = check_file(obj4)
        if not any("FPU instruction" in b for b in bad):
            print("nofloat selftest: checker missed FPU instructions")
            return False
    print("nofloat selftest: checker flags __aeabi_fmul/__aeabi_ddiv and vmul.f32 as expected")
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=os.path.join(cb.ROOT, "build", "cortex-m3-fixed"))
    ap.add_argument("--no-build", action="store_true", help="check an existing build only")
    args = ap.parse_args()
    miss = cb.missing_tools(need_qemu=False)
    if miss:
        print("SKIP: the no-float check needs %s (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi)"
              % ", ".join(miss))
        return cb.SKIP
    if not selftest():
        return 1
    bdir = os.path.abspath(args.build_dir)
    if not args.no_build:
        cb.cross_build("cortex-m3-fixed", bdir)
    files = [os.path.join(bdir, "firmware", "libmc_firmware.a")]
    files += sorted(glob.glob(os.path.join(bdir, "hal", "backends", "mcu", "*.elf")))
    failed = False
    for path in files:
        if not os.path.exists(path):
            print("MISSING %s" % path)
            failed = True
            continue
        bad, n = check_file(path)
        rel = os.path.relpath(path, bdir)
        if bad:
            failed = True
            print("FLOAT CODE in %s (%d offending lines):" % (rel, len(bad)))
            for b in bad[:40]:
                print("  " + b)
        else:
            print("ok  %s: %d Cortex-M3 instructions, no soft-float helper, no FPU instruction" % (rel, n))
    print("nofloat: %s" % ("FAIL" if failed else "PASS"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
