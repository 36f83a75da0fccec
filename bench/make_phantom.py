#!/usr/bin/env python3
"""A deterministic uint16 phantom of tubes and shells with noise, N^3 voxels of 1 mm, written as an
uncompressed NIfTI-1 a slab of slices at a time (never whole in memory: 2048^3 is 16 GiB), and beside it a
detached NRRD header (.nhdr) naming the same voxels, so that one file can be read in place (the .nii)
and whole into memory (the .nhdr) for a comparison of the two.

The structure is one connected piece, so that one seed grows through all of it: a spherical shell
(radius 0.35 N, 0.012 N thick) crossed by three tubes (radius 0.02 N) along x, y and z, each through
the shell twice, and a torus (0.25 N about z, tube radius 0.02 N) that touches them. Inside reads
1000, outside 300, each voxel plus Gaussian noise of sigma 60 drawn from a generator seeded by its
slice, so the phantom does not depend on the slab size. The seed: voxel (N/2 + 0.35 N, N/2, N/2) on the shell.
    /usr/bin/python3 bench/make_phantom.py N OUT.nii"""
import os
import struct
import sys

import numpy as np

INSIDE, OUTSIDE, SIGMA = 1000, 300, 60
HEADER_BYTES = 352  # NIfTI-1's 348, then the 4 bytes saying no extension follows


def seed_voxel(n):
    return (n // 2 + int(0.35 * n), n // 2, n // 2)


def nifti_header(n):
    h = bytearray(HEADER_BYTES)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, n, n, n, 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, 512, 16)  # datatype uint16, bits per voxel
    struct.pack_into("<8f", h, 76, 1, 1, 1, 1, 1, 1, 1, 1)  # pixdim: qfac 1, 1 mm
    struct.pack_into("<f", h, 108, HEADER_BYTES)  # vox_offset
    struct.pack_into("<f", h, 112, 1.0)  # scl_slope 1: the stored numbers are the values
    h[123] = 2  # xyzt_units: mm
    struct.pack_into("<hh", h, 252, 0, 1)  # qform_code 0, sform_code 1 (scanner)
    for row in range(3):  # srow_x, srow_y, srow_z: identity, origin at voxel 0
        coefficients = [1.0 if c == row else 0.0 for c in range(3)] + [0.0]
        struct.pack_into("<4f", h, 280 + 16 * row, *coefficients)
    h[344:348] = b"n+1\0"
    return bytes(h)


def inside(n, z0, z1):
    """The phantom's mask over slices z0 .. z1 - 1, shape (z, y, x)."""
    c = (n - 1) / 2
    z, y, x = np.meshgrid(np.arange(z0, z1, dtype=np.float32) - c, np.arange(n, dtype=np.float32) - c,
                          np.arange(n, dtype=np.float32) - c, indexing="ij")
    r = np.sqrt(x * x + y * y + z * z)
    shell = np.abs(r - 0.35 * n) < 0.006 * n
    tube = 0.02 * n
    tubes = (y * y + z * z < tube * tube) | (x * x + (z - 0.1 * n) ** 2 < tube * tube) | ((x - 0.1 * n) ** 2 + y * y < tube * tube)
    torus = (np.sqrt(x * x + y * y) - 0.25 * n) ** 2 + z * z < tube * tube
    return shell | tubes | torus


def main():
    if len(sys.argv) != 3 or not sys.argv[1].isdigit() or not sys.argv[2].endswith(".nii"):
        sys.exit("usage: make_phantom.py N OUT.nii")
    n, out = int(sys.argv[1]), sys.argv[2]
    slab = max(1, (1 << 24) // (n * n))  # about 16 M voxels a slab
    with open(out, "wb") as f:
        f.write(nifti_header(n))
        for z0 in range(0, n, slab):
            z1 = min(n, z0 + slab)
            values = np.where(inside(n, z0, z1), INSIDE, OUTSIDE).astype(np.float32)
            for z in range(z0, z1):
                values[z - z0] += np.random.default_rng(z).normal(0, SIGMA, (n, n)).astype(np.float32)
            f.write(np.clip(np.rint(values), 0, 65535).astype("<u2").tobytes())
    with open(out[:-4] + ".nhdr", "w") as f:
        f.write(f"NRRD0004\ntype: uint16\ndimension: 3\nsizes: {n} {n} {n}\nspace: right-anterior-superior\n"
                f"space directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\nencoding: raw\nendian: little\n"
                f"byte skip: {HEADER_BYTES}\ndata file: {os.path.basename(out)}\n")


if __name__ == "__main__":
    main()
