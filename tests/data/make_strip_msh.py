#!/usr/bin/env python3
"""Writes the petsc engine's Gmsh test meshes (MSH 2.2 ASCII) without Gmsh: strip_4x1.msh (2D,
the default) and, with the argument 3d, plate_2x2.msh.

The strip [0, 4] x [0, 1] in 32 x 8 cells, each split into two triangles along alternating
diagonals, the interior nodes moved by up to 0.2 h in a fixed pattern (an unstructured-looking
mesh, flat sides). Node tags are a fixed permutation of the grid order, so that read_gmsh's
numbering (increasing tags) is not the geometric one. Physical lines: "clamped" (top), "contact"
(bottom), "left", "right"; physical surface "body". A strip, so that a graph partitioner's cut
crosses the contact side: every rank's part has Γ3 nodes (docs/petsc-engine.md).

    python3 tests/data/make_strip_msh.py > tests/data/strip_4x1.msh

plate_2x2.msh: the plate [0, 2] x [0, 2] x [0, 0.5] in 8 x 8 x 2 cubes, each split into the 6
tetrahedra around its diagonal (Kuhn's split, conforming), node tags permuted likewise; physical
surfaces "contact" (z = 0) and "clamped" (z = 0.5), physical volume "body". Thin, so that the cuts
cross the contact face.

    python3 tests/data/make_strip_msh.py 3d > tests/data/plate_2x2.msh

A larger plate of the same shape for the benchmarks: the cube counts after "3d" (the method-choice
bench writes its Gmsh plates this way).

    python3 tests/data/make_strip_msh.py 3d 48 48 12 > /tmp/plate.msh
"""
import itertools
import math
import sys


def plate(nx=8, ny=8, nz=2):
    lx, ly, lz = 2.0, 2.0, 0.5
    n = (nx + 1) * (ny + 1) * (nz + 1)
    if n % 7919 == 0:
        sys.exit("make_strip_msh.py: the node count must not be a multiple of 7919 (the tag permutation)")

    def node(i, j, k):
        return (k * (ny + 1) + j) * (nx + 1) + i

    def tag3(g):
        return (7919 * g) % n + 1  # 7919 is prime and does not divide n: a permutation

    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "3",
           '2 1 "clamped"', '2 2 "contact"', '3 3 "body"', "$EndPhysicalNames", "$Nodes", str(n)]
    pts = {}
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                pts[tag3(node(i, j, k))] = (i * lx / nx, j * ly / ny, k * lz / nz)
    for t in sorted(pts):
        out.append("%d %.17g %.17g %.17g" % ((t,) + pts[t]))
    out.append("$EndNodes")
    faces, tets = [], []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                def c(b):  # the cube's corner with offsets b = (di, dj, dk)
                    return tag3(node(i + b[0], j + b[1], k + b[2]))
                for perm in itertools.permutations(range(3)):
                    b, path = [0, 0, 0], [c((0, 0, 0))]
                    for axis in perm:
                        b[axis] = 1
                        path.append(c(tuple(b)))
                    tets.append(path)
                if k == 0:
                    faces += [(2, (c((0, 0, 0)), c((1, 0, 0)), c((1, 1, 0)))), (2, (c((0, 0, 0)), c((0, 1, 0)), c((1, 1, 0))))]
                if k == nz - 1:
                    faces += [(1, (c((0, 0, 1)), c((1, 0, 1)), c((1, 1, 1)))), (1, (c((0, 0, 1)), c((0, 1, 1)), c((1, 1, 1))))]
    out += ["$Elements", str(len(faces) + len(tets))]
    e = 0
    for phys, f in faces:
        e += 1
        out.append("%d 2 2 %d %d %d %d %d" % ((e, phys, phys) + f))
    for t in tets:
        e += 1
        out.append("%d 4 2 3 3 %d %d %d %d" % ((e,) + tuple(t)))
    out.append("$EndElements")
    print("\n".join(out))


if len(sys.argv) > 1 and sys.argv[1] == "3d":
    plate(*(int(a) for a in sys.argv[2:5]))
    sys.exit(0)

NX, NY, LX, LY = 32, 8, 4.0, 1.0
N = (NX + 1) * (NY + 1)


def grid(i, j):
    return j * (NX + 1) + i


def tag(g):
    # 7919 is prime and does not divide N = 297: g -> 7919 g mod N is a permutation.
    return (7919 * g) % N + 1


hx, hy = LX / NX, LY / NY
pts = {}
for j in range(NY + 1):
    for i in range(NX + 1):
        x, y = i * hx, j * hy
        if 0 < i < NX and 0 < j < NY:
            x += 0.2 * hx * math.sin(1.7 * i + 2.3 * j)
            y += 0.2 * hy * math.cos(2.9 * i - 1.1 * j)
        pts[tag(grid(i, j))] = (x, y)

lines = []  # (physical, node tags)
for i in range(NX):
    lines.append((2, (tag(grid(i, 0)), tag(grid(i + 1, 0)))))        # contact (bottom)
    lines.append((1, (tag(grid(i + 1, NY)), tag(grid(i, NY)))))      # clamped (top)
for j in range(NY):
    lines.append((3, (tag(grid(0, j + 1)), tag(grid(0, j)))))        # left
    lines.append((4, (tag(grid(NX, j)), tag(grid(NX, j + 1)))))      # right
tris = []
for j in range(NY):
    for i in range(NX):
        a, b, c, d = grid(i, j), grid(i + 1, j), grid(i + 1, j + 1), grid(i, j + 1)
        if (i + j) % 2 == 0:
            tris += [(a, b, c), (a, c, d)]
        else:
            tris += [(a, b, d), (b, c, d)]

out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "5",
       '1 1 "clamped"', '1 2 "contact"', '1 3 "left"', '1 4 "right"', '2 5 "body"', "$EndPhysicalNames",
       "$Nodes", str(N)]
for t in sorted(pts):
    out.append("%d %.17g %.17g 0" % (t, pts[t][0], pts[t][1]))
out += ["$EndNodes", "$Elements", str(len(lines) + len(tris))]
e = 0
for phys, (p, q) in lines:
    e += 1
    out.append("%d 1 2 %d %d %d %d" % (e, phys, phys, p, q))
for tri in tris:
    e += 1
    out.append("%d 2 2 5 5 %d %d %d" % (e, tag(tri[0]), tag(tri[1]), tag(tri[2])))
out.append("$EndElements")
print("\n".join(out))
