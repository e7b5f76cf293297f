"""Helpers shared by tools/bench/pil.py and tools/bench/nofloat_check.py:
find the arm toolchain and qemu, configure/build a cross preset into a
given directory, run an image under qemu-system-arm."""
import os
import shutil
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SKIP = 77  # ctest SKIP_RETURN_CODE

PRESETS = {
    # numeric type -> (cross preset, qemu machine, host preset)
    "float": ("cortex-m4f", "mps2-an386", "host"),
    "fixed": ("cortex-m3-fixed", "mps2-an385", "host-fixed"),
}
TICK_NS = 40  # mps2 core clock 25 MHz: SysTick period


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def missing_tools(need_qemu=True):
    tools = ["arm-none-eabi-gcc", "arm-none-eabi-objdump", "arm-none-eabi-size"]
    if need_qemu:
        tools.append("qemu-system-arm")
    return [t for t in tools if shutil.which(t) is None]


def run(cmd, **kw):
    log("+", " ".join(cmd))
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    if r.returncode != 0:
        log(r.stdout[-6000:])
        raise RuntimeError("command failed (%d): %s" % (r.returncode, " ".join(cmd)))
    return r.stdout


def cross_build(preset, build_dir, defs=None, targets=None):
    cmd = ["cmake", "--preset", preset, "-S", ROOT, "-B", build_dir]
    for k, v in (defs or {}).items():
        cmd.append("-D%s=%s" % (k, v))
    run(cmd, cwd=ROOT)
    b = ["cmake", "--build", build_dir]
    if targets:
        b += ["--target"] + list(targets)
    run(b, cwd=ROOT)


def qemu(machine, elf, shift, timeout=600):
    cmd = ["qemu-system-arm", "-M", machine, "-nographic", "-monitor", "none", "-serial", "none",
           "-semihosting-config", "enable=on,target=native", "-icount", "shift=%d" % shift, "-kernel", elf]
    log("+", " ".join(cmd))
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)
    return r.returncode, r.stdout


def size_of(paths):
    """text, data, bss summed over ELF files / archives (arm-none-eabi-size)."""
    out = run(["arm-none-eabi-size", "-t"] + list(paths))
    last = out.strip().splitlines()[-1].split()
    return {"text": int(last[0]), "data": int(last[1]), "bss": int(last[2])}
