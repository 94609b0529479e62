"""Readers for rotleap's text outputs, shared by the bench scripts (standard library only)."""


def keyvals(path):
    """PREFIX.summary.txt or PREFIX.results.txt -> {key: value text}."""
    out = {}
    with open(path) as f:
        for line in f:
            if "=" in line and not line.startswith("#"):
                k, v = line.split("=", 1)
                out[k.strip()] = v.strip()
    return out
