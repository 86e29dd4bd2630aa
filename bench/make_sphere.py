#!/usr/bin/env python3
# A UV sphere of 1,000,994 triangles, as OBJ, for facet-bench --mesh (the
# million-triangle row of docs/performance.md, "Your own mesh"):
#   python3 bench/make_sphere.py sphere-1m.obj
# Counter-clockwise faces seen from outside, as OBJ has them.
import math, sys
rings, segs = 500, 1003   # 2 * segs * (rings - 1) = 1,000,994 triangles
out = open(sys.argv[1], 'w')
out.write('v 0 1 0\n')
for r in range(1, rings):
    t = math.pi * r / rings
    for s in range(segs):
        p = 2 * math.pi * s / segs
        out.write('v %.6f %.6f %.6f\n' % (math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p)))
out.write('v 0 -1 0\n')
bottom = 2 + (rings - 1) * segs  # the last vertex, 1-based
def v(r, s): return 2 + (r - 1) * segs + s % segs
for s in range(segs): out.write('f 1 %d %d\n' % (v(1, s + 1), v(1, s)))
for r in range(1, rings - 1):
    for s in range(segs):
        a, b, c, d = v(r, s), v(r, s + 1), v(r + 1, s), v(r + 1, s + 1)
        out.write('f %d %d %d\nf %d %d %d\n' % (a, b, d, a, d, c))
for s in range(segs): out.write('f %d %d %d\n' % (bottom, v(rings - 1, s), v(rings - 1, s + 1)))
