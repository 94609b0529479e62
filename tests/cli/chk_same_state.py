#!/usr/bin/env python3
"""Two rotleap checkpoints hold the same state and run record, bit for bit, apart from the labels.

usage: chk_same_state.py A.chk B.chk

A run of a molecule defined in a deck and the run of the catalogue model it copies differ only in
the model's name: the species name in the state, and in the run record the PHYS text (system.model
and the molecule's sites) and the MARK hashes of the outputs that print the name (the PDB's
residue names, the XYZ's last column).  Everything else must be equal byte for byte: the header,
time, step, box, each species' kind, mass, moments, body-frame sites and count, every state array,
and the run record's BOOK (averages, thermostat account), RNG, LIST, WTCH, RLAX and OPST sections.
Layout: io/io_checkpoint.c (payload, version 1) and app/runrec.h (run record, version 5).
Exit 0 if so, 1 with the first difference."""
import struct
import sys


def parse(path):
    b = open(path, "rb").read()
    assert b[:8] == b"RLCHKPT\0", path + ": not a checkpoint"
    (plen,) = struct.unpack_from("<Q", b, 16)
    p = b[24:24 + plen]
    at = 4 + 4 + 8 + 8 + 24  # units, removed_dof, time, step, box
    (nsp,) = struct.unpack_from("<I", p, at)
    at += 4
    pieces = [p[:at]]  # everything up to here is compared as is
    names = []
    for _ in range(nsp):
        (nl,) = struct.unpack_from("<I", p, at)
        names.append(p[at + 4:at + 4 + nl])
        at += 4 + nl
        start = at
        at += 4 + 8 + 24  # kind, mass, J
        (ns,) = struct.unpack_from("<i", p, at)
        at += 4 + 24 * ns + 4  # sites, count
        pieces.append(p[start:at])
    (n, nrot, nmat, naxis) = struct.unpack_from("<4I", p, at)
    end = at + 16 + 8 * (6 * n + 3 * nrot + 9 * nmat + 3 * naxis)
    pieces.append(p[at:end])
    (bs,) = struct.unpack_from("<Q", p, end)
    blob = p[end + 8:end + 8 + bs]
    assert end + 8 + bs == len(p), path + ": trailing bytes"
    sections = {"magic": blob[:16]}
    at = 16
    while at < len(blob):
        tag = blob[at:at + 4].decode()
        (ln,) = struct.unpack_from("<Q", blob, at + 4)
        sections[tag] = blob[at + 12:at + 12 + ln]
        at += 12 + ln
    return pieces, names, sections


def main():
    a, b = parse(sys.argv[1]), parse(sys.argv[2])
    if len(a[0]) != len(b[0]):
        print("different numbers of species")
        return 1
    what = ["header, time, step, box"] + ["species %d" % k for k in range(len(a[0]) - 2)] + ["state arrays"]
    for w, x, y in zip(what, a[0], b[0]):
        if x != y:
            print("%s differ" % w)
            return 1
    for tag in sorted(set(a[2]) | set(b[2])):
        if tag in ("PHYS", "MARK"):
            continue
        if a[2].get(tag) != b[2].get(tag):
            print("run record section %s differs" % tag)
            return 1
    print("same state and run record (species %s and %s)" % (a[1], b[1]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
