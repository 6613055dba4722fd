#!/usr/bin/env python3
"""Generated scatters: many separate small parts in a box, as OBJ (session 41).

  bench/reach/scatter.py quads N OUT.obj   N quads 1 x 0.5, bent 0.3, in a 100^3 box
  bench/reach/scatter.py bands N OUT.obj   N open six-sided tubes 1 across, 1 long

Quads are discs: `prepare=auto` doubles each and maps it as a part. Their envelope
(`--prepare wrap`, or build/bench/envelope_bench --variant envelope --write ENV.obj) merges
them into one body of blobs; at N = 20,000 that body did not map (BENCHMARKS.md,
"Session 41 (lead)"). Bands are not discs: past 64 of them auto wraps the whole.
The positions come from Python's random with seed 1 (quads) or 3 (bands).
"""
import math
import random
import sys


def quads(n, out):
    random.seed(1)
    for i in range(n):
        x, y, z = [random.uniform(0, 100) for _ in range(3)]
        for dx, dy in ((0, 0), (1, 0), (1, 1), (0, 1)):
            out.write(f'v {x + dx} {y + dy * 0.5} {z + dx * 0.3}\n')
    for i in range(n):
        b = 4 * i + 1
        out.write(f'f {b} {b + 1} {b + 2}\nf {b} {b + 2} {b + 3}\n')


def bands(n, out, sides=6):
    random.seed(3)
    faces = []
    for i in range(n):
        x, y, z = [random.uniform(0, 100) for _ in range(3)]
        base = 2 * sides * i
        for ring in range(2):
            for k in range(sides):
                a = 2 * math.pi * k / sides
                out.write('v %f %f %f\n' % (x + 0.5 * math.cos(a), y + 0.5 * math.sin(a), z + ring))
        for k in range(sides):
            k2 = (k + 1) % sides
            faces.append((base + k, base + k2, base + sides + k2))
            faces.append((base + k, base + sides + k2, base + sides + k))
    for a, b, c in faces:
        out.write(f'f {a + 1} {b + 1} {c + 1}\n')


if __name__ == '__main__':
    if len(sys.argv) != 4 or sys.argv[1] not in ('quads', 'bands'):
        sys.exit(__doc__)
    with open(sys.argv[3], 'w') as out:
        (quads if sys.argv[1] == 'quads' else bands)(int(sys.argv[2]), out)
