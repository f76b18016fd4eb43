"""A profile target: 1500 distinct puck_rooms commands, one `World.execute`
call each, on one thread, every step of every command simulated (a world
that keeps no prefix state: `prefix_states=0`).

    perf record -F 999 -g -o /tmp/perf.data python python/examples/profile_single_step.py
    perf report -i /tmp/perf.data --no-children --sort symbol --stdio
"""

import os, random
os.environ["RAYON_NUM_THREADS"] = "1"
import e3d
s = e3d.Scene.builtin("puck_rooms")
w = s.world(prefix_states=0)
rng = random.Random(1)
total = 4 ** 7
cmds = s.parse(["".join("ESWN"[(i >> (2 * k)) & 3] for k in range(7)) for i in rng.sample(range(total), 1500)])
for c in cmds:
    w.execute(c)
