#!/usr/bin/env python3
"""Reads an STM32F405 image (build/stm32f405/firmware.elf) and checks what
a reset needs before any code runs (ARMv7-M ARM B1.5.3; RM0090 2.4, table
61): the vector table at the start of flash (0x08000000, where the F405
boots from main flash), its word 0 (the initial stack pointer) in SRAM or
CCM and 8-byte aligned, word 1 (reset) in flash with the Thumb bit set
and pointing at Reset_Handler, every vector odd and in flash, and the
handlers of the ADC (18), TIM1 break (24), CAN1 RX0 (20) and CAN1 SCE (22)
interrupts the image's own, not the default one. Prints what it found;
exit 0 when all hold, 1 otherwise. Needs arm-none-eabi-objcopy and -nm."""
import os
import struct
import subprocess
import sys
import tempfile

FLASH = (0x08000000, 0x08100000)
RAMS = [(0x20000000, 0x20020000), (0x10000000, 0x10010000)]
IRQS = {"ADC_IRQHandler": 18, "TIM1_BRK_TIM9_IRQHandler": 24, "CAN1_RX0_IRQHandler": 20, "CAN1_SCE_IRQHandler": 22}
N_VECTORS = 16 + 82


def main(elf):
    fails = []

    def check(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            fails.append(what)

    syms = {}
    for line in subprocess.run(["arm-none-eabi-nm", elf], capture_output=True, text=True, check=True).stdout.splitlines():
        parts = line.split()
        if len(parts) == 3:
            syms.setdefault(parts[2], int(parts[0], 16))
    with tempfile.TemporaryDirectory() as d:
        raw = os.path.join(d, "vec.bin")
        subprocess.run(["arm-none-eabi-objcopy", "-O", "binary", "-j", ".isr_vector", elf, raw], check=True)
        data = open(raw, "rb").read()
    hdr = subprocess.run(["arm-none-eabi-objdump", "-h", elf], capture_output=True, text=True, check=True).stdout
    vma = next((int(l.split()[3], 16) for l in hdr.splitlines() if " .isr_vector " in l), None)
    check(vma == FLASH[0], f".isr_vector at 0x{vma or 0:08x} (0x08000000, the boot address)")
    check(len(data) >= 4 * N_VECTORS, f"vector table of {len(data) // 4} words ({N_VECTORS} needed)")
    if len(data) < 8:
        return 1
    words = struct.unpack("<%dI" % (len(data) // 4), data)
    sp, reset = words[0], words[1]
    check(any(lo < sp <= hi for lo, hi in RAMS) and sp % 8 == 0, f"initial SP 0x{sp:08x} in SRAM or CCM, 8-aligned")
    check(FLASH[0] <= reset < FLASH[1] and reset & 1 == 1, f"reset vector 0x{reset:08x} in flash, Thumb")
    check("Reset_Handler" in syms and (reset & ~1) == syms["Reset_Handler"] & ~1, "reset vector is Reset_Handler")
    bad = [i for i, w in enumerate(words[1:N_VECTORS], start=1)
           if w != 0 and not (FLASH[0] <= w < FLASH[1] and w & 1)]
    reserved = {7, 8, 9, 10, 13}
    zero = [i for i, w in enumerate(words[1:N_VECTORS], start=1) if w == 0 and i not in reserved]
    check(not bad and not zero, f"every vector a Thumb address in flash (bad: {bad}, empty: {zero})")
    default = syms.get("Default_Handler")
    for name, irq in IRQS.items():
        w = words[16 + irq]
        own = name in syms and (w & ~1) == (syms[name] & ~1) and (default is None or (w & ~1) != (default & ~1))
        check(own, f"IRQ {irq} -> {name} (0x{w:08x})")
    print(f"check_stm32_elf: {'FAILED' if fails else 'all checks passed'}")
    return 1 if fails else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: check_stm32_elf.py firmware.elf", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
