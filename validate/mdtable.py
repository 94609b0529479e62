"""Pieces the validate/ scripts share: block statistics and writing a generated Markdown report.
Standard library only."""
import math
import os

READING = "\nReading (written after the run"


def blocks(x, nb):
    """Mean of x and the standard error of the means of nb equal blocks (the tail is dropped);
    (nan, nan) if x has fewer than nb values."""
    n = len(x) // nb
    if n < 1 or nb < 2:
        return float("nan"), float("nan")
    b = [sum(x[i * n:(i + 1) * n]) / n for i in range(nb)]
    m = sum(b) / nb
    return m, math.sqrt(sum((v - m) ** 2 for v in b) / (nb - 1) / nb)


def write_md(path, text):
    """Writes the generated text to path atomically (a temporary name, then rename), keeping the
    hand-written reading an earlier version had below its table (from a line starting 'Reading
    (written after the run' to the end)."""
    old = open(path).read() if os.path.exists(path) else ""
    i = old.find(READING)
    if i >= 0:
        text += old[i:]
    with open(path + ".part", "w") as f:
        f.write(text)
    os.replace(path + ".part", path)
