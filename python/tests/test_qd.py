"""e3d.qd: a scene as a quality-diversity scoring function. The first part
needs no pyribs (the scoring itself, ``e3d._qd``, against
``World.execute``); the second runs when ``ribs`` is installed (the
archive matching e3d's cells, QD-score and coverage as pyribs computes
them, pyribs' MAP-Elites on a scene)."""

import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import e3d
from e3d._qd import Scoring

ARM7_TORQUES = [1.8, 1.2, 0.75, 0.45, 0.24, 0.12, 0.06]


def test_symbol_solutions_round_to_the_nearest_index_clipped():
    s = Scoring("two_rooms")
    assert s.solution_dim == 7 and s.bounds == [(-0.5, 3.5)] * 7
    x = [[-0.7, 0.49, 0.5, 1.5, 2.51, 3.4, 9.0]]
    # numpy's rint: halves to even (0.5 -> 0, 1.5 -> 2); outside: clipped
    assert s.commands(x).tolist() == [[0, 0, 0, 2, 3, 3, 3]]
    assert s.commands(x).dtype == np.uint8
    c = s.scene.parse(["EESSWNE", "NNNNNNN"])
    assert s.solutions(c).tolist() == c.astype(float).tolist()
    assert (s.commands(s.solutions(c)) == c).all()


def test_scoring_matches_world_execute_command_by_command():
    s = Scoring("three_rooms")
    rng = np.random.default_rng(3)
    x = rng.uniform(-1.0, 4.5, size=(40, 9))
    objective, measures, out = s.evaluate(x)
    assert objective.shape == (40,) and measures.shape == (40, 2)
    world = s.scene.world()
    (x0, x1), (y0, y1) = s.ranges
    for i, c in enumerate(s.commands(x)):
        o = world.execute(c)
        assert (out.effect[i], out.reward[i], out.x[i], out.y[i]) == (o.effect, o.reward, o.x, o.y)
        assert objective[i] == o.reward
        row, col = divmod(o.effect, 9)
        # the centre of the effect's 1 m cell, row 0 at the top (y in [2, 3])
        assert measures[i].tolist() == [col + 0.5, 2.5 - row]
    # the whole batch again through __call__: the same numbers
    o2, m2 = s(x)
    assert (o2 == objective).all() and (m2 == measures).all()
    p = Scoring("three_rooms", descriptor="point")
    _, mp = p(x)
    assert mp.tolist() == np.stack([out.x, out.y], axis=1).tolist()


def test_two_rooms_reward_and_cell():
    s = Scoring("two_rooms")
    assert (s.dims, s.ranges, s.num_cells, s.offset) == ((6, 3), ((0.0, 6.0), (0.0, 3.0)), 18, 0.0)
    objective, measures = s(s.solutions(s.scene.parse(["SEEEEES", "NNNNNNN"])))
    o = s.scene.world().execute("SEEEEES")
    assert (o.effect, o.reward) == (17, 1.0)
    assert objective.tolist() == [1.0, 0.0]
    assert measures.tolist() == [[5.5, 0.5], [0.5, 2.5]]


def test_effort_sums_the_sizes_of_the_actions():
    # e3d's own effort (Scene.effort): the quality is 1 - effort / max_effort, offset 0
    s = Scoring("arm7", quality="effort")
    assert s.offset == 0.0 and s.scene.max_effort == pytest.approx(sum(ARM7_TORQUES))
    c = s.scene.parse(["+++++++", "0000000", "-0+0-0+"])
    e = [sum(ARM7_TORQUES), 0.0, 1.8 + 0.75 + 0.24 + 0.06]
    assert s.effort(c).tolist() == pytest.approx(e)
    assert s.scene.effort(["-0+0-0+"]).tolist() == pytest.approx(e[2:])
    nan = np.full(3, np.nan)
    q = s.quality_of(c, e3d.BatchOutcome(np.zeros(3, np.int64), np.zeros(3), nan, nan))
    assert q.tolist() == pytest.approx([0.0, 1.0, 1 - e[2] / sum(ARM7_TORQUES)])
    # three_rooms: 9 impulses of 2.4 N*s whatever the command
    t = Scoring("three_rooms", quality="effort")
    assert t.effort(t.scene.parse(["EEEEEEEEE", "NSWENSWEN"])).tolist() == pytest.approx([21.6] * 2)
    assert not t.scene.effort_varies and s.scene.effort_varies


def test_continuous_scene_values_clipped_and_effort():
    s = Scoring("arm7_continuous", quality="effort")
    assert s.bounds[0] == (-1.8, 1.8) and s.bounds[6] == (-0.06, 0.06)
    x = np.array([[2.0, -0.5, 0.0, 0.1, -1.0, 0.0, 0.03]])
    c = s.commands(x)
    assert c.tolist() == [[1.8, -0.5, 0.0, 0.1, -0.24, 0.0, 0.03]]
    assert s.effort(c).tolist() == pytest.approx([1.8 + 0.5 + 0.1 + 0.24 + 0.03])
    assert s.scene.max_effort == pytest.approx(sum(ARM7_TORQUES))


def test_elites_qd_score_and_coverage_by_hand():
    # a callable quality: the first slot's symbol index
    s = Scoring("two_rooms", quality=lambda c, o: c[:, 0].astype(float), offset=-1.0)
    c = np.array([[0] * 7, [2] * 7, [1] * 7, [3] * 7], dtype=np.uint8)
    el = s.elites(c, [0, 0, 5, 17])
    assert el.shape == (18,)
    assert el[[0, 5, 17]].tolist() == [2.0, 1.0, 3.0]
    assert np.isnan(np.delete(el, [0, 5, 17])).all()
    assert s.qd_score(el) == (2 + 1) + (1 + 1) + (3 + 1)
    assert s.coverage(el) == 3 / 18
    empty = s.elites(c[:0], [])
    assert (s.qd_score(empty), s.coverage(empty)) == (0.0, 0.0)
    # "reward" reads the scene's reward of each effect, not the record's
    r = Scoring("two_rooms")
    el = r.elites(c[:2], [17, 3])
    assert r.qd_score(el) == 1.0 and r.coverage(el) == 2 / 18


def test_a_session_as_an_archive():
    s = Scoring("two_rooms", quality="effort")
    rec = e3d.run_session("two_rooms", "uniform", trials=300, seed=4)
    el = s.elites(rec.commands, rec.effects)
    # every command is 7 moves: each filled cell holds quality 0, and e3d reports no qd_score
    assert s.coverage(el) == rec.metrics["distinct_effects"] / 18
    assert s.qd_score(el) == 0.0 and rec.metrics["qd_score"] is None
    # arm7: the Scoring's QD-score is e3d's own qd_score
    arm = Scoring("arm7", quality="effort")
    rec = e3d.run_session("arm7", "uniform", trials=300, seed=4)
    el = arm.elites(rec.commands, rec.effects)
    assert arm.qd_score(el) == pytest.approx(rec.metrics["qd_score"])
    assert set(np.flatnonzero(~np.isnan(el))) == set(rec.effects.tolist())


def test_pyribs_index_and_e3d_effect():
    s = Scoring("two_rooms")
    # effect 17 = row 2 (the bottom), col 5: pyribs' x bin 5, y bin 0
    assert s.index_of([17, 0, 5]).tolist() == [5 * 3 + 0, 0 * 3 + 2, 5 * 3 + 2]
    assert (s.effect_of(s.index_of(np.arange(18))) == np.arange(18)).all()


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="quality = 'speed'"):
        Scoring("two_rooms", quality="speed")
    with pytest.raises(ValueError, match="descriptor = 'pose'"):
        Scoring("two_rooms", descriptor="pose")
    with pytest.raises(ValueError, match="offset: a callable quality"):
        Scoring("two_rooms", quality=lambda c, o: o.reward)
    s = Scoring("two_rooms")
    with pytest.raises(ValueError, match=r"solutions: expected an array \[N, 7\]"):
        s.commands(np.zeros((2, 6)))
    with pytest.raises(ValueError, match="finite"):
        s.commands([[np.nan] * 7])
    with pytest.raises(ValueError, match="world: a world of 'arm7'"):
        Scoring("two_rooms", world=e3d.Scene.builtin("arm7").world())


def run_python(code):
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)


def test_import_e3d_needs_no_ribs_and_e3d_qd_says_what_to_install():
    block = "import sys; sys.modules['ribs'] = None\n"  # as if ribs were not installed
    r = run_python(block + "import e3d; print(e3d.run_session)")
    assert r.returncode == 0, r.stderr
    r = run_python(block + "import e3d.qd")
    assert r.returncode != 0
    assert "ImportError: e3d.qd needs pyribs: pip install ribs" in r.stderr


# ---- with pyribs


def test_grid_archive_holds_e3ds_cells_and_its_stats():
    pytest.importorskip("ribs")
    from e3d import qd
    s = qd.Scoring("three_rooms", quality="effort")
    archive = qd.grid_archive(s)
    assert archive.cells == 27 and archive.qd_score_offset == 0.0
    arm = qd.grid_archive("arm7", quality="effort")  # from a scene: its Scoring's archive
    assert (arm.cells, arm.solution_dim, arm.qd_score_offset) == (225, 7, 0.0)
    assert arm.dims.tolist() == [15, 15] and arm.lower_bounds.tolist() == [-1.875, -1.875]
    rng = np.random.default_rng(5)
    x = rng.uniform(-0.5, 3.5, size=(200, 9))
    objective, measures, out = s.evaluate(x)
    # pyribs bins every command into e3d's cell, by its centre or its point
    assert (s.effect_of(archive.index_of(measures)) == out.effect).all()
    points = np.stack([out.x, out.y], axis=1)
    assert (s.effect_of(archive.index_of(points)) == out.effect).all()
    archive.add(x, objective, measures)
    el = s.elites(s.commands(x), out.effect)
    assert np.array_equal(qd.elites_of(archive, s), el, equal_nan=True)
    assert archive.stats.qd_score == pytest.approx(s.qd_score(el))
    assert archive.stats.coverage == pytest.approx(s.coverage(el))
    assert 0 < s.coverage(el) < 1


def test_map_elites_on_a_scene_is_reproducible():
    pytest.importorskip("ribs")
    from e3d import qd
    s = qd.Scoring("two_rooms", quality="reward")
    a = qd.map_elites("two_rooms", 200, seed=7, scoring=s, batch_size=50)
    b = qd.map_elites("two_rooms", 200, seed=7, batch_size=50)
    ea, eb = qd.elites_of(a, s), qd.elites_of(b, s)
    assert np.array_equal(ea, eb, equal_nan=True)
    assert a.stats.coverage == s.coverage(ea) > 0.5
    # the reward (1 in cell 17, else 0) as quality, offset 0: 1 if the rewarded cell is filled
    assert a.stats.qd_score == s.qd_score(ea) == (0.0 if np.isnan(ea[17]) else 1.0)
    # every elite's solution executes to its cell
    data = a.data(["solution", "index"])
    out = s.world.execute_batch(s.commands(data["solution"]))
    assert (out.effect == s.effect_of(data["index"])).all()
    with pytest.raises(ValueError, match="trials = 120: expected a multiple of batch_size = 50"):
        qd.map_elites("two_rooms", 120, batch_size=50)


def test_quality_diversity_md_runs(root):
    pytest.importorskip("ribs")
    text = (root / "docs" / "quality-diversity.md").read_text()
    codes = re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)
    assert codes
    ns = {}
    for i, code in enumerate(codes):
        exec(compile(code, f"docs/quality-diversity.md block {i + 1}", "exec"), ns)
    scoring, archive, elites = ns["scoring"], ns["archive"], ns["elites"]
    assert 0 < archive.stats.coverage <= 68 / 225  # arm7's tip reaches 68 of the 225 cells
    assert archive.stats.qd_score == pytest.approx(scoring.qd_score(ns["qd"].elites_of(archive, scoring)))
    assert 0 < scoring.qd_score(elites) <= scoring.coverage(elites) * 225


def test_compare_script_prints_its_table(root, tmp_path):
    pytest.importorskip("ribs")
    pytest.importorskip("scipy")
    r = subprocess.run([sys.executable, str(root / "scripts" / "qd-compare.py"), "--scenes",
                        "two_rooms", "--learners", "e3d,uniform", "--seeds", "3", "--trials", "100",
                        "--table-cache", str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    rows = [line.split(" | ") for line in r.stdout.splitlines() if line.startswith("| two_rooms")]
    assert [row[1] for row in rows] == ["e3d", "uniform", "pyribs MAP-Elites"]
    s = Scoring("two_rooms")
    batch = e3d.run_sessions("two_rooms", "uniform", trials=100, seeds=range(3))
    cov = [s.coverage(s.elites(batch.commands[i], batch.effects[i])) for i in range(3)]
    # the uniform row's coverage: the mean of the three sessions' coverages
    assert rows[1][3].startswith(f"{np.mean(cov):.3f} ± ")
    assert rows[2][4:] == ["", " |"]
