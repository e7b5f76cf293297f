"""Rules of docs/architecture.md that a grep can check: the control code
(firmware/, but for the host-side design/) reads only the HAL's data types,
never calls the HAL, allocates nothing, prints nothing, knows no backend."""
from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FIRMWARE = ROOT / "firmware"


def control_sources() -> list[Path]:
    return sorted(p for p in FIRMWARE.rglob("*.[ch]") if "design" not in p.relative_to(FIRMWARE).parts)


def test_there_is_control_code() -> None:
    names = {p.name for p in control_sources()}
    assert {"paper000_drive.c", "supervisor.c", "phase_adapter.h", "fg_estimator.h"} <= names


def test_firmware_reads_hal_types_but_never_includes_hal_h() -> None:
    bad = [str(p.relative_to(ROOT)) for p in control_sources()
           if re.search(r'#\s*include\s*[<"]hal/hal\.h[>"]', p.read_text(encoding="utf-8"))]
    assert not bad, f"control code includes hal/hal.h: {bad}"


def test_no_heap_no_io_no_backend_switch() -> None:
    pattern = re.compile(r"\b(malloc|calloc|realloc|free|printf|fprintf|puts|fopen)\s*\(|#\s*if(n?def)?\s+.*\bSIM\b")
    bad = []
    for p in control_sources():
        for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1):
            code = line.split("//")[0]
            if not code.lstrip().startswith(("*", "/*")) and pattern.search(code):
                bad.append(f"{p.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not bad, "\n".join(bad)
