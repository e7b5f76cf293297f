"""tools/lib: what several tools share (motorsim.py: run motorsim, read its outputs)."""
