"""A scene's `noise` from Python: World runs noisy commands live and keyed as
`e3d scene exec` does, `reevaluate` gives `scene exec --repeat`'s rows, and
`reproducibility` the figure of `e3d run`."""

import os

import e3d

from conftest import read_csv

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NOISY = os.path.join(ROOT, "tests", "scenes", "puck_noisy.ron")
COMMANDS = ["SEEEEES", "SSEENNE", "EEEEEEE", "NWSENWS"]


def test_a_noisy_world_gives_scene_exec_rows_and_keeps_no_memo(cli):
    world = e3d.Scene.load(NOISY).world()
    out = world.execute_batch(COMMANDS)
    rows = read_csv(cli("scene", "exec", NOISY, *COMMANDS).stdout)
    assert out.effect.tolist() == [int(r["effect"]) for r in rows]
    assert out.x.tolist() == [float(r["x"]) for r in rows]
    # no memo: each call draws again, keyed the same, so the same bits
    assert world.memo_len == 0
    assert world.execute_batch(COMMANDS).x.tolist() == out.x.tolist()
    # the noise is there: the noise-free scene ends elsewhere
    plain = e3d.Scene.builtin("puck_rooms").world().execute_batch(COMMANDS)
    assert plain.x.tolist() != out.x.tolist()


def test_reevaluate_gives_scene_exec_repeat(cli):
    world = e3d.Scene.load(NOISY).world()
    r = world.reevaluate(COMMANDS, repeat=9, seed=4)
    rows = read_csv(cli("scene", "exec", NOISY, "--repeat", "9", "--seed", "4", *COMMANDS).stdout)
    assert r["runs"] == 9
    assert r["effect"].tolist() == [int(x["effect"]) for x in rows]
    assert [round(s, 4) for s in r["share"].tolist()] == [float(x["share"]) for x in rows]
    # a noise-free scene keeps every effect
    plain = e3d.Scene.builtin("puck_rooms").world().reevaluate(COMMANDS, repeat=9)
    assert plain["share"].tolist() == [1.0] * 4


def test_reproducibility_is_1_without_noise_and_below_with_heavy_noise(tmp_path):
    text = open(os.path.join(ROOT, "scenes", "puck_rooms.ron")).read()
    noisy = text.replace('effect: (body: "puck"', 'noise: (actions: Uniform(half_width: 0.9)),\n        effect: (body: "puck"')
    (tmp_path / "heavy.ron").write_text(noisy)
    heavy = e3d.Scene.load(str(tmp_path / "heavy.ron"))
    learner = e3d.Learner(heavy, "uniform")
    low = heavy.world().reproducibility(learner, repeat=10, commands=16, seed=3)
    assert low is not None and low < 0.3
    assert low * 16 == round(low * 16)
    plain = e3d.Scene.builtin("puck_rooms")
    assert plain.world().reproducibility(e3d.Learner(plain, "uniform"), repeat=10, commands=16) == 1.0
    # seeded: the same figure again
    assert heavy.world().reproducibility(learner, repeat=10, commands=16, seed=3) == low


def test_seed_draws_each_rollout_reproducibly_as_scene_exec_seed(cli):
    world = e3d.Scene.load(NOISY).world()
    point = lambda o: (o.x, o.y)
    a = point(world.execute("SSEENNE", seed=7))
    # the same seed, the same terminal point; another seed, another
    assert point(world.execute("SSEENNE", seed=7)) == a
    assert point(world.execute("SSEENNE", seed=8)) != a
    # seed=0 is the default
    assert point(world.execute("SSEENNE")) == point(world.execute("SSEENNE", seed=0))
    # a batch: row i drawn as `scene exec --seed S`'s row i
    out = world.execute_batch(COMMANDS, seed=7)
    rows = read_csv(cli("scene", "exec", NOISY, "--seed", "7", *COMMANDS).stdout)
    assert out.x.tolist() == [float(r["x"]) for r in rows]
    assert out.y.tolist() == [float(r["y"]) for r in rows]
    assert out.effect.tolist() == [int(r["effect"]) for r in rows]
    # execute is row 0 of `scene exec --seed S`
    row = read_csv(cli("scene", "exec", NOISY, "--seed", "7", "SSEENNE").stdout)[0]
    assert a == (float(row["x"]), float(row["y"]))
    assert world.execute_batch(COMMANDS, seed=9).x.tolist() != out.x.tolist()
    # run 0 of `reevaluate(repeat=1, seed=S)` is row i of seed S
    r = world.reevaluate(COMMANDS, repeat=1, seed=7)
    assert r["effect"].tolist() == out.effect.tolist()
