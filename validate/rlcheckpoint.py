"""Read (and lightly rewrite) rotleap checkpoints, format version 1 (docs/files.md).

Standard library only (struct, zlib, gzip), so that the CTest comparison runs without numpy or
OpenMM.  Lengths are in the system's units (nm for real systems).

    ck = read("x.chk")            # or read("x.chk.gz")
    ck["box"], ck["species"][0]["sites"], ck["r"][i], ck["A"][i]   (A: 3x3 nested lists)
    site_positions(ck)           # [[x, y, z] per site of every body]: r + A^T d, as rotleap

rotleap places the sites of body i at r_i + A_i^T d_a, with d_a the body-frame sites stored in
the species table (centre of mass at the origin, principal axes).
"""
import gzip
import struct
import zlib

MAGIC = b"RLCHKPT\0"


class _Reader:
    def __init__(self, buf, off):
        self.buf, self.off = buf, off

    def take(self, fmt):
        vals = struct.unpack_from("<" + fmt, self.buf, self.off)
        self.off += struct.calcsize("<" + fmt)
        return vals if len(vals) > 1 else vals[0]

    def doubles(self, n):
        vals = struct.unpack_from("<%dd" % n, self.buf, self.off)
        self.off += 8 * n
        return list(vals)


def load_bytes(path):
    with open(path, "rb") as f:
        raw = f.read()
    return gzip.decompress(raw) if path.endswith(".gz") else raw


def parse(buf):
    if buf[:8] != MAGIC:
        raise ValueError("not a rotleap checkpoint")
    version, _, plen = struct.unpack_from("<IIQ", buf, 8)
    if version != 1:
        raise ValueError("checkpoint format version %d; this reader knows 1" % version)
    if len(buf) != 24 + plen + 4:
        raise ValueError("checkpoint size %d, header announces %d" % (len(buf), 24 + plen + 4))
    crc = struct.unpack_from("<I", buf, 24 + plen)[0]
    if zlib.crc32(buf[:24 + plen]) & 0xFFFFFFFF != crc:
        raise ValueError("checkpoint checksum mismatch")
    rd = _Reader(buf, 24)
    ck = {"units": rd.take("I"), "removed_dof": rd.take("i"), "time": rd.take("d"),
          "step": rd.take("q"), "box": rd.doubles(3), "species": []}
    for _ in range(rd.take("I")):
        nlen = rd.take("I")
        name = buf[rd.off:rd.off + nlen].decode()
        rd.off += nlen
        sp = {"name": name, "kind": rd.take("i"), "mass": rd.take("d"), "moments": rd.doubles(3)}
        ns = rd.take("i")
        flat = rd.doubles(3 * ns)
        sp["sites"] = [flat[3 * a:3 * a + 3] for a in range(ns)]
        sp["count"] = rd.take("i")
        ck["species"].append(sp)
    n, nrot, nmat, naxis = rd.take("IIII")
    ck["n"], ck["nrot"], ck["nmat"], ck["naxis"] = n, nrot, nmat, naxis

    def vecs(count, width):
        flat = rd.doubles(width * count)
        return [flat[width * i:width * i + width] for i in range(count)]

    ck["_v_off"] = rd.off + 24 * n                      # byte offset of v (for zero_velocities)
    ck["r"] = vecs(n, 3)
    ck["v"] = vecs(n, 3)
    ck["_l_off"] = rd.off
    ck["l"] = vecs(nrot, 3)
    ck["A"] = [[m[0:3], m[3:6], m[6:9]] for m in vecs(nmat, 9)]
    ck["rho"] = vecs(naxis, 3)
    ck["blob_size"] = rd.take("Q")
    return ck


def read(path):
    return parse(load_bytes(path))


KIND_POINT, KIND_DIPOLE, KIND_LINEAR = 0, 1, 2  # rl_kind (system.h); 3, 4, 5 carry a matrix A


def site_positions(ck):
    """Lab positions of every site, bodies in order, sites in species order: r + A^T d for bodies
    with a rotation matrix (indexed among those bodies, as the checkpoint stores them), r + d_z rho
    for a linear molecule or point dipole (which carry only the axis rho = body Z, indexed among
    those), r + d for a point body."""
    out, body, imat, iaxis = [], 0, 0, 0
    for sp in ck["species"]:
        for _ in range(sp["count"]):
            r = ck["r"][body]
            if sp["kind"] == KIND_POINT:
                A = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
            elif sp["kind"] in (KIND_DIPOLE, KIND_LINEAR):
                rho = ck["rho"][iaxis]
                iaxis += 1
                A = [[0, 0, 0], [0, 0, 0], rho]  # sites of an axis body lie on body Z
            else:
                A = ck["A"][imat]
                imat += 1
            for d in sp["sites"]:
                out.append([r[i] + A[0][i] * d[0] + A[1][i] * d[1] + A[2][i] * d[2]
                            for i in range(3)])
            body += 1
    return out


def zero_velocities(buf):
    """The same checkpoint with v and l set to zero (and the CRC recomputed).  Positions and
    orientations are untouched; a single-point evaluation does not read v or l, and zeros compress
    well.  Returns bytes."""
    ck = parse(buf)
    out = bytearray(buf)
    out[ck["_v_off"]:ck["_v_off"] + 24 * ck["n"]] = bytes(24 * ck["n"])
    out[ck["_l_off"]:ck["_l_off"] + 24 * ck["nrot"]] = bytes(24 * ck["nrot"])
    plen = struct.unpack_from("<Q", out, 16)[0]
    struct.pack_into("<I", out, 24 + plen, zlib.crc32(bytes(out[:24 + plen])) & 0xFFFFFFFF)
    return bytes(out)


def splice_state(template, source):
    """A copy of checkpoint `template` (bytes; e.g. the 0-step checkpoint of an NVE run, whose
    run record an NVE restart accepts) with the positions r and orientation matrices A of
    checkpoint `source` (bytes; same species table, counts and box) and v = l = 0, CRC
    recomputed.  The result starts an NVE run from source's configuration at rest: the mid-step
    velocities v(-h/2) and angular momenta l(-h/2) are zero."""
    t, s = parse(template), parse(source)
    if t["species"] != s["species"] or t["box"] != s["box"] or t["n"] != s["n"] or \
            t["naxis"] or s["naxis"]:
        raise ValueError("splice_state: the checkpoints hold different systems")
    out = bytearray(zero_velocities(template))
    n, nmat = t["n"], t["nmat"]
    r_off = t["_v_off"] - 24 * n
    a_off = t["_l_off"] + 24 * t["nrot"]
    s_r = s["_v_off"] - 24 * n
    s_a = s["_l_off"] + 24 * s["nrot"]
    out[r_off:r_off + 24 * n] = source[s_r:s_r + 24 * n]
    out[a_off:a_off + 72 * nmat] = source[s_a:s_a + 72 * nmat]
    plen = struct.unpack_from("<Q", out, 16)[0]
    struct.pack_into("<I", out, 24 + plen, zlib.crc32(bytes(out[:24 + plen])) & 0xFFFFFFFF)
    return bytes(out)
