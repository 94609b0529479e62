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


def tokens(text):
    """'model=tip4p N=216 ms_per_step=1.5 ...' lines (bench/ffbench's output) -> {key: value text}."""
    kv = {}
    for line in text.splitlines():
        for tok in line.split():
            if "=" in tok:
                k, v = tok.split("=", 1)
                kv[k] = v
    return kv
