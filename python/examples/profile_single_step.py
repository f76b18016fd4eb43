"""A profile target: 1500 distinct puck_rooms commands, one `World.execute`
call each, on one thread (every call a simulation of the one-copy world).

    perf record -F 999 -g -o /tmp/perf.data python python/examples/profile_single_step.py
    perf report -i /tmp/perf.data --no-children --sort symbol --stdio
"""

import os, random
os.environ["RAYON_NUM_THREADS"] = "1"
import e3d
s = e3d.Scene.builtin("puck_rooms")
w = s.world()
rng = random.Random(1)
total = 4 ** 7
cmds = s.parse(["".join("ESWN"[(i >> (2 * k)) & 3] for k in range(7)) for i in rng.sample(range(total), 1500)])
for c in cmds:
    w.execute(c)
