#!/usr/bin/env python3
"""Writes the crafted hostile inputs of tests/hostile (run from this folder). Each file is small and
broken in one way that once crashed, hung or exhausted memory; hostile_test.cpp expects a clean error."""
import struct

def pcd_header(fields='x y z', size='4 4 4', type_='F F F', count='1 1 1', width='3', height='1', points='3', data='ascii'):
    return (f"# .PCD v0.7\nVERSION 0.7\nFIELDS {fields}\nSIZE {size}\nTYPE {type_}\nCOUNT {count}\n"
            f"WIDTH {width}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\n" + (f"POINTS {points}\n" if points is not None else "") +
            f"DATA {data}\n").encode()

def write(name, data):
    with open(name, 'wb') as f:
        f.write(data if isinstance(data, bytes) else data.encode())

body = b"0 0 0\n1 0 0\n0 1 0\n"
write('pcd-negative-count.pcd', pcd_header(count='1 -1 1') + body)
write('pcd-overflow-count.pcd', pcd_header(count='1 99999999999999999999 1') + body)
write('pcd-huge-count.pcd', pcd_header(count='1 2147483647 1', data='binary') + b"\0" * 36)
write('pcd-negative-size.pcd', pcd_header(size='4 -4 4', data='binary') + b"\0" * 36)
write('pcd-size-count-overflow.pcd', pcd_header(size='8 8 8', count='1 1 268435456', data='binary') + b"\0" * 72)
# Found by fuzz_pcd: no POINTS line, and WIDTH x HEIGHT beyond 64-bit integers (UB when multiplied).
write('pcd-width-height-overflow.pcd', pcd_header(width='100000000', height='555555000000', points=None, data='binary') + b"\0" * 36)
write('pcd-claims-5e8-points.pcd', pcd_header(width='500000000', points='500000000', data='binary') + b"\0" * 1000)
# binary_compressed: (compressed size, uncompressed size) then LZF bytes.
write('pcd-compressed-zero-size.pcd', pcd_header(data='binary_compressed') + struct.pack('<II', 4, 0) + b"\x03abcd")
write('pcd-compressed-huge-size.pcd', pcd_header(width='100000000', points='100000000', data='binary_compressed')
      + struct.pack('<II', 16, 1200000000) + b"\x0f" + b"x" * 16)
write('pcd-compressed-count-mismatch.pcd', pcd_header(width='10', points='10', data='binary_compressed')
      + struct.pack('<II', 37, 36) + b"\x1f" + b"\0" * 32 + b"\x03" + b"\0" * 4)
write('pcd-compressed-corrupt.pcd', pcd_header(data='binary_compressed') + struct.pack('<II', 3, 36) + b"\xe0\xff\xff")
write('xyz-float-overflow.xyz', "0 0 0\n1 0 0\n0 1e39 0\n")
write('xyz-double-overflow.xyz', "0 0 0\n1 0 0\n0 1e999 0\n")
# Binary PLY announcing 5,000 vertices of 1,000 uchar properties in a 2 KB file.
props = "".join(f"property uchar p{i}\n" for i in range(1000))
write('ply-many-properties.ply', ("ply\nformat binary_little_endian 1.0\nelement vertex 5000\nproperty float x\n"
      "property float y\nproperty float z\n" + props + "end_header\n").encode() + b"\0" * 64)
grid_vertices = "".join(f"{i % 4} {i // 4} 0\n" for i in range(16))
write('range-grid-wrong-cols.ply', "ply\nformat ascii 1.0\nobj_info num_cols 8\nobj_info num_rows 4\nelement vertex 16\n"
      "property float x\nproperty float y\nproperty float z\nelement range_grid 16\nproperty list uchar int vertex_indices\n"
      "end_header\n" + grid_vertices + "".join(f"1 {i}\n" for i in range(16)))
write('range-grid-bad-index.ply', "ply\nformat ascii 1.0\nobj_info num_cols 4\nobj_info num_rows 4\nelement vertex 16\n"
      "property float x\nproperty float y\nproperty float z\nelement range_grid 16\nproperty list uchar int vertex_indices\n"
      "end_header\n" + grid_vertices + "".join(f"1 {i * 1000}\n" for i in range(16)))
write('obj-double-overflow.obj', "v 0 0 0\nv 1 0 0\nv 0 1e309 0\nf 1 2 3\n")
write('off-double-overflow.off', "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1e309 0\n3 0 1 2\n")
write('ply-double-overflow.ply', "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1e309 0\n3 0 1 2\n")
write('stl-double-overflow.stl', "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1e309 0\n"
      "endloop\nendfacet\nendsolid x\n")
# A float-typed vertex index far beyond any integer type (found by fuzz_range): the message must print it
# without converting it to an integer first.
write('ply-index-beyond-integers.ply', "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1e30\n")
