#!/usr/bin/env python3
"""Joins one-level .astc files (Arm's header, one per MIP level, largest first) into a KTX 1.1
file with the whole chain (docs/compressed-files.md#ktx): a pre-compressed texture for
scripts/bench-compressed.sh. Usage: astc-ktx.py OUT.ktx LEVEL0.astc LEVEL1.astc ..."""
import struct
import sys

GL_RGBA = 0x1908
# GL_COMPRESSED_RGBA_ASTC_WxH_KHR, 0x93B0 .. 0x93BD, in this footprint order.
FOOTPRINTS = [(4, 4), (5, 4), (5, 5), (6, 5), (6, 6), (8, 5), (8, 6), (8, 8), (10, 5), (10, 6),
              (10, 8), (10, 10), (12, 10), (12, 12)]


def read_astc(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 16 or struct.unpack("<I", data[:4])[0] != 0x5CA1AB13:
        sys.exit(f"{path}: not an .astc file")
    bw, bh, bd = data[4], data[5], data[6]
    dim = [int.from_bytes(data[7 + 3 * i:10 + 3 * i], "little") for i in range(3)]
    if bd != 1 or dim[2] != 1:
        sys.exit(f"{path}: not a 2-D image")
    blocks = -(-dim[0] // bw) * -(-dim[1] // bh)
    if len(data) != 16 + 16 * blocks:
        sys.exit(f"{path}: {len(data) - 16} bytes of blocks, expected {16 * blocks}")
    return (bw, bh), dim[0], dim[1], data[16:]


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    levels = [read_astc(p) for p in sys.argv[2:]]
    fp, w, h, _ = levels[0]
    for k, (f, lw, lh, _) in enumerate(levels):
        if f != fp or lw != max(1, w >> k) or lh != max(1, h >> k):
            sys.exit(f"{sys.argv[2 + k]}: level {k} is {lw}x{lh} {f}, "
                     f"expected {max(1, w >> k)}x{max(1, h >> k)} {fp}")
    out = bytearray(b"\xABKTX 11\xBB\r\n\x1A\n")
    out += struct.pack("<13I", 0x04030201, 0, 1, 0, 0x93B0 + FOOTPRINTS.index(fp), GL_RGBA, w, h,
                       0, 0, 1, len(levels), 0)
    for _, _, _, blocks in levels:
        out += struct.pack("<I", len(blocks)) + blocks  # 16-byte blocks: already 4-aligned
    with open(sys.argv[1], "wb") as f:
        f.write(out)


main()
