#!/usr/bin/env python3
"""Writes the triangle meshes of experiments/scenes/mesh-room.json (a torus, a lathed vase and a
subdivided icosahedron) as OBJ files under experiments/scenes/meshes/. Deterministic: running it
again rewrites the committed files byte for byte."""
import math
import os

OUT = os.path.join(os.path.dirname(__file__), "..", "experiments", "scenes", "meshes")


def write(name, verts, faces):
    with open(os.path.join(OUT, name), "w", newline="\n") as f:
        f.write(f"# {name}: written by scripts/make_mesh_room.py\n")
        for v in verts:
            f.write("v %.5f %.5f %.5f\n" % v)
        for a, b, c in faces:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")


def grid(rows, cols, point, wrap_rows):
    """Triangles of a (rows x cols) parametric grid, wrapped around in cols (and rows if asked)."""
    verts = [point(i, j) for i in range(rows) for j in range(cols)]
    faces = []
    for i in range(rows if wrap_rows else rows - 1):
        for j in range(cols):
            a, b = i * cols + j, i * cols + (j + 1) % cols
            c, d = ((i + 1) % rows) * cols + j, ((i + 1) % rows) * cols + (j + 1) % cols
            faces += [(a, c, b), (b, c, d)]
    return verts, faces


def torus(cx, cy, cz, big, small, n=48, m=24):
    def p(i, j):
        u, v = 2 * math.pi * i / n, 2 * math.pi * j / m
        r = big + small * math.cos(v)
        return (cx + r * math.cos(u), cy + small * math.sin(v), cz + r * math.sin(u))
    return grid(n, m, p, True)


def vase(cx, cz, height, rows=32, cols=32):
    def p(i, j):
        t = i / (rows - 1)
        r = 0.25 + 0.18 * math.sin(math.pi * (0.2 + 1.3 * t)) + 0.05 * t
        a = 2 * math.pi * j / cols
        return (cx + r * math.cos(a), height * t, cz + r * math.sin(a))
    return grid(rows, cols, p, False)


def icosphere(cx, cy, cz, radius, levels=2):
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    for _ in range(levels):
        cache, new = {}, []
        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(x + y) / 2 for x, y in zip(verts[a], verts[b])]
                n = math.sqrt(sum(x * x for x in m))
                verts.append(tuple(x / n for x in m))
                cache[key] = len(verts) - 1
            return cache[key]
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return [(cx + radius * x, cy + radius * y, cz + radius * z) for x, y, z in verts], faces


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    write("torus.obj", *torus(-1.1, 0.35, 0.2, 0.7, 0.3))
    write("vase.obj", *vase(1.2, -0.4, 1.6))
    write("gem.obj", *icosphere(0.35, 0.45, 1.2, 0.45))
