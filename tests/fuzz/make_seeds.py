#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz harnesses (run from this folder): one small valid file per format
and variant, so the fuzzers start from inputs that reach deep into each reader."""
import os, struct

def put(folder, name, data):
    os.makedirs(f"corpus/{folder}", exist_ok=True)
    with open(f"corpus/{folder}/{name}", "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())

# OBJ: triangles, a polygon, negative indices, colours, texture/normal references, comments, CRLF.
put("obj", "tri.obj", "# a triangle\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
put("obj", "polygon.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -4 -3 -1\n")
put("obj", "colours.obj", "v 0 0 0 1 0 0\r\nv 1 0 0 0 1 0\r\nv 0 1 0 0 0 1\r\nf 1 2 3\r\n")
# OFF and COFF.
put("off", "tri.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
put("off", "coff.off", "COFF\n# comment\n4 2 0\n0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 9 9 9\n4 0 1 2 3\n3 0 2 3\n")
# PLY: ascii with extra properties, binary little and big endian, triangle strips.
head = "ply\nformat {}\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
put("ply", "ascii.ply", head.format("ascii 1.0") + "property uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
    "end_header\n0 0 0 255\n1 0 0 0\n0 1 0 7\n3 0 1 2\n")
for order, tag in (("<", "binary_little_endian 1.0"), (">", "binary_big_endian 1.0")):
    body = b"".join(struct.pack(order + "fff", *p) for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0)))
    body += struct.pack(order + "Biii", 3, 0, 1, 2)
    put("ply", tag.split()[0] + ".ply", (head.format(tag) + "element face 1\nproperty list uchar int vertex_indices\nend_header\n").encode() + body)
put("ply", "strips.ply", "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
    "element tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 1 0\n6 0 1 2 3 -1 4\n")
# STL: ascii and binary.
put("stl", "ascii.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n")
put("stl", "binary.stl", b"binary".ljust(80, b" ") + struct.pack("<I", 1) + struct.pack("<12f", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0) + b"\0\0")

# PCD: ascii (with rgb as a float, organized), binary with normals, binary_compressed (LZF literal runs).
def pcd(fields, size, type_, count, width, height, data):
    return (f"# .PCD v0.7\nVERSION 0.7\nFIELDS {fields}\nSIZE {size}\nTYPE {type_}\nCOUNT {count}\nWIDTH {width}\nHEIGHT {height}\n"
            f"VIEWPOINT 0 0 0 1 0 0 0\nPOINTS {width * height}\nDATA {data}\n").encode()
put("pcd", "ascii.pcd", pcd("x y z rgb", "4 4 4 4", "F F F F", "1 1 1 1", 2, 2, "ascii") +
    b"0 0 0 4.2108e+06\n1 0 0 4.2108e+06\nnan nan nan 0\n1 1 0 1.0e-38\n")
pts = [(0, 0, 0, 0, 0, 1), (1, 0, 0, 0, 0, 1), (0, 1, 0, 0, 0, 1)]
put("pcd", "binary.pcd", pcd("x y z normal_x normal_y normal_z", "4 4 4 4 4 4", "F F F F F F", "1 1 1 1 1 1", 3, 1, "binary") +
    b"".join(struct.pack("<6f", *p) for p in pts))
raw = b"".join(struct.pack("<3f", *(p[c] for p in pts)) for c in range(3))  # field-major, as PCL writes it
lzf = b"".join(bytes([len(raw[i:i + 32]) - 1]) + raw[i:i + 32] for i in range(0, len(raw), 32))
put("pcd", "compressed.pcd", pcd("x y z", "4 4 4", "F F F", "1 1 1", 3, 1, "binary_compressed") + struct.pack("<II", len(lzf), len(raw)) + lzf)
put("pcd", "types.pcd", pcd("x y z intensity label", "8 8 8 2 1", "F F F U I", "1 1 1 1 1", 1, 1, "binary") +
    struct.pack("<3dHb", 1.5, 2.5, 3.5, 7, -1))

# Text clouds: 3, 4, 6 (normals, colours) and 7 columns, headers, separators, the .pts count line.
put("xyz", "three.xyz", "0 0 0\n1 0 0\n0 1 0\n")
put("xyz", "normals.xyz", "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n")
put("xyz", "rgb.xyz", "//X Y Z R G B\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n")
put("xyz", "header.csv", "x,y,z,intensity\n0,0,0,5\n1,0,0,6\n0,1,0,7\n")
put("xyz", "count.pts", "3\n0 0 0 10 1 2 3\n1 0 0 10 4 5 6\n0 1 0 10 7 8 9\n")
# A range grid (organized PLY) and a .conf pose file.
put("range", "grid.ply", "ply\nformat ascii 1.0\nobj_info num_cols 2\nobj_info num_rows 2\nelement vertex 3\nproperty float x\n"
    "property float y\nproperty float z\nelement range_grid 4\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n1 0\n1 1\n0\n1 2\n")
put("conf", "bun.conf", "camera -0.0172 -0.0936 -0.734 -0.0461723 0.970603 -0.235889 0.0124573\n"
    "bmesh bun000.ply 0 0 0 0 0 0 1\nbmesh bun045.ply -0.052 -0.0004 -0.011 0.0055 -0.2946 -0.0039 0.9556\n")
